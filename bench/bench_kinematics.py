# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Analytic IK against a numerical solver (scipy least squares) on the same targets.

Prints solves per second of each, the ratio, and the worst position error of each:
the analytic solver must be both faster and exact where the numerical one only
converges.
"""

import time

import numpy as np
from scipy.optimize import least_squares

from tactex_description.geometry import ARM_JOINT_NAMES, OPEN_MANIPULATOR_X
from tactex_description.kinematics import inverse_kinematics, tool_pose

TARGETS = 300


def main() -> None:
    """Time both solvers on seeded reachable targets and print one table."""
    rng = np.random.default_rng(0)
    joints = [OPEN_MANIPULATOR_X.joint(n) for n in ARM_JOINT_NAMES]
    lower = np.array([j.lower for j in joints])
    upper = np.array([j.upper for j in joints])
    samples = rng.uniform(lower, upper, size=(TARGETS, 4))
    targets = [tool_pose(q) for q in samples]

    start = time.perf_counter()
    analytic_error = 0.0
    for position, pitch in targets:
        for q in inverse_kinematics(position, pitch).solutions:
            analytic_error = max(analytic_error, float(np.linalg.norm(tool_pose(q)[0] - position)))
    analytic_s = time.perf_counter() - start

    def residual(q, position, pitch):
        reached, reached_pitch = tool_pose(q)
        return np.append(reached - position, 0.1 * np.sin(reached_pitch - pitch))

    start = time.perf_counter()
    numeric_error = 0.0
    for position, pitch in targets:
        fit = least_squares(residual, (lower + upper) / 2, bounds=(lower, upper),
                            args=(position, pitch), xtol=1e-15, ftol=1e-15, gtol=1e-15)
        numeric_error = max(numeric_error, float(np.linalg.norm(fit.fun[:3])))
    numeric_s = time.perf_counter() - start

    print(f'{"solver":<28}{"solves/s":>12}{"worst error (m)":>18}')
    print(f'{"analytic (all solutions)":<28}{TARGETS / analytic_s:>12.0f}{analytic_error:>18.2e}')
    print(f'{"scipy least_squares (one)":<28}{TARGETS / numeric_s:>12.0f}{numeric_error:>18.2e}')
    print(f'analytic / numerical speed ratio: {numeric_s / analytic_s:.1f}x')


if __name__ == '__main__':
    main()
