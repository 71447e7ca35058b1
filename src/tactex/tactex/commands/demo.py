# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex demo`: the part of the simulated pipeline that works today, run end to end.

Today's slice is the robot description: the exploration motion of the probe phase
(approach height, descend, retract, step 1 cm) is solved with our analytic IK and
played on the MuJoCo arm through its position servos; the sensor tip it reaches
is compared with the target. There is no surface, sensor or classifier in it yet.
"""

from __future__ import annotations

import argparse
import math

import numpy as np


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('--points', type=int, default=5,
                        help='probe stations, 1 cm apart (default 5)')
    parser.add_argument('--settle-s', type=float, default=1.5,
                        help='simulated time to hold each waypoint (default 1.5 s)')


def run(args: argparse.Namespace) -> int:
    """Play the probe motion in MuJoCo and print the tracking error per waypoint."""
    import mujoco

    from tactex_description.geometry import ARM_JOINT_NAMES
    from tactex_description.kinematics import forward_kinematics, inverse_kinematics
    from tactex_description.mjcf import build_mjcf

    if args.points < 1 or not math.isfinite(args.settle_s) or args.settle_s <= 0:
        print('error: --points must be >= 1 and --settle-s > 0')
        return 1
    print('tactex demo, slice 1/5: robot description (IK -> MuJoCo servos -> FK).')
    print('Not yet in the demo: sensor stream, surface contact, sweep, classification.\n')
    model = mujoco.MjModel.from_xml_string(build_mjcf())
    data = mujoco.MjData(model)
    joints = [model.joint(name).qposadr[0] for name in ARM_JOINT_NAMES]
    seed = np.array([0.0, -0.3, 0.3, 1.5])
    waypoints = []
    for station in range(args.points):
        x = 0.10 + 0.01 * station
        waypoints += [(x, 0.0, 0.08), (x, 0.0, 0.03), (x, 0.0, 0.08)]
    print(f'{"target x,y,z (m)":<26}{"reached x,y,z (m)":<28}{"error (mm)":>10}')
    worst = 0.0
    steps = int(round(args.settle_s / model.opt.timestep))
    for target in waypoints:
        result = inverse_kinematics(target, math.pi / 2, seed=seed)
        if not result.reachable:
            print(f'error: waypoint {target} unreachable: {result.detail}')
            return 1
        seed = result.solutions[0]
        data.ctrl[:4] = seed
        for _ in range(steps):
            mujoco.mj_step(model, data)
        reached = forward_kinematics(data.qpos[joints], 'sensor_edge')[:3, 3]
        error_mm = 1e3 * float(np.linalg.norm(reached - target))
        worst = max(worst, error_mm)
        print(f'{_xyz(target):<26}{_xyz(reached):<28}{error_mm:>10.2f}')
    print(f'\n{len(waypoints)} waypoints, worst steady-state error {worst:.2f} mm '
          '(position servos under gravity).')
    return 0


def _xyz(values) -> str:
    return ' '.join(f'{v:+.4f}' for v in values)
