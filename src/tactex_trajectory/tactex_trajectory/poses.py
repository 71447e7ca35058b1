# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Sweep poses: the sensor edge on the path, tilted by the edge offset, pressed in, solved.

At each path sample the asked pose of `sensor_edge` is: its rounded rim touching the
surface point, pressed `press_depth_m` further along the inward normal; the sensor axis
(+z of sensor_edge, pointing into the surface) tilted from the inward normal by
`edge_offset_rad` in the plane of the normal and the direction of travel, so that only
the rim touches and the sticky face never drags. The rim point sits on the arm's side
of the sensor (sensor_edge's +x points back towards joint1), so the axis always tilts
away from the arm: sweeping away from the arm the edge trails, sweeping towards it the
edge leads.

The 4-DOF arm sets the tool's yaw by the position (no roll): a pose it cannot take
exactly is projected to the nearest one it can (position kept, the pitch that brings
the sensor frame closest to the asked one), and the angle between the two is the
sample's residual. The IK branch (joint1 facing the path or turned away, elbow up or
down) is chosen once, at the first sample nearest to the seed, and kept: a sample the
branch cannot reach refuses the sweep instead of switching.
"""

from __future__ import annotations

from dataclasses import dataclass
import math

import numpy as np

from tactex_common import frames
from tactex_common.numbers import is_finite_number
from tactex_description.geometry import OPEN_MANIPULATOR_X, PRESS_TRAVEL_M
from tactex_description.kinematics import PlanarArm
from tactex_description.mjcf import EDGE_TIP_RADIUS_M
from tactex_trajectory.errors import SweepRefused
from tactex_trajectory.path import SweepPath

TOOL_FRAME = frames.EDGE
# Pitch steps tried around the best pitch when it breaks a joint limit (rad).
PITCH_SEARCH_STEP_RAD = 0.005
# Neighbouring solutions further apart than this (rad, any joint) are checked for a
# singularity between them: the poses between are solved, halving the gap up to
# CONTINUITY_DEPTH times; a jump that does not shrink refuses the sweep.
MAX_JOINT_STEP_RAD = 0.1
CONTINUITY_DEPTH = 6
# Planned poses keep this far inside the joint limits, so the trajectory between them
# (and the arm's tracking) stays inside too (rad).
LIMIT_MARGIN_RAD = 0.02
ARM = PlanarArm.from_geometry(OPEN_MANIPULATOR_X, TOOL_FRAME)


@dataclass(frozen=True)
class PoseSettings:
    """How the sensor meets the surface.

    Attributes:
        edge_offset_rad: tilt of the sensor axis from the inward normal, 0 .. pi/2.
        press_depth_m: indentation of the rim into the surface along the normal,
            0 .. the compliant body's travel.
        max_residual_rad: the largest angle allowed between an asked pose and the
            nearest one the arm can take.
    """

    edge_offset_rad: float = 0.5
    press_depth_m: float = 0.0015
    max_residual_rad: float = 0.2

    def __post_init__(self) -> None:
        """Reject values outside their ranges."""
        checks = (('edge_offset_rad', 0.0, math.pi / 2),
                  ('press_depth_m', 0.0, PRESS_TRAVEL_M),
                  ('max_residual_rad', 1e-6, math.pi))
        for name, low, high in checks:
            value = getattr(self, name)
            if not (is_finite_number(value) and low <= value < high):
                raise ValueError(f'{name} must be in [{low:g}, {high:g}), got {value!r}')


@dataclass(frozen=True)
class Branch:
    """An IK branch: joint1 facing the target or turned away; elbow up or down."""

    facing: bool
    elbow_up: bool

    def __str__(self) -> str:
        """E.g. 'joint1 facing the path, elbow up'."""
        return (f'joint1 {"facing the path" if self.facing else "turned away"}, '
                f'elbow {"up" if self.elbow_up else "down"}')


@dataclass(frozen=True)
class SweepPoses:
    """Solved poses along a path (or along any line of edge positions).

    Attributes:
        joints: (m, 4) joint1..joint4 (rad).
        edge_positions: (m, 3) where sensor_edge is placed (m, base_link).
        rotations: (m, 3, 3) the asked orientations of sensor_edge.
        pitch_rad: (m,) tool pitch of each solution (see tactex_description.kinematics).
        residual_rad: (m,) angle between the asked and the reached orientation.
        branch: the IK branch of every sample.
    """

    joints: np.ndarray
    edge_positions: np.ndarray
    rotations: np.ndarray
    pitch_rad: np.ndarray
    residual_rad: np.ndarray
    branch: Branch


def tilt_sign(path: SweepPath) -> float:
    """+1 when the path runs away from joint1's axis overall, -1 when towards it."""
    radial = path.points[:, :2] - np.array([ARM.base_x, 0.0])
    lengths = np.linalg.norm(radial, axis=1, keepdims=True)
    radial = radial / np.where(lengths > 1e-9, lengths, 1.0)
    return 1.0 if float(np.sum(path.tangents[:, :2] * radial)) >= 0.0 else -1.0


def asked_rotations(normals: np.ndarray, tangents: np.ndarray, edge_offset_rad: float,
                    sign: float) -> np.ndarray:
    """(m, 3, 3) orientations of sensor_edge: columns x (towards the rim point), y, z (axis).

    The axis is the inward normal tilted by the offset towards `sign` x the tangent.
    """
    lean = sign * tangents
    cosine, sine = math.cos(edge_offset_rad), math.sin(edge_offset_rad)
    axis = -cosine * normals + sine * lean
    rim = -cosine * lean - sine * normals
    return np.stack([rim, np.cross(axis, rim), axis], axis=2)


def edge_positions(points: np.ndarray, normals: np.ndarray, press_depth_m: float,
                   lift_m: float | np.ndarray = 0.0) -> np.ndarray:
    """Where sensor_edge goes so that its rim is pressed `press_depth_m` into the surface.

    With `lift_m` > 0 the pressed position is lifted that far along the normal.
    """
    lift = np.reshape(lift_m, (-1, 1)) if np.ndim(lift_m) else lift_m
    return points + (EDGE_TIP_RADIUS_M - press_depth_m + lift) * normals


def sweep_poses(path: SweepPath, settings: PoseSettings, seed) -> SweepPoses:
    """Solve the pose of every path sample on one IK branch.

    Args:
        path: the sampled surface curve.
        settings: edge offset, press depth, residual tolerance.
        seed: joint1..joint4 (rad) the first sample's branch and solution are chosen
            closest to (the arm's present joints).

    Raises:
        SweepRefused: a sample is out of reach, needs another branch, or its residual
            exceeds the tolerance; the message names it.
    """
    rotations = asked_rotations(path.normals, path.tangents, settings.edge_offset_rad,
                                tilt_sign(path))
    positions = edge_positions(path.points, path.normals, settings.press_depth_m)
    labels = [f'path sample {k} ({s * 1e3:.1f} mm along the path)'
              for k, s in enumerate(path.arclength_m)]
    return solve_poses(positions, rotations, seed, settings.max_residual_rad, labels=labels)


def solve_poses(positions: np.ndarray, rotations: np.ndarray, seed, max_residual_rad: float,
                *, branch: Branch | None = None, labels: list[str] | None = None
                ) -> SweepPoses:
    """Solve edge poses in order, each seeded by the one before, on one IK branch.

    Args:
        positions: (m, 3) sensor_edge positions.
        rotations: (m, 3, 3) asked orientations.
        seed: joints the first solution is chosen closest to.
        max_residual_rad: refuse a pose farther than this from the asked orientation.
        branch: the branch to stay on; None: the first solution's.
        labels: how to name each pose in an error ('pose k' by default).

    Raises:
        SweepRefused: see `sweep_poses`.
    """
    labels = labels or [f'pose {k}' for k in range(len(positions))]
    previous = np.asarray(seed, dtype=float)
    joints, pitches, residuals = [], [], []
    for position, rotation, label in zip(positions, rotations, labels, strict=True):
        solution, pitch, residual, branch = _solve_one(position, rotation, previous, branch,
                                                       max_residual_rad, label)
        if joints and not _continuous(joints[-1], positions[len(joints) - 1],
                                      rotations[len(joints) - 1], solution, position, rotation,
                                      branch, max_residual_rad, CONTINUITY_DEPTH):
            jump = float(np.max(np.abs(solution - joints[-1])))
            raise SweepRefused(f'{label}: the joints would jump {jump:.2f} rad from the pose '
                               f'before (a singularity between them); keep the path away '
                               f'from full stretch and from above joint1')
        joints.append(solution)
        pitches.append(pitch)
        residuals.append(residual)
        previous = solution
    return SweepPoses(np.array(joints).reshape(-1, 4), np.asarray(positions, dtype=float),
                      np.asarray(rotations, dtype=float), np.array(pitches),
                      np.array(residuals), branch)


def _continuous(start_joints: np.ndarray, start_position: np.ndarray,
                start_rotation: np.ndarray, end_joints: np.ndarray, end_position: np.ndarray,
                end_rotation: np.ndarray, branch: Branch, max_residual_rad: float,
                depth: int) -> bool:
    """True when the arm moves between two solutions without a jump (bisecting the gap)."""
    if np.max(np.abs(end_joints - start_joints)) <= MAX_JOINT_STEP_RAD:
        return True
    if depth == 0:
        return False
    position = 0.5 * (start_position + end_position)
    left, _, right = np.linalg.svd(start_rotation + end_rotation)
    rotation = left @ right  # the rotation halfway (polar factor of the mean)
    try:
        middle = _solve_one(position, rotation, start_joints, branch, max_residual_rad, '')[0]
    except SweepRefused:
        return False
    return (_continuous(start_joints, start_position, start_rotation, middle, position, rotation,
                        branch, max_residual_rad, depth - 1)
            and _continuous(middle, position, rotation, end_joints, end_position, end_rotation,
                            branch, max_residual_rad, depth - 1))


def branch_of(joints, position) -> Branch:
    """The IK branch of a solution reaching `position` (facing: joint1 points at it)."""
    q1, _, q3, _ = (float(q) for q in joints)
    heading = math.atan2(float(position[1]), float(position[0]) - ARM.base_x)
    bend = -(q3 + math.atan2(ARM.upper[1], ARM.upper[0]))
    return Branch(facing=math.cos(q1 - heading) >= 0.0, elbow_up=bend <= 0.0)


def reached_rotation(joints) -> np.ndarray:
    """Orientation of sensor_edge at arm joints (compliant joints at rest)."""
    q1 = float(joints[0])
    return _frame(q1, float(joints[1] + joints[2] + joints[3]))


def _frame(q1: float, pitch: float) -> np.ndarray:
    """Rz(q1) Ry(pitch + pi/2): sensor_edge's orientation for joint1 and the tool pitch."""
    c1, s1 = math.cos(q1), math.sin(q1)
    cp, sp = math.cos(pitch + math.pi / 2), math.sin(pitch + math.pi / 2)
    return np.array([[c1 * cp, -s1, c1 * sp], [s1 * cp, c1, s1 * sp], [-sp, 0.0, cp]])


def _best_pitch(rotation: np.ndarray, q1: float) -> float:
    """The pitch whose frame is closest to `rotation` for this joint1 (max trace)."""
    c1, s1 = math.cos(q1), math.sin(q1)
    yawed = rotation.T @ np.array([[c1, -s1, 0.0], [s1, c1, 0.0], [0.0, 0.0, 1.0]])
    angle = math.atan2(yawed[2, 0] - yawed[0, 2], yawed[0, 0] + yawed[2, 2])
    return angle - math.pi / 2


def _angle_between(first: np.ndarray, second: np.ndarray) -> float:
    cosine = (float(np.trace(first.T @ second)) - 1.0) / 2.0
    return math.acos(min(1.0, max(-1.0, cosine)))


def _solve_one(position: np.ndarray, rotation: np.ndarray, seed: np.ndarray,
               branch: Branch | None, max_residual_rad: float, label: str
               ) -> tuple[np.ndarray, float, float, Branch]:
    """The solution on `branch` (or nearest to `seed`) with the smallest residual."""
    heading = math.atan2(float(position[1]), float(position[0]) - ARM.base_x)
    facings = (True, False) if branch is None else (branch.facing,)
    best = None
    reasons = []
    for facing in facings:
        q1 = heading if facing else heading + math.pi
        pitch0 = _best_pitch(rotation, q1)
        steps = int(max_residual_rad / PITCH_SEARCH_STEP_RAD) + 1
        for offset in sorted((k * PITCH_SEARCH_STEP_RAD for k in range(-steps, steps + 1)),
                             key=abs):
            result = ARM.inverse(position, pitch0 + offset, seed=seed)
            if not result.reachable:
                if offset == 0.0:
                    reasons.append(result.detail)
                continue
            on_branch = [q for q in result.solutions
                         if (branch is None or branch_of(q, position) == branch)
                         and branch_of(q, position).facing == facing]
            found = [q for q in on_branch if np.all(q >= ARM.lower + LIMIT_MARGIN_RAD)
                     and np.all(q <= ARM.upper_limit - LIMIT_MARGIN_RAD)]
            if not found:
                if offset == 0.0:
                    reasons.append(_near_limit(on_branch[0]) if on_branch else
                                   'only reachable as ' + ', '.join(sorted(
                                       {str(branch_of(q, position))
                                        for q in result.solutions})))
                continue
            solution = found[0]
            residual = _angle_between(rotation, reached_rotation(solution))
            distance = float(np.sum((solution - seed) ** 2))
            if best is None or (branch is None and distance < best[3]):
                best = (solution, pitch0 + offset, residual, distance)
            break
    if best is None:
        if branch is not None:
            detail = '; '.join(reasons) or 'no solution on this branch'
            raise SweepRefused(f"{label} at {_mm(position)} is out of the arm's reach on the "
                               f"sweep's IK branch ({branch}): {detail}; a branch switch is "
                               f'never made within one sweep')
        raise SweepRefused(f"{label} at {_mm(position)} is out of the arm's reach: "
                           f'{"; ".join(reasons)}')
    solution, pitch, residual, _ = best
    if residual > max_residual_rad:
        raise SweepRefused(
            f'{label} at {_mm(position)}: the nearest pose the 4-DOF arm can take is '
            f'{math.degrees(residual):.1f} deg from the asked one (tolerance '
            f'{math.degrees(max_residual_rad):.1f} deg); the arm has no roll, so the path '
            f"must run roughly along the arm's radial plane there")
    return solution, pitch, residual, branch_of(solution, position) if branch is None \
        else branch


def _near_limit(joints: np.ndarray) -> str:
    """Which joint comes closer to its limit than the planning margin."""
    room = np.minimum(joints - ARM.lower, ARM.upper_limit - joints)
    index = int(np.argmin(room))
    return (f'joint{index + 1}={joints[index]:.4f} rad is within {LIMIT_MARGIN_RAD} rad of its '
            f'limit [{ARM.lower[index]:.4f}, {ARM.upper_limit[index]:.4f}]')


def _mm(position: np.ndarray) -> str:
    return '(' + ', '.join(f'{float(v) * 1e3:.1f}' for v in position) + ') mm'  # inf, no warning
