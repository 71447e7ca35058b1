# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""How far the sensor edge had travelled along its path at each sample of a recording.

The edge's positions come from the simulator's ground truth where the recording has it,
else from the forward kinematics of the arm's joint states. Travel is counted in steps
of at least `STEP_M`: a Dynamixel XM430 resolves 0.088 degrees, which moves the edge
about 0.4 mm at the arm's reach, so encoder jitter of a standing arm would otherwise add
up to travel that never happened.
"""

from __future__ import annotations

import math

import numpy as np

from tactex_classify.data.bags import Recording
from tactex_description.kinematics import forward_kinematics

STEP_M = 5e-4


def edge_positions(recording: Recording) -> tuple[np.ndarray, np.ndarray, str] | None:
    """(stamps ns, (n, 3) edge positions in metres, their source), or None without two."""
    truth = recording.truth
    if truth is not None and truth.edge_ns.size:
        stamps, points = truth.edge_ns, np.asarray(truth.edge_m, dtype=float)
        source = "the simulator's edge positions"
    else:
        usable = np.all(np.isfinite(recording.joint_positions), axis=1)
        stamps = recording.joint_stamps_ns[usable]
        points = np.array([forward_kinematics(q)[:3, 3]
                           for q in recording.joint_positions[usable]]).reshape(-1, 3)
        source = 'forward kinematics of the joint states'
    finite = np.all(np.isfinite(points), axis=1)
    stamps, points = stamps[finite], points[finite]
    if stamps.size < 2:
        return None
    order = np.argsort(stamps, kind='stable')
    return stamps[order], points[order], source


def travelled(points: np.ndarray, step_m: float = STEP_M) -> np.ndarray:
    """Distance travelled at each point (m), counted once a move reaches `step_m`.

    A point within `step_m` of the last counted one adds nothing; one beyond it adds its
    distance from that point and becomes the new one.
    """
    distance = np.zeros(len(points))
    if not len(points):
        return distance
    anchor, total = points[0], 0.0
    for index in range(1, len(points)):
        with np.errstate(over='ignore', invalid='ignore'):
            move = float(np.linalg.norm(points[index] - anchor))
        if math.isfinite(move) and move >= step_m:  # a jump past float range is no travel
            total, anchor = total + move, points[index]
        distance[index] = total
    return distance


def edge_travel_m(recording: Recording) -> tuple[np.ndarray, str] | None:
    """The edge's travel at each IMU sample (m, from its first pose) and where it came from.

    None when the recording has neither ground truth nor arm joint positions (two or
    more). Samples before the first pose read 0, after the last the final travel.
    """
    found = edge_positions(recording)
    if found is None:
        return None
    stamps, points, source = found
    return np.interp(recording.stamps_ns, stamps, travelled(points)), source
