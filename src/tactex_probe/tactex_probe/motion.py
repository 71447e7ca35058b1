# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Tool poses of the probing sensor and straight-line joint paths between them.

The probing tool is the sensor's face as it bears on a surface. The face is the disc
`RIM_RADIUS_M` wide, `FACE_DISTANCE_M` past `sensor_link` along its z axis, but the tip
at `sensor_edge` (the rim point that slides in a sweep) stands `EDGE_TIP_RADIUS_M` proud
of it, so on a flat surface the body rests on that tip and the opposite rim. Its bearing
plane is therefore tilted by `FACE_TILT_RAD` = asin(tip / rim diameter) about the
sensor's y axis: `FACE_AXIS` (unit, into the surface) and `FACE_CENTRE` (midway between
the two bearing points) are given in `sensor_link` coordinates.

The 4-DOF arm can only tilt the tool within its own vertical plane (through the joint1
axis and the tool), so a tool pose is the face centre plus one tilt: the angle of the
face axis from straight down, positive when it leans away from the base. A path is
solved with the analytic IK at evenly spaced instants along a straight line, each
solution seeded with the previous one, so the arm never switches IK branch.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
import math

import numpy as np

from tactex_common import frames
from tactex_description.geometry import ARM_VELOCITY_LIMIT, OPEN_MANIPULATOR_X
from tactex_description.kinematics import (
    forward_kinematics,
    inverse_kinematics,
    PlanarArm,
)
from tactex_description.mjcf import EDGE_TIP_RADIUS_M

TOOL_FRAME = frames.SENSOR
RIM_RADIUS_M, _, FACE_DISTANCE_M = OPEN_MANIPULATOR_X.joint('sensor_edge_fixed').origin_xyz
FACE_TILT_RAD = math.asin(EDGE_TIP_RADIUS_M / (2.0 * RIM_RADIUS_M))
FACE_AXIS = np.array([-math.sin(FACE_TILT_RAD), 0.0, math.cos(FACE_TILT_RAD)])
_TIP_BEARING = np.array([RIM_RADIUS_M, 0.0, FACE_DISTANCE_M]) + EDGE_TIP_RADIUS_M * FACE_AXIS
FACE_CENTRE = 0.5 * (_TIP_BEARING + np.array([-RIM_RADIUS_M, 0.0, FACE_DISTANCE_M]))
# Centre of the tip sphere (sensor_edge), in sensor_link coordinates.
TIP_CENTRE = np.array([RIM_RADIUS_M, 0.0, FACE_DISTANCE_M])
BASE_X_M = PlanarArm.from_geometry(OPEN_MANIPULATOR_X, TOOL_FRAME).base_x
# Largest joint change between two path points before a path counts as a branch switch.
MAX_JOINT_STEP_RAD = 0.2
# Paths are slowed down where a joint would turn faster than this share of its limit
# (the driver's interpolation between points may overshoot the straight line's speed).
JOINT_SPEED_SHARE = 0.4


class PathUnreachable(Exception):
    """A tool pose or path the arm cannot reach; the message says where and why."""


@dataclass(frozen=True)
class ToolPose:
    """Face centre (m, base_link) and tilt of the tool axis from straight down (rad)."""

    point: np.ndarray
    tilt: float

    def __post_init__(self) -> None:
        """Store the point as a float array."""
        object.__setattr__(self, 'point', np.asarray(self.point, dtype=float).copy())

    @property
    def heading(self) -> float:
        """Direction of the arm plane about z (rad): where joint1 faces the tool."""
        return math.atan2(float(self.point[1]), float(self.point[0]) - BASE_X_M)

    @property
    def axis(self) -> np.ndarray:
        """Unit face axis (base_link), pointing out of the face into the surface."""
        return tool_axis(self.heading, self.tilt)

    def moved(self, offset) -> ToolPose:
        """The same tilt, the face centre moved by `offset` (m)."""
        return ToolPose(self.point + np.asarray(offset, dtype=float), self.tilt)


def tool_axis(heading: float, tilt: float) -> np.ndarray:
    """Unit face axis of an arm plane at `heading` tilted by `tilt` from straight down."""
    return np.array([math.sin(tilt) * math.cos(heading), math.sin(tilt) * math.sin(heading),
                     -math.cos(tilt)])


def tilt_towards(normal, heading: float) -> float:
    """Tilt whose face axis is closest to -`normal` (the face parallel to the surface)."""
    n = np.asarray(normal, dtype=float)
    radial = n[0] * math.cos(heading) + n[1] * math.sin(heading)
    return math.atan2(-radial, float(n[2]))


def sensor_rotation(heading: float, tilt: float) -> np.ndarray:
    """Rotation base_link <- sensor_link of the undeformed body at a tool pose."""
    pitch = math.pi / 2 - (tilt - FACE_TILT_RAD)
    z = np.array([math.cos(pitch) * math.cos(heading), math.cos(pitch) * math.sin(heading),
                  -math.sin(pitch)])
    y = np.array([-math.sin(heading), math.cos(heading), 0.0])
    return np.column_stack([np.cross(y, z), y, z])


def face_tilt(rotation: np.ndarray, heading: float) -> float:
    """Tilt of the face axis of a sensor held at `rotation` (base_link <- sensor_link)."""
    axis = rotation @ FACE_AXIS
    radial = axis[0] * math.cos(heading) + axis[1] * math.sin(heading)
    return math.atan2(radial, -axis[2])


def tip_position(pose: ToolPose) -> np.ndarray:
    """Centre of the tip sphere (m, base_link) of the undeformed body at `pose`."""
    return pose.point + sensor_rotation(pose.heading, pose.tilt) @ (TIP_CENTRE - FACE_CENTRE)


def pose_with_tip_at(tip: np.ndarray, tilt: float) -> ToolPose:
    """The tool pose whose tip centre is at `tip` (the tip lies in the arm plane too)."""
    heading = ToolPose(tip, 0.0).heading
    return ToolPose(np.asarray(tip, dtype=float)
                    + sensor_rotation(heading, tilt) @ (FACE_CENTRE - TIP_CENTRE), tilt)


def solve(pose: ToolPose, seed: Sequence[float]) -> np.ndarray:
    """Arm joints (joint1..joint4, rad) placing the face centre at `pose`.

    Raises:
        PathUnreachable: no IK solution within the joint limits (with the IK's reason).
    """
    pitch = math.pi / 2 - (pose.tilt - FACE_TILT_RAD)
    link_point = pose.point - sensor_rotation(pose.heading, pose.tilt) @ FACE_CENTRE
    result = inverse_kinematics(link_point, pitch, tool_frame=TOOL_FRAME, seed=seed)
    if not result.reachable:
        x, y, z = (float(v) for v in pose.point)
        raise PathUnreachable(f'face centre ({x:.4f}, {y:.4f}, {z:.4f}) m with tilt '
                              f'{math.degrees(pose.tilt):.1f} deg: {result.detail}')
    return result.solutions[0]


def pose_of(joints: Sequence[float]) -> ToolPose:
    """The tool pose of arm joints (joint1..joint4, rad): the inverse of `solve`."""
    sensor = forward_kinematics(joints, TOOL_FRAME)
    point = sensor[:3, :3] @ FACE_CENTRE + sensor[:3, 3]
    heading = math.atan2(float(point[1]), float(point[0]) - BASE_X_M)
    return ToolPose(point, face_tilt(sensor[:3, :3], heading))


@dataclass(frozen=True)
class JointPath:
    """Arm joints (n, 4) at times (n,) s after the path starts (the start itself excluded).

    The commanded tool moves along straight segments between `knots`, reached at
    `knot_times_s` (the first knot, the start, at 0).
    """

    times_s: np.ndarray
    joints: np.ndarray
    knots: tuple[ToolPose, ...]
    knot_times_s: tuple[float, ...]

    @property
    def duration_s(self) -> float:
        """Time to the last point (s)."""
        return float(self.times_s[-1])

    @property
    def end(self) -> ToolPose:
        """Where the path ends."""
        return self.knots[-1]

    def pose_at(self, elapsed_s: float) -> ToolPose:
        """The commanded tool pose `elapsed_s` after the start (held at both ends)."""
        times = self.knot_times_s
        segment = int(np.clip(np.searchsorted(times, elapsed_s) - 1, 0, len(times) - 2))
        span = times[segment + 1] - times[segment]
        fraction = min(max((elapsed_s - times[segment]) / span, 0.0), 1.0)
        start, end = self.knots[segment], self.knots[segment + 1]
        return ToolPose(start.point + fraction * (end.point - start.point),
                        start.tilt + fraction * (end.tilt - start.tilt))


def hold_path(pose: ToolPose, joints: Sequence[float], hold_s: float = 0.05) -> JointPath:
    """A path that stays at `joints` (the arm's commanded joints at `pose`)."""
    joints = np.asarray(joints, dtype=float)
    return JointPath(np.array([hold_s]), joints[None, :].copy(), (pose, pose), (0.0, hold_s))


def joints_at(path: JointPath, elapsed_s: float) -> np.ndarray:
    """The path's joints `elapsed_s` after its start, linearly between its points."""
    times = np.concatenate([[0.0], path.times_s])
    joints = np.vstack([path.joints[:1], path.joints])
    return np.array([np.interp(elapsed_s, times, joints[:, j]) for j in range(joints.shape[1])])


def concatenate(paths: Sequence[JointPath]) -> JointPath:
    """One path running `paths` one after the other (each starts where the last ended)."""
    times, joints, knots, knot_times = [], [], [paths[0].knots[0]], [0.0]
    offset = 0.0
    for path in paths:
        times.append(path.times_s + offset)
        joints.append(path.joints)
        knots.extend(path.knots[1:])
        knot_times.extend(t + offset for t in path.knot_times_s[1:])
        offset += path.duration_s
    return JointPath(np.concatenate(times), np.vstack(joints), tuple(knots), tuple(knot_times))


def straight_path(start: ToolPose, end: ToolPose, speed_m_s: float, seed: Sequence[float], *,
                  tilt_speed_rad_s: float = 0.5, step_s: float = 0.05) -> JointPath:
    """Joints along the straight line from `start` to `end`, tilt turning evenly.

    Args:
        start: where the path begins (the arm is there, or commanded there).
        end: where it ends.
        speed_m_s: speed of the face centre.
        seed: joints at `start` (IK branch to keep).
        tilt_speed_rad_s: fastest change of the tilt.
        step_s: time between path points.

    Raises:
        PathUnreachable: a point of the line has no IK solution, or the IK would switch
            branch between two points (the message says where).
    """
    if not (speed_m_s > 0 and tilt_speed_rad_s > 0 and step_s > 0):
        raise ValueError(f'speeds and step must be > 0, got {speed_m_s!r}, '
                         f'{tilt_speed_rad_s!r}, {step_s!r}')
    solve(end, seed)  # an end out of reach is refused before a path to it is sized
    distance = float(np.linalg.norm(end.point - start.point))
    duration = max(distance / speed_m_s, abs(end.tilt - start.tilt) / tilt_speed_rad_s, step_s)
    count = max(1, math.ceil(duration / step_s - 1e-9))
    times = duration * np.arange(1, count + 1) / count
    joints = np.empty((count, 4))
    previous = np.asarray(seed, dtype=float)
    for i, fraction in enumerate(np.arange(1, count + 1) / count):
        pose = ToolPose(start.point + fraction * (end.point - start.point),
                        start.tilt + fraction * (end.tilt - start.tilt))
        joints[i] = solve(pose, previous)
        if np.max(np.abs(joints[i] - previous)) > MAX_JOINT_STEP_RAD:
            raise PathUnreachable(f'the path to {np.round(end.point, 4).tolist()} m would switch '
                                  f'IK branch at {100 * fraction:.0f} % of its length')
        previous = joints[i]
    steps = np.abs(np.diff(np.vstack([np.asarray(seed, dtype=float), joints]), axis=0))
    slowest_step_s = float(steps.max()) / (JOINT_SPEED_SHARE * ARM_VELOCITY_LIMIT)
    if slowest_step_s > duration / count:
        duration = slowest_step_s * count
        times = duration * np.arange(1, count + 1) / count
    return JointPath(times, joints, (start, end), (0.0, duration))


def chain(poses: Sequence[ToolPose], speed_m_s: float, seed: Sequence[float]) -> JointPath:
    """Straight paths through `poses` in turn, each starting from the last one's joints.

    Raises:
        PathUnreachable: a leg of it (the message says where).
    """
    paths = []
    for start, end in zip(poses[:-1], poses[1:], strict=True):
        paths.append(straight_path(start, end, speed_m_s, seed))
        seed = paths[-1].joints[-1]
    return concatenate(paths)


def transfer(start: ToolPose, target: ToolPose, speed_m_s: float,
             seed: Sequence[float]) -> JointPath:
    """A path from `start` to `target` that stays above both (several routes tried).

    Up first, across at the higher of the two heights, then down; failing that the
    straight line; failing that the same as the first with the tool upright meanwhile.

    Raises:
        PathUnreachable: no route works (the message is the first route's reason).
    """
    safe_z = max(float(start.point[2]), float(target.point[2]))
    upright = ToolPose(start.point, 0.0)
    routes = (
        (start, ToolPose([*start.point[:2], safe_z], start.tilt),
         ToolPose([*target.point[:2], safe_z], target.tilt), target),
        (start, target),
        (start, upright, ToolPose([*start.point[:2], safe_z], 0.0),
         ToolPose([*target.point[:2], safe_z], 0.0), target),
    )
    first_error = None
    for route in routes:
        try:
            return chain(route, speed_m_s, seed)
        except PathUnreachable as err:
            first_error = first_error or err
    raise first_error


def reachable_part(start: ToolPose, end: ToolPose, speed_m_s: float,
                   seed: Sequence[float]) -> JointPath:
    """The straight path towards `end`, cut where the arm stops reaching (1 mm steps).

    Raises:
        PathUnreachable: not even the first millimetre is reachable.
    """
    offset = end.point - start.point
    steps = max(1, int(float(np.linalg.norm(offset)) / 0.001))
    reach = 0
    for i in range(1, steps + 1):
        try:
            solve(start.moved(offset * i / steps), seed)
        except PathUnreachable:
            break
        reach = i
    if reach == 0:
        raise PathUnreachable(f'the motion from {np.round(start.point, 4).tolist()} m '
                              'leaves the workspace at once')
    return straight_path(start, start.moved(offset * reach / steps), speed_m_s, seed)
