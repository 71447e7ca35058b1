# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Analytic IK against a numerical solver (scipy least squares) given a fair start.

Two uses, each timed for both solvers on the same seeded targets in one run:
- along paths (what sweep planning does: a target every 10 ms of a smooth motion), the
  numerical solver starts from its previous solution and the analytic one sorts its
  solutions by closeness to the previous one;
- scattered targets with no previous solution, the numerical solver tries several starts
  (the middle of the joint ranges and random ones) and keeps its best; the analytic one
  returns every solution.
Prints solves per second, the worst position error, how often each misses a target by
more than 1e-6 m, and the speed ratio. Writes bench/results/kinematics.json.
"""

import json
from pathlib import Path
import time

import numpy as np
from scipy.optimize import least_squares

from tactex_description.geometry import ARM_JOINT_NAMES, OPEN_MANIPULATOR_X
from tactex_description.kinematics import inverse_kinematics, tool_pose

RESULTS = Path(__file__).parent / 'results'
PATHS, POINTS = 20, 100
SCATTERED, STARTS = 200, 4
MISS_M = 1e-6
JOINTS = [OPEN_MANIPULATOR_X.joint(n) for n in ARM_JOINT_NAMES]
LOWER = np.array([j.lower for j in JOINTS])
UPPER = np.array([j.upper for j in JOINTS])


def residual(q, position, pitch):
    reached, reached_pitch = tool_pose(q)
    return np.append(reached - position, 0.1 * np.sin(reached_pitch - pitch))


def numerical(position, pitch, start):
    fit = least_squares(residual, start, bounds=(LOWER, UPPER), args=(position, pitch),
                        xtol=1e-15, ftol=1e-15, gtol=1e-15)
    return fit.x, float(np.linalg.norm(fit.fun[:3]))


def position_error(q, position) -> float:
    return float(np.linalg.norm(tool_pose(q)[0] - position))


def paths(rng):
    """Smooth joint motions inside the limits and their tool targets, 10 ms apart."""
    for _ in range(PATHS):
        centre = rng.uniform(LOWER + 0.3, UPPER - 0.3)
        amplitude = rng.uniform(0.05, 0.3, 4)
        phase = rng.uniform(0, 2 * np.pi, 4)
        t = np.arange(POINTS) * 0.01
        joints = centre + amplitude * np.sin(2 * np.pi * 0.5 * t[:, None] + phase)
        yield joints[0], [tool_pose(q) for q in joints]


def summary(name: str, seconds: float, count: int, errors: list[float]) -> dict:
    errors = np.array(errors)
    return {'solver': name, 'solves_per_s': count / seconds, 'worst_error_m': float(errors.max()),
            'misses': int(np.sum(errors > MISS_M)), 'targets': count}


def along_paths(rng) -> list[dict]:
    cases = list(paths(rng))
    count = PATHS * POINTS
    start = time.perf_counter()
    errors = []
    for q0, targets in cases:
        previous = q0
        for position, pitch in targets:
            result = inverse_kinematics(position, pitch, seed=previous)
            previous = result.solutions[0]
            errors.append(position_error(previous, position))
    analytic = summary('analytic, sorted by the previous solution', time.perf_counter() - start,
                       count, errors)
    start = time.perf_counter()
    errors = []
    for q0, targets in cases:
        previous = q0
        for position, pitch in targets:
            previous, error = numerical(position, pitch, previous)
            errors.append(error)
    numeric = summary('scipy least_squares from the previous solution',
                      time.perf_counter() - start, count, errors)
    return [analytic, numeric]


def scattered(rng) -> list[dict]:
    targets = [tool_pose(q) for q in rng.uniform(LOWER, UPPER, size=(SCATTERED, 4))]
    starts = [(LOWER + UPPER) / 2, *rng.uniform(LOWER, UPPER, size=(STARTS - 1, 4))]
    start = time.perf_counter()
    errors = [max(position_error(q, position) for q in inverse_kinematics(
        position, pitch).solutions) for position, pitch in targets]
    analytic = summary('analytic, every solution', time.perf_counter() - start, SCATTERED,
                       errors)
    start = time.perf_counter()
    errors = [min(numerical(position, pitch, q0)[1] for q0 in starts)
              for position, pitch in targets]
    numeric = summary(f'scipy least_squares, best of {STARTS} starts',
                      time.perf_counter() - start, SCATTERED, errors)
    return [analytic, numeric]


def main() -> None:
    """Time both solvers in both uses, print one table, keep the JSON."""
    rng = np.random.default_rng(0)
    uses = {'along paths': along_paths(rng), 'scattered targets': scattered(rng)}
    print(f'{"use":<20}{"solver":<48}{"solves/s":>10}{"worst error (m)":>17}{"misses":>8}')
    for use, (analytic, numeric) in uses.items():
        for row in (analytic, numeric):
            print(f'{use:<20}{row["solver"]:<48}{row["solves_per_s"]:>10.0f}'
                  f'{row["worst_error_m"]:>17.2e}{row["misses"]:>5}/{row["targets"]}')
        print(f'{use}: analytic / numerical speed ratio '
              f'{analytic["solves_per_s"] / numeric["solves_per_s"]:.1f}x')
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / 'kinematics.json').write_text(json.dumps(uses, indent=1) + '\n',
                                             encoding='utf-8')


if __name__ == '__main__':
    main()
