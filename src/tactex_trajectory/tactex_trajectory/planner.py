# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The sweep planner: probed contacts + the arm's joints -> one joint trajectory.

Phases, each ending at rest: `move` (joint space, from the present joints to above the
first path sample; through a lift straight up when the direct move would come close to
the surface), `descend` (along the first normal until the rim is pressed in), `settle`
(hold while the body and the pressure settle), `slide` (along the path: ramp up, the
constant sliding speed, ramp down) and `lift` (along the last normal). The planned
contact segment is the constant-speed part of the slide; a path too short for it to
last `MIN_CONTACT_S` is refused (the sweep could not measure its speed). The whole
trajectory is
checked by the driver's own validation before it is returned, so the driver and the
simulator accept what the planner makes.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import math

import numpy as np

from tactex_common.constants import SLIDING_SPEED_M_S
from tactex_common.numbers import is_finite_number
from tactex_description.mjcf import EDGE_TIP_RADIUS_M
from tactex_description.speed_ramp import RAMP_ACCELERATION_M_S2, ramped_law
from tactex_driver.errors import TrajectoryRejected
from tactex_driver.playback import JointLimits, LIMIT_TOLERANCE, plan
from tactex_trajectory.errors import SweepRefused
from tactex_trajectory.path import MAX_EXTENT_M, path_from_contacts, PathSettings, SweepPath
from tactex_trajectory.poses import (
    ARM,
    edge_positions,
    PoseSettings,
    reached_rotation,
    solve_poses,
    sweep_poses,
    SweepPoses,
)
from tactex_trajectory.timing import (
    check_duration,
    concatenate,
    JointPath,
    move_duration,
    ramp_duration,
    timed_move,
    TimedJoints,
)

# Edge travel between the solved poses of a straight approach, descent or lift (m).
LINE_STEP_M = 0.001
# A move closer than this fraction of the approach height to the surface goes via a lift.
CLEARANCE_FRACTION = 0.5
# Moves and dwells last at least this long (s).
MIN_MOVE_S = 0.5
# Edge positions checked along a move for clearance.
CLEARANCE_SAMPLES = 60
LIMITS = JointLimits.of_robot()
# A sweep's sliding speed is measured over windows this long (s) of its contact segment.
SPEED_WINDOW_S = 0.25
# The constant-speed contact segment lasts at least this long (s): two speed windows.
MIN_CONTACT_S = 2 * SPEED_WINDOW_S


@dataclass(frozen=True)
class SweepSettings:
    """Everything a sweep is planned with (SI units).

    Attributes:
        sliding_speed_m_s: speed of the edge along the surface while in contact.
        approach_height_m: height above the surface (along the normal) where the
            descent starts and the lift ends.
        descent_speed_m_s: peak speed of the descent and the lift.
        ramp_acceleration_m_s2: largest acceleration of the edge in the speed ramps.
        settle_s: dwell pressed into the surface before sliding.
        path: how contacts become the path.
        pose: edge offset, press depth and residual tolerance.
    """

    sliding_speed_m_s: float = SLIDING_SPEED_M_S
    approach_height_m: float = 0.02
    descent_speed_m_s: float = 0.03
    ramp_acceleration_m_s2: float = RAMP_ACCELERATION_M_S2
    settle_s: float = 0.3
    path: PathSettings = field(default_factory=PathSettings)
    pose: PoseSettings = field(default_factory=PoseSettings)

    def __post_init__(self) -> None:
        """Reject non-positive or non-finite values."""
        for name in ('sliding_speed_m_s', 'approach_height_m', 'descent_speed_m_s',
                     'ramp_acceleration_m_s2'):
            value = getattr(self, name)
            if not (is_finite_number(value) and value > 0):
                raise ValueError(f'{name} must be a finite number > 0, got {value!r}')
        if not (isinstance(self.settle_s, (int, float)) and 0 <= self.settle_s < 60):
            raise ValueError(f'settle_s must be in [0, 60), got {self.settle_s!r}')


@dataclass(frozen=True)
class Phase:
    """A named part of the trajectory, [start_s, end_s] from its start."""

    name: str
    start_s: float
    end_s: float


@dataclass(frozen=True)
class SweepPlan:
    """A planned sweep.

    Attributes:
        trajectory: the joint trajectory, starting at the present joints at t = 0.
        path: the path it follows (with the contacts dropped and why).
        poses: the solved pose of every path sample (residuals, IK branch).
        phases: move, descend, settle, slide, lift (a move is left out when the arm is
            already there).
        contact_start_s, contact_end_s: the planned contact segment (constant speed).
        settings: what it was planned with.
    """

    trajectory: TimedJoints
    path: SweepPath
    poses: SweepPoses
    phases: tuple[Phase, ...]
    contact_start_s: float
    contact_end_s: float
    settings: SweepSettings

    def phase(self, name: str) -> Phase:
        """The phase called `name`.

        Raises:
            KeyError: no such phase in this plan.
        """
        for phase in self.phases:
            if phase.name == name:
                return phase
        raise KeyError(f'no phase {name!r}; phases: {[p.name for p in self.phases]}')

    def phase_at(self, t_s: float) -> str:
        """Name of the phase running at `t_s` ('' after the end)."""
        return next((p.name for p in self.phases if t_s <= p.end_s), '')

    def travel_at(self, t_s: float) -> float:
        """Arc length (m) of the path covered at `t_s` (0 before, the length after)."""
        slide = self.phase('slide')
        law = ramped_law(self.path.length_m, self.settings.sliding_speed_m_s,
                         self._ramp_s)
        return float(law.position(np.array(t_s - slide.start_s)))

    @property
    def _ramp_s(self) -> float:
        return self.contact_start_s - self.phase('slide').start_s


def plan_sweep(points, normals, ok, start_joints, settings: SweepSettings = SweepSettings()
               ) -> SweepPlan:
    """Plan a sweep along probed contacts from the arm's present joints.

    Args:
        points: (n, 3) contact positions in base_link (m).
        normals: (n, 3) outward surface normals.
        ok: (n,) True for contacts the probe reports as good (None: all).
        start_joints: joint1..joint4 (rad), optionally the gripper (m) as a fifth value.
        settings: speeds, heights, path and pose settings.

    Raises:
        PathError: the contacts give no usable path.
        SweepRefused: the arm cannot sweep it as asked; the message says why and where.
    """
    start = np.asarray(start_joints, dtype=float)
    if start.shape not in ((4,), (5,)) or not np.all(np.isfinite(start)):
        raise ValueError(f'start_joints must be 4 or 5 finite values, got {start_joints!r}')
    current = np.concatenate([start, [0.0]]) if start.size == 4 else start
    outside = ((current < LIMITS.lower - LIMIT_TOLERANCE)
               | (current > LIMITS.upper + LIMIT_TOLERANCE))
    if np.any(outside[:4]):  # the driver refuses a trajectory from there anyway
        joint = int(np.argmax(outside[:4]))
        raise SweepRefused(f'{LIMITS.names[joint]} = {current[joint]:.4g} is outside its '
                           f'limits [{LIMITS.lower[joint]:.4f}, {LIMITS.upper[joint]:.4f}]; '
                           'move the arm inside them first')
    path = path_from_contacts(points, normals, ok, settings.path)
    poses = sweep_poses(path, settings.pose, current[:4])
    slide_path = JointPath(path.arclength_m, poses.joints)
    ramp_s = ramp_duration(slide_path, settings.sliding_speed_m_s,
                           settings.ramp_acceleration_m_s2)
    ramp_m = settings.sliding_speed_m_s * ramp_s / 2.0
    contact_m = settings.sliding_speed_m_s * MIN_CONTACT_S
    if path.length_m < 2.0 * ramp_m + contact_m:
        raise SweepRefused(f'the path is {path.length_m * 1e3:.1f} mm long; ramping to '
                           f'{settings.sliding_speed_m_s * 1e3:g} mm/s and back takes '
                           f'{2e3 * ramp_m:.1f} mm, and the contact segment slides at that '
                           f'speed for at least {MIN_CONTACT_S:g} s ({contact_m * 1e3:.1f} mm) '
                           'to measure it: probe a longer pathway or slide slower')
    law = ramped_law(path.length_m, settings.sliding_speed_m_s, ramp_s)
    check_duration(law.duration_s, f'sliding {path.length_m * 1e3:.1f} mm at '
                                   f'{settings.sliding_speed_m_s:.3g} m/s')
    dense_t = np.linspace(0.0, law.duration_s, 20 * len(path.arclength_m) + 200)
    slide_t = np.interp(path.arclength_m, law.position(dense_t), dense_t)
    slide_t[0], slide_t[-1] = 0.0, law.duration_s
    slide = slide_path.timed(law, slide_t)
    descend = _line(path, poses, 0, settings, down=True)
    lift = _line(path, poses, -1, settings, down=False)
    parts = [('descend', descend), ('settle', _dwell(poses.joints[0], settings.settle_s)),
             ('slide', slide), ('lift', lift)]
    moves = _moves(current[:4], descend.positions[0], path, settings)
    named = [('move', move) for move in moves] + parts
    trajectory = concatenate([part for _, part in named])
    phases, clock = [], 0.0
    for name, part in named:
        phases.append(Phase(name, clock, clock + part.duration_s))
        clock += part.duration_s
    phases = _merge_moves(phases)
    slide_phase = next(p for p in phases if p.name == 'slide')
    _check_with_driver(trajectory, current)
    return SweepPlan(trajectory, path, poses, tuple(phases), slide_phase.start_s + ramp_s,
                     slide_phase.end_s - ramp_s, settings)


def retract(plan: SweepPlan, joints) -> TimedJoints:
    """Lift the edge off the surface from the arm's present joints (an abort or a cancel).

    The edge rises straight along the path's normal under it, by the approach height, at
    the descent speed, keeping the sensor's orientation, on the sweep's IK branch; where
    that cannot be solved it rises straight up. An edge already as high above the path as
    the approach (where the planned lift ends) holds where it is. The first point is
    `joints` at t = 0.
    """
    joints = np.asarray(joints, dtype=float)[:4]
    hold = TimedJoints(np.zeros(1), joints[None], np.zeros((1, 4)), np.zeros((1, 4)))
    edge, _ = ARM.tool_pose(joints)
    travel = float(plan.path.travel_of(edge)[0])
    point, normal = (np.array([np.interp(travel, plan.path.arclength_m, values[:, k])
                               for k in range(3)])
                     for values in (plan.path.points, plan.path.normals))
    normal /= np.linalg.norm(normal)
    height = plan.settings.approach_height_m
    rim_height = float((edge - point) @ normal) - EDGE_TIP_RADIUS_M
    if rim_height >= height - plan.settings.pose.press_depth_m - LINE_STEP_M:
        return hold
    lifts = np.linspace(0.0, height, max(2, int(math.ceil(height / LINE_STEP_M)) + 1))
    rotation = reached_rotation(joints)
    for direction in (normal, np.array([0.0, 0.0, 1.0])):
        try:
            solved = solve_poses(edge + lifts[:, None] * direction,
                                 np.repeat(rotation[None], len(lifts), axis=0), joints,
                                 plan.settings.pose.max_residual_rad, branch=plan.poses.branch)
        except SweepRefused:
            continue
        line = JointPath(lifts, solved.joints)
        return timed_move(line, move_duration(line, peak_speed=plan.settings.descent_speed_m_s,
                                              minimum_s=MIN_MOVE_S))
    return hold


def _line(path: SweepPath, poses: SweepPoses, index: int, settings: SweepSettings, *,
          down: bool) -> TimedJoints:
    """Straight along the normal of a path end: down onto it or up from it."""
    height = settings.approach_height_m
    if height > MAX_EXTENT_M:  # refused before its poses are allocated
        raise SweepRefused(f"an approach height of {height:.3g} m is beyond the arm's reach")
    count = max(2, int(math.ceil(height / LINE_STEP_M)) + 1)
    lifts = np.linspace(height, 0.0, count) if down else np.linspace(0.0, height, count)
    point, normal = path.points[index], path.normals[index]
    positions = edge_positions(np.tile(point, (count, 1)), np.tile(normal, (count, 1)),
                               settings.pose.press_depth_m, lifts)
    rotations = np.repeat(poses.rotations[index][None], count, axis=0)
    # Solve from the pressed pose outwards so every solution is seeded by its neighbour.
    order = slice(None, None, -1) if down else slice(None)
    solved = solve_poses(positions[order], rotations[order], poses.joints[index],
                         settings.pose.max_residual_rad, branch=poses.branch,
                         labels=[f'{"descent" if down else "lift"} at {lift * 1e3:.0f} mm '
                                 f'above the surface' for lift in lifts[order]])
    joints = solved.joints[order]
    line = JointPath(np.abs(lifts - lifts[0]), joints)
    return timed_move(line, move_duration(line, peak_speed=settings.descent_speed_m_s,
                                          minimum_s=MIN_MOVE_S))


def _dwell(joints: np.ndarray, duration_s: float) -> TimedJoints:
    if duration_s <= 0.0:
        return TimedJoints(np.zeros(1), joints[None], np.zeros((1, 4)), np.zeros((1, 4)))
    return TimedJoints(np.array([0.0, duration_s]), np.tile(joints, (2, 1)), np.zeros((2, 4)),
                       np.zeros((2, 4)))


def _moves(start: np.ndarray, goal: np.ndarray, path: SweepPath,
           settings: SweepSettings) -> list[TimedJoints]:
    """Joint-space moves from the present joints to above the first sample.

    Direct when it keeps clear of the surface; otherwise via the start lifted straight
    up to the approach height above the highest path point.

    Raises:
        SweepRefused: neither way keeps clear.
    """
    if np.max(np.abs(goal - start)) < 1e-6:
        return []
    direct = _move(start, goal)
    if not _too_close(direct, path, settings):
        return [direct]
    position, pitch = ARM.tool_pose(start)
    top = float(np.max(path.points[:, 2])) + settings.approach_height_m + EDGE_TIP_RADIUS_M
    lifted = ARM.inverse([position[0], position[1], max(top, float(position[2]))], pitch,
                         seed=start)
    if lifted.reachable:
        # The lift rises from wherever the edge is (even pressed in): only the travel
        # after it must keep clear.
        moves = [_move(start, lifted.solutions[0]), _move(lifted.solutions[0], goal)]
        if not _too_close(moves[1], path, settings):
            return moves
    raise SweepRefused('the move from the present pose to above the first path sample '
                       'would pass within '
                       f'{CLEARANCE_FRACTION * settings.approach_height_m * 1e3:.0f} mm of the '
                       'surface; move the arm above the pathway first')


def _move(start: np.ndarray, goal: np.ndarray) -> TimedJoints:
    path = JointPath(np.array([0.0, 1.0]), np.vstack([start, goal]))
    return timed_move(path, move_duration(path, minimum_s=MIN_MOVE_S))


def _too_close(move: TimedJoints, path: SweepPath, settings: SweepSettings) -> bool:
    """True when the edge comes within the clearance of the surface near the path."""
    times = np.linspace(0.0, move.duration_s, CLEARANCE_SAMPLES)
    joints = move.interpolant()(times)
    clearance = CLEARANCE_FRACTION * settings.approach_height_m + EDGE_TIP_RADIUS_M
    for q in joints:
        edge, _ = ARM.tool_pose(q)
        offsets = edge - path.points
        near = np.linalg.norm(offsets[:, :2], axis=1) < settings.approach_height_m
        heights = np.sum(offsets * path.normals, axis=1)
        if np.any(near & (heights < clearance - 1e-9)):
            return True
    return False


def _merge_moves(phases: list[Phase]) -> list[Phase]:
    """One `move` phase for the (one or two) moves."""
    moves = [p for p in phases if p.name == 'move']
    rest = [p for p in phases if p.name != 'move']
    if not moves:
        return rest
    return [Phase('move', moves[0].start_s, moves[-1].end_s)] + rest


def _check_with_driver(trajectory: TimedJoints, current: np.ndarray) -> None:
    """Refuse what the driver would refuse (limits, profile, start)."""
    try:
        plan(list(trajectory.joint_names), trajectory.times_s.tolist(),
             trajectory.positions.tolist(), trajectory.velocities.tolist(), current, LIMITS)
    except TrajectoryRejected as err:
        raise SweepRefused(f'the driver would reject the trajectory: {err}') from None

