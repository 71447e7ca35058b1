# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Probe-and-broadcast exploration as a state machine that knows no ROS, clock or arm.

The caller feeds it stamped joint states, IMU samples (accel with the Madgwick attitude)
and barometer samples, and calls `step(now_ns)` at its control rate; `step` returns the
events of `tactex_probe.explorer_interface` (`Command`, `Stop`, `Feedback`, `Recorded`,
`Finished` with the pathway). It drives the simulator (`tactex_probe.closed_loop`) and
the real arm (`probe_node`) alike. Commands reach the arm late, by a varying amount, so
a path that cuts a motion short follows a `Stop` and starts where the joint states then
show the arm standing.

Every touch: move above the point (`tactex_probe.targets` says where), hold still for
the free-air baseline, descend at the descent speed until the barometer reports
contact. Two passes (`Method.TIP_THEN_FACE`): locate, the tool leaning
`tip_margin_rad` past the profile's tilt so the tip touches first and the forward
kinematics at the contact's onset put it on the surface; then measure, the face turned
to the traced profile's normal, pressed to half and full force, the deformation giving
the normal (`tactex_probe.normals`), turned again by the root search of
`tactex_probe.alignment` until the face lay flat. `Method.FACE_ONLY` is the original's
single pass. A failed touch ends its probe with a status; silent joint states or an arm
that does not follow abort the goal; `cancel` lifts first.

Longer than 500 lines: the stages of a touch and their handlers are one state machine,
read top to bottom; its geometry (`targets`), motions (`motion`) and events
(`explorer_interface`) live in their own modules.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import enum
import math

import numpy as np

from tactex_description.mjcf import EDGE_TIP_RADIUS_M
from tactex_probe import targets
from tactex_probe.alignment import best, next_tilt, TouchResult
from tactex_probe.detection import Channel, ContactDetector, ContactEvent
from tactex_probe.explorer_interface import (
    Command,
    ExplorerConfig,
    Feedback,
    Finished,
    Measurement,
    Method,
    Outcome,
    Phase,
    Recorded,
    Stop,
)
from tactex_probe.history import SampleHistory
from tactex_probe.motion import (
    chain,
    hold_path,
    JointPath,
    joints_at,
    PathUnreachable,
    pose_of,
    pose_with_tip_at,
    reachable_part,
    solve,
    straight_path,
    tilt_towards,
    tip_position,
    ToolPose,
    transfer,
)
from tactex_probe.normals import (
    bearing_point,
    estimate_normal,
    NormalEstimate,
    PRESS_STIFFNESS_N_M,
)
from tactex_probe.pathway import ContactStatus, Pathway, ProbeParameters, ProbeRecord

# A tilt change below this is not worth another touch.
MIN_TILT_STEP_RAD = math.radians(0.2)
# A press goes this much further than the press spring needs for its force level (m).
PRESS_MARGIN_M = 0.002
# Each measuring touch presses to these shares of the measuring force, measuring at each.
PRESS_LEVELS = (0.5, 1.0)
# The free-air hold waits up to this many times its length for enough samples.
BASELINE_PATIENCE = 5
# The free-air window ends this long before the contact's onset (ns).
FREE_GUARD_NS = 30_000_000
# How long a measuring window waits for samples stamped inside it to arrive (ns).
LATE_DATA_NS = 1_000_000_000
# A face that never lay flat and turned more than this gives no normal at all.
MAX_UNFLAT_TURN_RAD = math.radians(3.0)
# While moving in free air a force proxy above this is a contact: turning the tool shifts
# the barometer by up to ~0.15 N (the body's weight on the press spring), so the light
# touch threshold of a descent would fire.
MOVING_CONTACT_N = 0.3
# A move stopped by a contact that then vanished is tried again at most this often.
MAX_BLOCKED_RETRIES = 2
# After the arm stopped on a located contact, the contact must still hold this long (s).
CONFIRM_S = 0.1
# After a stop the arm stands still once no joint moved more than REST_MOTION_RAD in the
# joint states of the last REST_S (s); the next path starts from there.
REST_S = 0.2
REST_MOTION_RAD = 0.0025
# The tip touched first only if the tool leaned at least this far past the surface's tilt;
# a point located with less lead (the measured normal tells) is located again.
MIN_TIP_LEAD_RAD = math.radians(5.0)


class _Stage(enum.Enum):
    """Internal steps, each shown to the user as a feedback phase (`_PHASES`)."""

    START = enum.auto()
    MOVING = enum.auto()
    BLOCKED = enum.auto()
    BASELINE = enum.auto()
    DESCENDING = enum.auto()
    CONFIRMING = enum.auto()
    PRESSING = enum.auto()
    SETTLING = enum.auto()
    MEASURING = enum.auto()
    LIFTING = enum.auto()
    RETRACTING = enum.auto()
    CANCELING = enum.auto()
    DONE = enum.auto()


_PHASES = {
    _Stage.START: Phase.MOVING, _Stage.MOVING: Phase.MOVING, _Stage.BLOCKED: Phase.MOVING,
    _Stage.BASELINE: Phase.DESCENDING, _Stage.DESCENDING: Phase.DESCENDING,
    _Stage.CONFIRMING: Phase.DESCENDING,
    _Stage.PRESSING: Phase.MEASURING, _Stage.SETTLING: Phase.MEASURING,
    _Stage.MEASURING: Phase.MEASURING, _Stage.LIFTING: Phase.MEASURING,
    _Stage.RETRACTING: Phase.RETRACTING, _Stage.CANCELING: Phase.RETRACTING,
    _Stage.DONE: Phase.RETRACTING,
}


class _Pass(enum.Enum):
    LOCATE = 'locate'
    MEASURE = 'measure'


@dataclass(frozen=True)
class _Located:
    """Where the tip touched a probe point, and the tool's tilt then."""

    tip_centre: np.ndarray  # centre of the tip sphere at the onset (m, base_link)
    event: ContactEvent
    tilt: float


@dataclass
class _Touch:
    """What one touch of the current probe has seen so far."""

    free_from_ns: int
    free_until_ns: int
    tilt: float
    event: ContactEvent | None = None
    peak_force_n: float = 0.0
    estimates: list[NormalEstimate] = field(default_factory=list)

    @property
    def level(self) -> int:
        """Index of the force level being pressed to (0: light, 1: full)."""
        return len(self.estimates)


class Explorer:
    """Runs one Probe goal.

    Args:
        parameters: the goal.
        config: tuning (default `ExplorerConfig()`).
    """

    def __init__(self, parameters: ProbeParameters, config: ExplorerConfig | None = None
                 ) -> None:
        self.parameters = parameters
        self.config = ExplorerConfig() if config is None else config
        self.history = SampleHistory()
        self.detector = ContactDetector(self.config.detector)
        self.press_force_n = min(self.config.press_force_n, 0.75 * parameters.force_limit)
        self._records: dict[int, ProbeRecord] = {}
        self._located: dict[int, _Located] = {}
        two_pass = self.config.method is Method.TIP_THEN_FACE
        self._pass = _Pass.LOCATE if two_pass else _Pass.MEASURE
        count = parameters.probe_count
        # Locating also touches one step beyond each end (not probe points: nothing is
        # recorded for them), so every probe point's profile slope is a central one.
        self._queue = [-1, *range(count), count] if two_pass else list(range(count))
        self._stage = _Stage.START
        self._index = 0
        self._started_ns: int | None = None
        self._now_ns = 0
        self._stage_ns = 0
        self._path: JointPath | None = None  # None: the arm stands where it was stopped
        self._path_ns = 0
        self._stop_ns: int | None = None  # a stop was sent then; the arm is not at rest yet
        self._after_stop = None  # what to do once the arm stands still after that stop
        self._touch: _Touch | None = None
        self._touches: list[TouchResult] = []
        self._touch_events: list[ContactEvent] = []
        self._touch_windows: list[tuple[int, int]] = []
        self._blocked_retries = 0
        self.measurements: dict[int, Measurement] = {}
        self._relocate_normal: np.ndarray | None = None
        self._cancel_requested = False
        self._last_force_n = 0.0
        self._last_force_ns = 0
        self._events: list = []
        self._finished: Finished | None = None

    # -- inputs -------------------------------------------------------------------------
    def joint_state(self, stamp_ns: int, positions) -> None:
        """Arm joints joint1..joint4 (rad) at `stamp_ns`."""
        self.history.add_joints(stamp_ns, positions)

    def imu(self, stamp_ns: int, accel, quaternion) -> None:
        """Accelerometer (m/s^2, sensor frame) and the Madgwick attitude (w, x, y, z)."""
        if self.history.add_imu(stamp_ns, accel, quaternion) and not self.detector.uses_pressure:
            self._detect(self.detector.update(stamp_ns, math.nan, accel))

    def pressure(self, stamp_ns: int, pressure_pa: float) -> None:
        """Barometer (Pa)."""
        if not self.history.add_pressure(stamp_ns, pressure_pa):
            return
        self._detect(self.detector.update(stamp_ns, pressure_pa))
        if self.detector.armed and self.detector.uses_pressure:
            self._last_force_n = self.detector.force_proxy(pressure_pa)
            self._last_force_ns = int(stamp_ns)
            if self._touch is not None:
                self._touch.peak_force_n = max(self._touch.peak_force_n, self._last_force_n)

    def _detect(self, event: ContactEvent | None) -> None:
        if event is not None and self._touch is not None and self._touch.event is None:
            self._touch.event = event

    def cancel(self) -> None:
        """Stop probing: lift to the approach height, then finish as canceled."""
        self._cancel_requested = True

    @property
    def finished(self) -> Finished | None:
        """The end of the goal, once reached."""
        return self._finished

    @property
    def records(self) -> list[ProbeRecord]:
        """The probes finished so far, in index order."""
        return [self._records[i] for i in sorted(self._records)]

    @property
    def phase(self) -> Phase:
        """The feedback phase now."""
        return _PHASES[self._stage]

    # -- the loop ------------------------------------------------------------------------
    def step(self, now_ns: int) -> list:
        """Advance to `now_ns`; return the events this produced, in order."""
        if self._finished is not None:
            return []
        if self._started_ns is None:
            self._started_ns = self._stage_ns = now_ns
        self._now_ns = now_ns
        self._events = []
        if not self._healthy(now_ns):
            return self._events
        try:
            if self._stop_ns is not None:
                if not self._at_rest():
                    return self._events
                after, self._stop_ns, self._after_stop = self._after_stop, None, None
                if after is not None:
                    after(now_ns)
                    return self._events
            if self._cancel_requested and self._stage not in (_Stage.CANCELING, _Stage.START):
                self._stop(now_ns, lambda now: self._lift_to(now, self._approach_height(),
                                                             _Stage.CANCELING))
            elif self._cancel_requested and self._stage is _Stage.START:
                self._finish(now_ns, Outcome.CANCELED, 'canceled before the arm moved')
            else:
                getattr(self, f'_on_{self._stage.name.lower()}')(now_ns)
        except PathUnreachable as err:
            self._finish(now_ns, Outcome.ABORTED, f'no way to move on: {err}')
        return self._events

    def _healthy(self, now_ns: int) -> bool:
        """Abort when the joint states fall silent or the arm does not follow."""
        latest = self.history.latest_joints
        silent_s = (now_ns - (latest[0] if latest else self._started_ns)) * 1e-9
        if silent_s > self.config.joint_timeout_s * (1 if latest else 4):
            self._finish(now_ns, Outcome.ABORTED, f'no joint state for {silent_s:.2f} s (a '
                                                  'servo or the driver dropped out)')
            return False
        if self._stop_ns is not None and latest is not None and \
                (now_ns - self._stop_ns) * 1e-9 > self.config.motion_timeout_s:
            self._finish(now_ns, Outcome.ABORTED,
                         f'the arm does not stop: it still moved '
                         f'{(now_ns - self._stop_ns) * 1e-9:.1f} s after the stop was sent')
            return False
        if self._path is not None and latest is not None:
            late_s = (now_ns - self._path_ns) * 1e-9 - self._path.duration_s
            error = np.abs(latest[1] - self._path.joints[-1])
            if late_s > self.config.motion_timeout_s and \
                    np.max(error) >= self.config.tracking_tolerance_rad:
                joint = int(np.argmax(error))
                self._finish(now_ns, Outcome.ABORTED,
                             f'the arm does not follow: joint{joint + 1} is {error[joint]:.3f} '
                             f'rad from its goal {late_s:.1f} s after the motion should have '
                             'ended')
                return False
        return True

    # -- stages ---------------------------------------------------------------------------
    def _on_start(self, now_ns: int) -> None:
        """Learn the free-air baseline where the arm stands, then go to the first point."""
        if self.history.latest_joints is None:
            return
        if (now_ns - self._stage_ns) * 1e-9 < self.config.baseline_s:
            return
        self._learn_baseline(now_ns)
        self._emit_feedback()
        self._next_probe(now_ns)

    def _force_since(self, stamp_ns: int) -> float:
        """The latest force proxy if it was read after `stamp_ns`, else 0 (not known yet)."""
        return self._last_force_n if self._last_force_ns > stamp_ns else 0.0

    def _on_moving(self, now_ns: int) -> None:
        if self._force_since(self._stage_ns) >= MOVING_CONTACT_N:
            self._stop(now_ns)
            self._set_stage(_Stage.BLOCKED, now_ns)
        elif self._motion_done(now_ns):
            self._hold(now_ns)
            self._set_stage(_Stage.BASELINE, now_ns)

    def _on_blocked(self, now_ns: int) -> None:
        """A contact while moving: if it outlasts the stop, the way is blocked; else go on."""
        confirm_ns = self._stage_ns + int(CONFIRM_S * 1e9)
        if now_ns < confirm_ns or (self._last_force_ns < confirm_ns
                                   and now_ns - confirm_ns < LATE_DATA_NS):
            return
        if self._force_since(confirm_ns) < MOVING_CONTACT_N and \
                self._blocked_retries < MAX_BLOCKED_RETRIES:
            self._blocked_retries += 1
            try:
                self._command(now_ns, self._path_to_approach(now_ns))
            except PathUnreachable as err:
                self._record_failure(now_ns, ContactStatus.UNREACHABLE, str(err))
                self._retract(now_ns)
                return
            self._set_stage(_Stage.MOVING, now_ns)
            return
        self._record_failure(now_ns, ContactStatus.UNREACHABLE,
                             'contact while moving sideways to the approach pose: the '
                             'surface is higher than the approach height')
        self._lift_to(now_ns, float(self._commanded_pose(now_ns).point[2])
                      + self.parameters.approach_height, _Stage.RETRACTING)

    def _on_baseline(self, now_ns: int) -> None:
        held_s = (now_ns - self._stage_ns) * 1e-9
        if held_s < self.config.baseline_s:
            return
        self._learn_baseline(now_ns)
        if not self.detector.armed:
            if held_s < BASELINE_PATIENCE * self.config.baseline_s:
                return  # samples are coming in slowly: hold a little longer
            self._record_failure(now_ns, ContactStatus.ESTIMATION_FAILED,
                                 f'too few valid barometer or IMU samples in free air in '
                                 f'{held_s:.1f} s')
            self._retract(now_ns)
            return
        self._touch = _Touch(self._stage_ns, now_ns, self._commanded_pose(now_ns).tilt)
        self._descend(now_ns)

    def _on_descending(self, now_ns: int) -> None:
        touch = self._touch
        if touch.event is not None and self._locating:
            self._stop(now_ns)
            self._set_stage(_Stage.CONFIRMING, now_ns)
        elif touch.event is not None:
            self._stop(now_ns, self._press)
        elif self._motion_done(now_ns):
            if self._touches:
                self._record_contact(now_ns, 'lost the surface on a repeated touch')
            elif self._pass is _Pass.MEASURE and self._index in self._located:
                self._record_failure(now_ns, ContactStatus.ESTIMATION_FAILED,
                                     'the face found no surface where the tip touched')
            else:
                depth = self.parameters.max_descent_depth
                self._record_failure(now_ns, ContactStatus.NO_CONTACT,
                                     f'no contact within {depth * 1e3:.1f} mm below the probe '
                                     'point', self._face_point())
            self._retract(now_ns)

    def _on_confirming(self, now_ns: int) -> None:
        """A located contact must outlast the stop: a burst of noise does not."""
        if (now_ns - self._stage_ns) * 1e-9 < CONFIRM_S:
            return
        if self.detector.in_contact:
            self._locate(now_ns)
        else:
            self._touch.event = None
            self._descend(now_ns)

    def _on_pressing(self, now_ns: int) -> None:
        target = self.press_force_n * PRESS_LEVELS[self._touch.level]
        if self._touch.peak_force_n >= self.parameters.force_limit:
            self._record_failure(now_ns, ContactStatus.OVER_FORCE,
                                 f'force proxy {self._touch.peak_force_n:.2f} N reached the '
                                 f'limit {self.parameters.force_limit:.2f} N',
                                 self._face_point())
            self._retract(now_ns)
        elif self._last_force_n >= target or self._motion_done(now_ns):
            # At press speed a late command moves the arm too little to matter (4 mm/s
            # for 1 s turns no joint by 0.1 rad), and pressed into the surface the joint
            # states lag the commanded pose: hold where this core commanded it.
            self._hold(now_ns)
            self._set_stage(_Stage.SETTLING, now_ns)

    def _on_settling(self, now_ns: int) -> None:
        if (now_ns - self._stage_ns) * 1e-9 >= self.config.settle_s:
            self._set_stage(_Stage.MEASURING, now_ns)

    def _on_measuring(self, now_ns: int) -> None:
        end_ns = self._stage_ns + int(self.config.measure_s * 1e9)
        if now_ns < end_ns:
            return
        if not self.history.caught_up(end_ns) and now_ns - end_ns < LATE_DATA_NS:
            return  # the window's last samples are still on their way
        estimate = self._estimate_now(end_ns)
        if estimate is None:
            self._retract(now_ns)
            return
        touch = self._touch
        touch.estimates.append(estimate)
        if touch.level < len(PRESS_LEVELS):
            self._press(now_ns)
            return
        self._touches.append(TouchResult(touch.tilt, *touch.estimates))
        self._touch_events.append(touch.event)
        self._touch_windows.append((self._stage_ns, end_ns))
        target = self._reachable_tilt(estimate.face_centre, next_tilt(self._touches))
        if (not self._touches[-1].flat(self.config.refine_tolerance_rad)
                and len(self._touches) <= self.config.refinements
                and abs(target - touch.tilt) > MIN_TILT_STEP_RAD):
            self._lift_and_turn(now_ns, estimate, target)
        elif self._tip_led_too_little():
            self._relocate(now_ns)
        else:
            self._record_contact(now_ns)
            self._retract(now_ns)

    def _tip_led_too_little(self) -> bool:
        """True when the located point was touched with too little lead for the tip."""
        located = self._located.get(self._index)
        if located is None or self._relocate_normal is not None:
            return False
        normal = best(self._touches, self.config.refine_tolerance_rad).full.normal
        return located.tilt - self._surface_tilt(normal) < MIN_TIP_LEAD_RAD

    def _relocate(self, now_ns: int) -> None:
        """Locate the point again, leaning past the measured normal, then record it."""
        chosen = best(self._touches, self.config.refine_tolerance_rad)
        self._relocate_normal = chosen.full.normal
        try:
            self._command(now_ns, self._path_to_approach(now_ns))
        except PathUnreachable as err:
            self._record_contact(now_ns, f'could not locate it again: {err}')
            self._retract(now_ns)
            return
        self._set_stage(_Stage.MOVING, now_ns)

    @property
    def _locating(self) -> bool:
        """True while a touch is to locate a point with the tip."""
        return self._pass is _Pass.LOCATE or self._relocate_normal is not None

    def _on_lifting(self, now_ns: int) -> None:
        if self._motion_done(now_ns):
            self._hold(now_ns)
            self._set_stage(_Stage.BASELINE, now_ns)

    def _on_retracting(self, now_ns: int) -> None:
        if self._motion_done(now_ns):
            self._next_probe(now_ns)

    def _on_canceling(self, now_ns: int) -> None:
        if self._motion_done(now_ns):
            self._finish(now_ns, Outcome.CANCELED, 'canceled; the arm holds at the approach '
                                                   'height')

    def _on_done(self, now_ns: int) -> None:
        """Nothing left to do."""

    # -- probe points ---------------------------------------------------------------------
    def _next_probe(self, now_ns: int) -> None:
        """Move to the next probe point of the pass (or start the next pass, or finish)."""
        while True:
            if not self._queue and self._pass is _Pass.LOCATE:
                self._pass = _Pass.MEASURE
                self._queue = sorted(i for i in self._located
                                     if 0 <= i < self.parameters.probe_count)
            if not self._queue:
                self._finish(now_ns, Outcome.SUCCEEDED, '')
                return
            self._index = self._queue.pop(0)
            self._touch, self._touches, self._touch_events = None, [], []
            self._touch_windows = []
            self._blocked_retries = 0
            self._relocate_normal = None
            try:
                self._command(now_ns, self._path_to_approach(now_ns))
            except PathUnreachable as err:
                self._record_failure(now_ns, ContactStatus.UNREACHABLE, str(err),
                                     self._point(self._index))
                continue
            self._set_stage(_Stage.MOVING, now_ns)
            return

    def _path_to_approach(self, now_ns: int) -> JointPath:
        """From where the arm is commanded now to the current point's approach pose."""
        return transfer(self._commanded_pose(now_ns), self._approach_pose(),
                        self.config.move_speed_m_s, self._seed())

    def _approach_pose(self) -> ToolPose:
        """The pose above the current point where its descent starts."""
        lift = np.array([0.0, 0.0, self.parameters.approach_height])
        if self._locating:
            if self._relocate_normal is None:
                point = self._point(self._index)
                normal = self._profile_normal(point)
            else:
                point, normal = self._surface_point(self._index), self._relocate_normal
            tilt = self._surface_tilt(normal) + self.config.tip_margin_rad
            tilt = self._reachable_tilt(point, tilt, point + lift, tip=True)
            return pose_with_tip_at(point + lift, tilt)
        if self._index in self._located:
            point = self._surface_point(self._index)
            tilt = self._surface_tilt(self._profile_normal(point))
        else:
            point = self._point(self._index)
            tilt = self._surface_tilt(targets.extrapolated_normal(
                self.records, point, self.parameters.direction, self._heading())) \
                if self.config.align_tool else 0.0
        # Near the edge of the workspace a lower approach may still be reachable.
        for share in (1.0, 0.5, 0.25):
            above = point + share * lift
            try:
                solve(ToolPose(above, tilt), self._seed())
            except PathUnreachable:
                continue
            return ToolPose(above, self._reachable_tilt(point, tilt, above))
        return ToolPose(point + lift, self._reachable_tilt(point, tilt, point + lift))

    def _surface_point(self, index: int) -> np.ndarray:
        """Where the tip touched probe `index`, on the surface under the tip sphere."""
        return targets.surface_point(self._located[index].tip_centre, self._tip_centres(),
                                     self.parameters.direction)

    def _tip_centres(self) -> list[np.ndarray]:
        return [located.tip_centre for located in self._located.values()]

    def _profile_normal(self, point) -> np.ndarray:
        return targets.profile_normal(self._tip_centres(), point, self.parameters.direction)

    def _surface_tilt(self, normal) -> float:
        return tilt_towards(normal, self._heading())

    def _reachable_tilt(self, point, tilt: float, *also, tip: bool = False) -> float:
        return targets.reachable_tilt(point, tilt, also, max_tilt_rad=self.config.max_tilt_rad,
                                      seed=self._seed(), tip=tip)

    def _point(self, index: int) -> np.ndarray:
        return targets.probe_point(self.parameters, index)

    def _is_probe_point(self, index: int) -> bool:
        return 0 <= index < self.parameters.probe_count

    def _approach_height(self) -> float:
        return float(self._point(self._index)[2]
                     + self.parameters.approach_height)

    def _heading(self) -> float:
        return targets.heading(self.parameters, self._index)

    # -- motions --------------------------------------------------------------------------
    def _descend(self, now_ns: int) -> None:
        start = self._commanded_pose(now_ns)
        if not self._touches:
            bottom = self._point(self._index)[2] - \
                self.parameters.max_descent_depth
            if self._locating:
                bottom += start.point[2] - tip_position(start)[2]
            end = ToolPose([*start.point[:2], bottom], start.tilt)
            speed = self.parameters.descent_speed
        else:
            end = start.moved(start.axis * 3.0 * self.config.refine_lift_m)
            speed = min(self.parameters.descent_speed, self.config.press_speed_m_s)
        try:
            path = reachable_part(start, end, speed, self._seed())
        except PathUnreachable as err:
            self._record_failure(now_ns, ContactStatus.UNREACHABLE, str(err))
            self._retract(now_ns)
            return
        self._command(now_ns, path)
        self._set_stage(_Stage.DESCENDING, now_ns)

    def _press(self, now_ns: int) -> None:
        """Press on along the tool axis, no further than the next force level needs.

        The travel is what the press spring needs for the missing force plus
        `PRESS_MARGIN_M`, so however late the force readings come, the force cannot
        overshoot the level by much more than the margin's worth.
        """
        start = self._commanded_pose(now_ns)
        level = self.press_force_n * PRESS_LEVELS[self._touch.level]
        travel = min(self.config.max_press_m, PRESS_MARGIN_M + max(
            0.0, level - self._last_force_n) / PRESS_STIFFNESS_N_M)
        try:
            path = straight_path(start, start.moved(start.axis * travel),
                                 self.config.press_speed_m_s, self._seed())
        except PathUnreachable as err:
            self._record_failure(now_ns, ContactStatus.UNREACHABLE, str(err))
            self._retract(now_ns)
            return
        self._command(now_ns, path)
        self._set_stage(_Stage.PRESSING, now_ns)

    def _hold(self, now_ns: int) -> None:
        """Stay where this core commands the arm now: its last path ended, or a press."""
        self._command(now_ns, hold_path(self._commanded_pose(now_ns), self._seed()))

    def _stop(self, now_ns: int, after=None) -> None:
        """Stop the arm where its driver commands it; `after(now_ns)` once it stands still.

        Meanwhile no stage runs; from then on paths start where the joint states show the
        arm (this core's model of a cut motion may be off by however late it arrived).
        """
        self._path, self._stop_ns, self._after_stop = None, now_ns, after
        self._events.append(Stop())

    def _at_rest(self) -> bool:
        """True when the joint states of the last REST_S, all after the stop, stand still."""
        latest = self.history.latest_joints
        if latest is None or latest[0] - int(REST_S * 1e9) < self._stop_ns:
            return False
        joints = self.history.joints_between(latest[0] - int(REST_S * 1e9), latest[0])
        return float(np.max(np.ptp(joints, axis=0))) < REST_MOTION_RAD

    def _lift_and_turn(self, now_ns: int, estimate: NormalEstimate, tilt: float) -> None:
        """Back off along the tool axis, turn to `tilt` about the contact, touch again."""
        start = self._commanded_pose(now_ns)
        pressed = max(0.0, float(np.dot(start.point - estimate.face_centre, start.axis)))
        lifted = start.moved(-start.axis * (self.config.refine_lift_m + pressed))
        turned = ToolPose(estimate.face_centre, tilt)
        turned = turned.moved(-turned.axis * self.config.refine_lift_m)
        try:
            self._command(now_ns, chain((start, lifted, turned), self.config.move_speed_m_s,
                                       self._seed()))
        except PathUnreachable as err:
            self._record_contact(now_ns, f'no further touch: {err}')
            self._retract(now_ns)
            return
        self._set_stage(_Stage.LIFTING, now_ns)

    def _retract(self, now_ns: int) -> None:
        """Straight up to the approach height of the current probe point."""
        self._lift_to(now_ns, self._approach_height(), _Stage.RETRACTING)

    def _lift_to(self, now_ns: int, height: float, stage: _Stage) -> None:
        """Straight up to `height` (or as far up as the arm reaches), then `stage`."""
        self._touch = None
        start = self._commanded_pose(now_ns)
        end = ToolPose([*start.point[:2], max(height, float(start.point[2]))], start.tilt)
        try:
            self._command(now_ns, reachable_part(start, end, self.config.move_speed_m_s,
                                                self._seed()))
        except PathUnreachable:
            self._hold(now_ns)
        self._set_stage(stage, now_ns)

    def _command(self, now_ns: int, path: JointPath) -> None:
        self._path, self._path_ns = path, now_ns
        self._events.append(Command(path))

    def _seed(self) -> np.ndarray:
        """The joints the arm is commanded to hold now: where every new path starts."""
        if self._path is None:
            return self.history.latest_joints[1]
        return joints_at(self._path, (self._now_ns - self._path_ns) * 1e-9)

    def _commanded_pose(self, now_ns: int) -> ToolPose:
        if self._path is None:
            return pose_of(self.history.latest_joints[1])
        return self._path.pose_at((now_ns - self._path_ns) * 1e-9)

    def _motion_done(self, now_ns: int) -> bool:
        """The path's time is up and the arm arrived (its joints near the path's end).

        Commands reach the arm late on a loaded machine; waiting for the arrival keeps
        the next path starting where the arm really is.
        """
        if (now_ns - self._path_ns) * 1e-9 < self._path.duration_s:
            return False
        latest = self.history.latest_joints
        return latest is not None and latest[0] >= self._path_ns and float(np.max(np.abs(
            latest[1] - self._path.joints[-1]))) < self.config.tracking_tolerance_rad

    def _set_stage(self, stage: _Stage, now_ns: int) -> None:
        changed = _PHASES[stage] is not _PHASES[self._stage]
        self._stage, self._stage_ns = stage, now_ns
        if changed:
            self._emit_feedback()

    # -- measuring ------------------------------------------------------------------------
    def _learn_baseline(self, now_ns: int) -> None:
        """Learn the detector's baseline from the samples since this stage began."""
        self.detector.reset()
        for pressure in self.history.pressures(self._stage_ns, now_ns):
            self.detector.learn(pressure)
        for accel in self.history.accels(self._stage_ns, now_ns):
            self.detector.learn(math.nan, accel)

    def _locate(self, now_ns: int) -> None:
        """The tip touched: its centre at the onset, by the joints at that instant."""
        touch = self._touch
        tilt = self._commanded_pose(now_ns).tilt
        if touch.peak_force_n >= self.parameters.force_limit:
            self._record_failure(now_ns, ContactStatus.OVER_FORCE,
                                 f'force proxy {touch.peak_force_n:.2f} N reached the limit '
                                 f'{self.parameters.force_limit:.2f} N before the arm stopped',
                                 self._face_point())
        else:
            joints = self.history.joints_at([touch.event.onset_ns])[0]
            self._located[self._index] = _Located(tip_position(pose_of(joints)), touch.event,
                                                  tilt)
            if self._relocate_normal is not None:
                self._record_contact(now_ns, 'located again leaning past the measured normal')
        self._retract(now_ns)

    def _face_point(self) -> np.ndarray:
        return pose_of(self.history.latest_joints[1]).point

    def _estimate_now(self, now_ns: int) -> NormalEstimate | None:
        """Estimate from the touch's free-air and measuring windows; None records a failure."""
        touch = self._touch
        pressures = self.history.pressures(self._stage_ns, now_ns)
        force = float(np.mean([self.detector.force_proxy(p) for p in pressures])) \
            if pressures.size else math.nan
        compression = max(force / PRESS_STIFFNESS_N_M, 0.0) if math.isfinite(force) else 0.0
        # Free air: the hold before the descent and the descent itself (same tilt).
        free = self.history.window(touch.free_from_ns,
                                   max(touch.free_until_ns, touch.event.onset_ns - FREE_GUARD_NS))
        pressed = self.history.window(self._stage_ns, now_ns, compression)
        if free is None or pressed is None:
            self._record_failure(now_ns, ContactStatus.ESTIMATION_FAILED,
                                 'no valid IMU sample in the free-air or the measuring window')
            return None
        try:
            estimate = estimate_normal(free, pressed)
        except ValueError as err:
            self._record_failure(now_ns, ContactStatus.ESTIMATION_FAILED, str(err))
            return None
        if estimate.normal[2] <= 0.0:
            self._record_failure(now_ns, ContactStatus.ESTIMATION_FAILED,
                                 'the estimated normal points down')
            return None
        return estimate

    # -- records ----------------------------------------------------------------------------
    def _record_contact(self, now_ns: int, note: str = '') -> None:
        """Record the probe from the flat touch (or the one whose face turned least).

        A face that never lay flat and still turned by more than `MAX_UNFLAT_TURN_RAD` was
        far from the surface's tilt: no normal is claimed (ESTIMATION_FAILED).
        """
        chosen = best(self._touches, self.config.refine_tolerance_rad)
        estimate = chosen.full
        flat = chosen.flat(self.config.refine_tolerance_rad)
        if not flat and abs(estimate.turn_rad) > MAX_UNFLAT_TURN_RAD:
            self._record_failure(
                now_ns, ContactStatus.ESTIMATION_FAILED,
                f'the face never lay flat in {len(self._touches)} touch(es): it still turned '
                f'{math.degrees(estimate.turn_rad):+.1f} deg at tilt '
                f'{math.degrees(chosen.tilt):+.1f} deg{"; " + note if note else ""}')
            return
        if self._index in self._located:
            located = self._located[self._index]
            event = located.event
            position = located.tip_centre - EDGE_TIP_RADIUS_M * estimate.normal
            where = 'tip located'
        else:
            event = self._touch_events[self._touches.index(chosen)]
            position = bearing_point(estimate)
            where = 'face bearing point'
        detail = (f'{where}; {len(self._touches)} touch(es), {"flat" if flat else "NOT flat"}: '
                  f'face turned {math.degrees(estimate.turn_rad):+.2f} deg at tilt '
                  f'{math.degrees(chosen.tilt):+.1f} deg; Madgwick and gravity '
                  f'{math.degrees(estimate.agreement_rad):.2f} deg apart, {estimate.source} used')
        self.measurements[self._index] = Measurement(
            event.onset_ns, self._touch_windows[self._touches.index(chosen)], estimate)
        self._add(ProbeRecord(
            index=self._index, status=ContactStatus.OK, stamp_ns=event.onset_ns,
            position=tuple(float(v) for v in position),
            normal=tuple(float(v) for v in estimate.normal),
            force_proxy=float(PRESS_STIFFNESS_N_M * estimate.compression_m),
            confidence=_confidence(estimate, flat, event.channel),
            detail=f'{detail}; {note}' if note else detail))

    def _record_failure(self, now_ns: int, status: ContactStatus, detail: str,
                        position=None) -> None:
        if position is None:
            position = self._point(self._index)
        if not self._is_probe_point(self._index):
            return  # a point beyond the ends, only located for the profile
        force = self._touch.peak_force_n if self._touch is not None else 0.0
        self._add(ProbeRecord(index=self._index, status=status, stamp_ns=int(now_ns),
                              position=tuple(float(v) for v in position), normal=(0.0, 0.0, 0.0),
                              force_proxy=float(max(force, 0.0)), confidence=0.0,
                              detail=detail))

    def _add(self, record: ProbeRecord) -> None:
        if record.index in self._records:
            return  # one outcome per probe point: the first one stands
        self._records[record.index] = record
        self._events.append(Recorded(record))
        self._emit_feedback()

    def _emit_feedback(self) -> None:
        records = self._records.values()
        last = max(records, key=lambda r: r.stamp_ns) if records else None
        count = self.parameters.probe_count
        self._events.append(Feedback(_PHASES[self._stage], min(max(self._index, 0), count - 1),
                                     count, sum(r.ok for r in records),
                                     last))

    def _finish(self, now_ns: int, outcome: Outcome, message: str) -> None:
        self._stage = _Stage.DONE
        pathway = Pathway(self.parameters, tuple(self.records), int(now_ns))
        self._finished = Finished(pathway, outcome, message)
        self._events.append(self._finished)


def _confidence(estimate: NormalEstimate, flat: bool, channel: Channel) -> float:
    """0..1: the two normals agree (Gaussian, 3 deg scale), the face lay flat, pressure saw it.

    A face that never lay flat gives a normal biased towards the tool's axis: it counts
    a quarter. A contact seen only by the accelerometer counts half; so does a normal
    from gravity alone (the filter was overruled), which cannot see a turn about the
    vertical.
    """
    agreement = 0.5 if estimate.source == 'gravity' else \
        math.exp(-(math.degrees(estimate.agreement_rad) / 3.0) ** 2)
    flatness = 1.0 if flat else 0.25
    channel_weight = 1.0 if channel is Channel.PRESSURE else 0.5
    return float(np.clip(agreement * flatness * channel_weight, 0.0, 1.0))
