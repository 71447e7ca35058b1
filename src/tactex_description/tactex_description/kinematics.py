# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Forward kinematics of any frame and analytic inverse kinematics of the 4-DOF arm.

The arm is planar after joint1: joints 2-4 turn about parallel y axes, so a tool
point in the x-z plane of `link5` reaches a position p with a tool pitch phi
(rotation of link5 about its y axis from the horizontal; positive tilts the tool
down, pi/2 points it straight at the floor) by at most four solutions: joint1
facing the target or turned away by pi, times elbow up or elbow down.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
import enum
import math

import numpy as np
from transforms3d.axangles import axangle2mat
from transforms3d.euler import euler2mat

from tactex_common import frames
from tactex_description.geometry import (
    ARM_JOINT_NAMES,
    Joint,
    JointKind,
    OPEN_MANIPULATOR_X,
    RobotGeometry,
)

# A target this far beyond the reach still counts as on the boundary (m). It is far
# below the 1e-9 m the kinematics promise and far above double rounding.
REACH_TOLERANCE_M = 1e-11


def joint_transform(joint: Joint, position: float) -> np.ndarray:
    """Return the 4x4 transform parent -> child of `joint` at `position` (rad or m)."""
    transform = np.eye(4)
    transform[:3, :3] = euler2mat(*joint.origin_rpy, axes='sxyz')
    transform[:3, 3] = joint.origin_xyz
    if joint.kind is JointKind.FIXED or position == 0.0:
        return transform
    motion = np.eye(4)
    if joint.kind is JointKind.REVOLUTE:
        motion[:3, :3] = axangle2mat(joint.axis, position)
    else:
        motion[:3, 3] = np.asarray(joint.axis) * position
    return transform @ motion


def forward_kinematics(
    positions: Mapping[str, float] | Sequence[float],
    frame: str = frames.EDGE,
    *,
    robot: RobotGeometry = OPEN_MANIPULATOR_X,
) -> np.ndarray:
    """Return the 4x4 pose of `frame` in the root frame.

    Args:
        positions: joint positions by name, or the four arm joints in order; joints
            not given (compliant ones, the gripper) are at zero.
        frame: any link of the robot.
        robot: the geometry to use.

    Raises:
        ValueError: not four arm joints, or a position that is not finite.
    """
    if not isinstance(positions, Mapping):
        values = np.asarray(positions, dtype=float)
        if values.shape != (len(ARM_JOINT_NAMES),):
            raise ValueError(
                f'expected {len(ARM_JOINT_NAMES)} arm joint positions, got shape '
                f'{values.shape!r}')
        positions = dict(zip(ARM_JOINT_NAMES, values, strict=True))
    if not all(math.isfinite(float(v)) for v in positions.values()):
        raise ValueError(f'joint positions must be finite, got {dict(positions)!r}')
    pose = np.eye(4)
    for joint in robot.chain_to(frame):
        source = joint.mimic_of or joint.name
        pose = pose @ joint_transform(joint, float(positions.get(source, 0.0)))
    return pose


class Unreachable(enum.Enum):
    """Why the inverse kinematics has no solution."""

    OUT_OF_REACH = 'out of reach'
    JOINT_LIMIT = 'joint limit'


@dataclass(frozen=True)
class IKResult:
    """All joint solutions (joint1..joint4) for a target, or the reason there are none."""

    solutions: tuple[np.ndarray, ...]
    reason: Unreachable | None = None
    detail: str = ''

    @property
    def reachable(self) -> bool:
        """True when at least one solution exists."""
        return bool(self.solutions)


@dataclass(frozen=True)
class PlanarArm:
    """The arm reduced to its plane: constants derived from a `RobotGeometry`.

    Attributes:
        base_x: x of the joint1 axis in the root frame (m).
        shoulder_z: height of joint2 in the root frame (m).
        upper: (x, z) of joint3 in the joint2 frame (m).
        forearm: x of joint4 in the joint3 frame (m).
        tool: (x, z) of the tool point in the link5 frame (m).
        lower, upper_limit: joint limits of joint1..joint4 (rad).
    """

    base_x: float
    shoulder_z: float
    upper: tuple[float, float]
    forearm: float
    tool: tuple[float, float]
    lower: np.ndarray
    upper_limit: np.ndarray

    @classmethod
    def from_geometry(cls, robot: RobotGeometry = OPEN_MANIPULATOR_X,
                      tool_frame: str = frames.EDGE) -> PlanarArm:
        """Derive the planar constants, checking that the arm really is planar."""
        j1, j2, j3, j4 = (robot.joint(name) for name in ARM_JOINT_NAMES)
        if j1.axis != (0.0, 0.0, 1.0) or any(j.axis != (0.0, 1.0, 0.0) for j in (j2, j3, j4)):
            raise ValueError('analytic IK needs joint1 about z and joints 2-4 about y')
        if any(j.origin_xyz[1] != 0.0 or j.origin_rpy != (0.0, 0.0, 0.0)
               for j in (j2, j3, j4)) or j2.origin_xyz[0] != 0.0:
            raise ValueError('analytic IK needs joints 2-4 in one plane through joint1')
        root_to_j1 = forward_kinematics({}, j1.parent, robot=robot)
        link5_to_tool = np.linalg.inv(forward_kinematics({}, 'link5', robot=robot)) @ \
            forward_kinematics({}, tool_frame, robot=robot)
        if abs(link5_to_tool[1, 3]) > 1e-12:
            raise ValueError(f'tool frame {tool_frame!r} is not in the arm plane')
        limits = [(j.lower, j.upper) for j in (j1, j2, j3, j4)]
        return cls(
            base_x=float(root_to_j1[0, 3] + j1.origin_xyz[0]),
            shoulder_z=float(root_to_j1[2, 3] + j1.origin_xyz[2] + j2.origin_xyz[2]),
            upper=(j3.origin_xyz[0], j3.origin_xyz[2]),
            forearm=j4.origin_xyz[0],
            tool=(float(link5_to_tool[0, 3]), float(link5_to_tool[2, 3])),
            lower=np.array([lo for lo, _ in limits]),
            upper_limit=np.array([hi for _, hi in limits]),
        )

    @property
    def reach(self) -> tuple[float, float]:
        """Smallest and largest distance from joint2 to joint4 (m)."""
        upper_len = math.hypot(*self.upper)
        return abs(upper_len - self.forearm), upper_len + self.forearm

    def tool_pose(self, joints: Sequence[float]) -> tuple[np.ndarray, float]:
        """Return the tool point (m, root frame) and tool pitch (rad) of four arm joints.

        Raises:
            ValueError: a joint position that is not finite.
        """
        if not all(math.isfinite(float(q)) for q in joints):
            raise ValueError(f'joint positions must be finite, got {joints!r}')
        # Modulo 2 pi first, so sums of huge angles cannot overflow.
        q1, q2, q3, q4 = (math.remainder(float(q), 2.0 * math.pi) for q in joints)
        pitch = q2 + q3 + q4
        radial = (self.upper[0] * math.cos(q2) + self.upper[1] * math.sin(q2)
                  + self.forearm * math.cos(q2 + q3)
                  + self.tool[0] * math.cos(pitch) + self.tool[1] * math.sin(pitch))
        height = (self.shoulder_z - self.upper[0] * math.sin(q2) + self.upper[1] * math.cos(q2)
                  - self.forearm * math.sin(q2 + q3)
                  - self.tool[0] * math.sin(pitch) + self.tool[1] * math.cos(pitch))
        position = np.array([self.base_x + radial * math.cos(q1), radial * math.sin(q1), height])
        return position, _wrap(pitch)

    def inverse(self, position: Sequence[float], pitch: float, *,
                seed: Sequence[float] | None = None) -> IKResult:
        """Return every joint solution placing the tool point at `position` with `pitch`.

        Args:
            position: target in the root frame (m).
            pitch: tool pitch (rad, any finite value; taken modulo 2 pi), see the module
                docstring.
            seed: joint vector to sort solutions by closeness to; its joint1 is also
                used where joint1 is undefined (target on the joint1 axis).

        Raises:
            ValueError: a target or seed that is not finite, or a seed not of four joints.
        """
        px, py, pz = (float(v) for v in position)
        pitch = float(pitch)
        if not all(math.isfinite(v) for v in (px, py, pz, pitch)):
            raise ValueError(f'target must be finite, got position {position!r}, '
                             f'pitch {pitch!r}')
        seed_q = None if seed is None else np.asarray(seed, dtype=float)
        if seed_q is not None and (seed_q.shape != (4,) or not np.all(np.isfinite(seed_q))):
            raise ValueError(f'seed must be four finite joint positions, got {seed!r}')
        # Taken modulo 2 pi first: q4 = pitch - q2 - q3 of a pitch of 1e15 rad would keep
        # only 1/8 rad of resolution.
        pitch = math.remainder(pitch, 2.0 * math.pi)
        dx = px - self.base_x
        radial_distance = math.hypot(dx, py)
        if radial_distance < 1e-12:
            heading = 0.0 if seed_q is None else float(seed_q[0])
        else:
            heading = math.atan2(py, dx)
        candidates = []
        for q1, radial in ((heading, radial_distance), (_wrap(heading + math.pi),
                                                         -radial_distance)):
            candidates.extend(self._planar(q1, radial, pz, pitch))
        if not candidates:
            low, high = self.reach
            distance = self._wrist_distance(radial_distance, pz, pitch)
            gap = distance - high if distance > high else low - distance
            return IKResult((), Unreachable.OUT_OF_REACH,
                            f'wrist is {distance:.6f} m from joint2, reach is '
                            f'{low:.6f}..{high:.6f} m: out of reach by {gap:.3g} m')
        within = [q for q in candidates
                  if np.all(q >= self.lower - 1e-12) and np.all(q <= self.upper_limit + 1e-12)]
        if not within:
            return IKResult((), Unreachable.JOINT_LIMIT, _limit_detail(
                candidates, self.lower, self.upper_limit))
        within = _unique(within)
        if seed_q is not None:
            within.sort(key=lambda q: float(np.sum(_wrap_array(q - seed_q) ** 2)))
        return IKResult(tuple(within))

    def _wrist_distance(self, radial: float, height: float, pitch: float) -> float:
        wrist_r, wrist_z = self._wrist(radial, height, pitch)
        return math.hypot(wrist_r, wrist_z - self.shoulder_z)

    def _wrist(self, radial: float, height: float, pitch: float) -> tuple[float, float]:
        c, s = math.cos(pitch), math.sin(pitch)
        return (radial - self.tool[0] * c - self.tool[1] * s,
                height + self.tool[0] * s - self.tool[1] * c)

    def _planar(self, q1: float, radial: float, height: float,
                pitch: float) -> list[np.ndarray]:
        wrist_r, wrist_z = self._wrist(radial, height, pitch)
        dr, dz = wrist_r, wrist_z - self.shoulder_z
        d2 = dr * dr + dz * dz
        upper_len = math.hypot(*self.upper)
        low, high = self.reach
        distance = math.sqrt(d2)
        if distance > high + REACH_TOLERANCE_M or distance < low - REACH_TOLERANCE_M:
            return []
        # Elbow angle delta between the forearm and the upper-arm vector, from the
        # factorised law of cosines (stable at full stretch and full fold).
        cos_term = d2 - upper_len ** 2 - self.forearm ** 2
        sin_sq = max(0.0, (high * high - d2) * (d2 - low * low))
        bend = math.atan2(math.sqrt(sin_sq), cos_term)
        upper_angle = math.atan2(self.upper[1], self.upper[0])
        solutions = []
        for delta in (bend, -bend):
            polar_upper = math.atan2(dz, dr) - math.atan2(
                self.forearm * math.sin(delta), upper_len + self.forearm * math.cos(delta))
            q2 = upper_angle - polar_upper
            q3 = -delta - upper_angle
            q4 = pitch - q2 - q3
            solutions.append(np.array([_wrap(q1), _wrap(q2), _wrap(q3), _wrap(q4)]))
        return solutions


def _wrap(angle: float) -> float:
    """Wrap an angle into [-pi, pi)."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


def _wrap_array(angles: np.ndarray) -> np.ndarray:
    return (angles + np.pi) % (2.0 * np.pi) - np.pi


def _unique(solutions: list[np.ndarray]) -> list[np.ndarray]:
    unique: list[np.ndarray] = []
    for q in solutions:
        if all(np.max(np.abs(_wrap_array(q - other))) > 1e-9 for other in unique):
            unique.append(q)
    return unique


def _limit_detail(candidates: list[np.ndarray], lower: np.ndarray, upper: np.ndarray) -> str:
    reasons = []
    for q in candidates:
        for name, value, lo, hi in zip(ARM_JOINT_NAMES, q, lower, upper, strict=True):
            if not lo - 1e-12 <= value <= hi + 1e-12:
                reasons.append(f'{name}={value:.4f} rad outside [{lo:.4f}, {hi:.4f}]')
                break
    return 'every solution breaks a joint limit: ' + '; '.join(dict.fromkeys(reasons))


def inverse_kinematics(position: Sequence[float], pitch: float, *,
                       tool_frame: str = frames.EDGE,
                       seed: Sequence[float] | None = None) -> IKResult:
    """Solve the arm for a tool point of `OPEN_MANIPULATOR_X` (see `PlanarArm.inverse`)."""
    return _planar_arm(tool_frame).inverse(position, pitch, seed=seed)


_PLANAR_ARMS: dict[str, PlanarArm] = {}


def _planar_arm(tool_frame: str) -> PlanarArm:
    if tool_frame not in _PLANAR_ARMS:
        _PLANAR_ARMS[tool_frame] = PlanarArm.from_geometry(OPEN_MANIPULATOR_X, tool_frame)
    return _PLANAR_ARMS[tool_frame]


def tool_pose(joints: Sequence[float], *, tool_frame: str = frames.EDGE
              ) -> tuple[np.ndarray, float]:
    """Return the tool point (m) and pitch (rad) of `OPEN_MANIPULATOR_X` at `joints`."""
    return _planar_arm(tool_frame).tool_pose(joints)
