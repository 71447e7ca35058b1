# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Watching a sweep while it runs: contact from pressure, force, tracking, sliding speed.

The sweep node feeds `SweepMonitor` every joint state and pressure sample with its time
since the trajectory was sent. The trajectory's own clock starts when the arm is seen to
leave its start as the plan does (so delivery latency and servo lag do not count as
tracking error); until then the arm is at rest and the pressure is its baseline. Leaving
the start is measured along the plan's first motion and farther than the step a servo
makes when the trajectory replaces what it held: a servo holds its goal sagged under the
load (a few mrad, about 1 mm at the edge), the plan starts at the measured joints, so the
goal steps by the sag at once; counted as the departure, that step started the clock up
to 0.37 s early, and the descent and the lift (30 mm/s) read as 10 mm off their command.
The monitor says whether the edge is in contact (the
pressure above its out-of-contact baseline by a threshold), whether `sweep/active` is
true (in the planned contact segment and in contact), and whether to abort: contact lost
in the contact segment for longer than a tolerance, the force proxy over its limit, or
the measured edge too far from the commanded one. At the end it gives the result: the
contact fraction of the segment, the sliding speed along the path, and the press depth
the arm held below the probed surface minus the one asked. No clock and no ROS here.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import math

import numpy as np

from tactex_common.numbers import is_finite_number
from tactex_description.geometry import OPEN_MANIPULATOR_X
from tactex_description.mjcf import EDGE_TIP_RADIUS_M
from tactex_trajectory.planner import SPEED_WINDOW_S, SweepPlan
from tactex_trajectory.poses import ARM

PRESS_STIFFNESS_N_M = OPEN_MANIPULATOR_X.joint('sensor_press').stiffness
# The baseline is the median pressure while the edge is this far or farther above the
# surface in the plan (m).
BASELINE_CLEARANCE_M = 0.005
# Edge travel from the start, along the plan's first motion, that marks the start of the
# motion, planned and measured (m): beyond the step of a servo's sag (about 1 mm).
DEPARTURE_M = 0.003
# Time constant of the sliding speed shown in the feedback (s).
SPEED_SMOOTHING_S = 0.2


@dataclass(frozen=True)
class MonitorSettings:
    """Thresholds of the sweep's watch (SI units).

    Attributes:
        contact_threshold_pa: pressure rise over the baseline that means contact.
        pressure_pa_per_m: pressure rise per metre of body compression (calibration).
        force_limit_n: abort when the force proxy (compression x stiffness) exceeds it.
        contact_loss_tolerance_s: abort when contact is lost this long in the segment.
        tracking_tolerance_m: abort when the measured edge is this far from the commanded.
    """

    contact_threshold_pa: float = 150.0
    pressure_pa_per_m: float = 1.5e6
    force_limit_n: float = 3.0
    contact_loss_tolerance_s: float = 0.5
    tracking_tolerance_m: float = 0.01

    def __post_init__(self) -> None:
        """Reject non-positive or non-finite thresholds."""
        for name in ('contact_threshold_pa', 'pressure_pa_per_m', 'force_limit_n',
                     'contact_loss_tolerance_s', 'tracking_tolerance_m'):
            value = getattr(self, name)
            if not (is_finite_number(value) and value > 0):
                raise ValueError(f'{name} must be a finite number > 0, got {value!r}')


@dataclass(frozen=True)
class MonitorStatus:
    """What the monitor knows after an update."""

    in_contact: bool
    active: bool
    force_n: float
    tracking_error_m: float
    sliding_speed_m_s: float
    progress: float
    abort_reason: str = ''


@dataclass(frozen=True)
class SweepResult:
    """The numbers of a finished (or aborted) sweep.

    Attributes:
        contact_fraction: fraction of the planned contact segment's pressure samples in
            contact (of the part that ran, when aborted).
        speed_mean_m_s, speed_std_m_s: sliding speed along the path while in contact in
            the segment.
        press_depth_error_m: rms of (held - asked) press depth while in contact in the
            segment; held is how deep the measured joints hold the rim below the probed
            surface.
        active_spans_s: (start, end) of each span of sweep/active (time since sending).
    """

    contact_fraction: float
    speed_mean_m_s: float
    speed_std_m_s: float
    press_depth_error_m: float
    active_spans_s: tuple[tuple[float, float], ...]


@dataclass
class _Track:
    times: list[float] = field(default_factory=list)
    values: list = field(default_factory=list)


class SweepMonitor:
    """Watch one sweep of `plan`; feed samples in time order.

    Args:
        plan: the sweep being executed.
        settings: thresholds.
    """

    def __init__(self, plan: SweepPlan, settings: MonitorSettings = MonitorSettings()) -> None:
        self.plan = plan
        self.settings = settings
        self._interpolant = plan.trajectory.interpolant()
        self._baseline_samples: list[float] = []
        self._baseline: float | None = None
        self._pressure = math.nan
        self._in_contact = False
        self._last_contact_s: float | None = None
        self._contact_samples = _Track()  # pressure samples in the segment: in contact?
        self._edges = _Track()  # (travel, press depth) of measured joints while active
        self._active = False
        self._spans: list[list[float]] = []
        self._speed = 0.0
        self._last_travel: tuple[float, float] | None = None
        self._force = 0.0
        self._tracking = 0.0
        self._abort = ''
        self._clear_until_s = self._clear_time()
        self._planned_departure_s, self._departure_direction, self._departure_m = \
            self._departure()
        self._offset_s: float | None = None
        self._rest_edge: np.ndarray | None = None

    def _clear_time(self) -> float:
        """Trajectory time until which the plan keeps the edge well above the surface."""
        descend = self.plan.phase('descend')
        fraction = 1.0 - BASELINE_CLEARANCE_M / self.plan.settings.approach_height_m
        return descend.start_s + max(0.0, fraction) * 0.5 * (descend.end_s - descend.start_s)

    def _departure(self) -> tuple[float, np.ndarray | None, float]:
        """When, in which direction and how far the planned edge departs from its start.

        The departure is the first of DEPARTURE_M, 2 DEPARTURE_M, ... of travel from the
        start after which the plan goes on along the same direction by DEPARTURE_M more;
        the direction is the start's to there. A plan whose first motion is a short step
        that then turns (a sweep planned where the last one ended moves 3 mm and descends)
        would otherwise depart at the corner, which an arm that sags and cuts corners
        never reaches. Where no distance qualifies, the first (or half the plan's largest
        distance from its start, when that is less) is kept. A plan that never leaves its
        start departs at 0 in no direction.
        """
        times = np.linspace(0.0, self.plan.trajectory.duration_s, 4000)
        edges = np.array([ARM.tool_pose(q)[0] for q in self._interpolant(times)])
        offsets = edges - edges[0]
        distances = np.linalg.norm(offsets, axis=1)
        reach = float(np.max(distances))
        first = min(DEPARTURE_M, 0.5 * reach)
        if first <= 1e-6:
            return 0.0, None, DEPARTURE_M

        def departure(threshold: float) -> tuple[int, np.ndarray, float]:
            index = int(np.argmax(distances >= threshold))
            return index, offsets[index] / distances[index], float(threshold)

        def goes_on(index: int, direction: np.ndarray, threshold: float) -> bool:
            return float(np.max(offsets[index:] @ direction)) >= threshold + DEPARTURE_M

        thresholds = np.arange(first, 0.5 * reach + 1e-12, DEPARTURE_M)
        index, direction, threshold = next(
            (d for d in map(departure, thresholds) if goes_on(*d)), departure(first))
        return float(times[index]), direction, threshold

    def _departed(self, measured: np.ndarray) -> bool:
        """Whether the measured edge has left its rest as the plan leaves its start."""
        offset = measured - self._rest_edge
        if self._departure_direction is None:
            return float(np.linalg.norm(offset)) > self._departure_m
        return float(offset @ self._departure_direction) >= self._departure_m

    @property
    def started(self) -> bool:
        """True once the arm was seen leaving its start."""
        return self._offset_s is not None

    def trajectory_time(self, time_s: float) -> float:
        """The trajectory's time at `time_s` (since sending): 0 until the arm starts."""
        return 0.0 if self._offset_s is None else max(0.0, time_s - self._offset_s)

    @property
    def baseline_pa(self) -> float | None:
        """The out-of-contact pressure (None until known)."""
        return self._baseline

    def update_pressure(self, time_s: float, pressure_pa: float) -> MonitorStatus:
        """A pressure sample at `time_s` (since sending); NaN samples are ignored."""
        t_s = self.trajectory_time(time_s)
        if not math.isfinite(pressure_pa):
            return self.status(time_s)
        if t_s <= self._clear_until_s:
            self._baseline_samples.append(pressure_pa)
            return self.status(time_s)
        if self._baseline is None:
            if not self._baseline_samples:
                self._abort = ('no pressure arrived before the descent: contact cannot be '
                               'watched; check the tactile topics')
                return self.status(time_s)
            self._baseline = float(np.median(self._baseline_samples))
        rise = pressure_pa - self._baseline
        self._force = max(0.0, rise) / self.settings.pressure_pa_per_m * PRESS_STIFFNESS_N_M
        self._in_contact = rise > self.settings.contact_threshold_pa
        in_segment = self.plan.contact_start_s <= t_s <= self.plan.contact_end_s
        if self._in_contact:
            self._last_contact_s = t_s
        if in_segment:
            self._contact_samples.times.append(t_s)
            self._contact_samples.values.append(self._in_contact)
            lost_since = self._last_contact_s if self._last_contact_s is not None and \
                self._last_contact_s >= self.plan.contact_start_s else self.plan.contact_start_s
            lost_for = t_s - lost_since
            if not self._in_contact and lost_for > self.settings.contact_loss_tolerance_s:
                travel = self.plan.travel_at(t_s)
                self._abort = (f'contact lost for {lost_for:.2f} s at {travel * 1e3:.0f} mm '
                               f'along the path (tolerance '
                               f'{self.settings.contact_loss_tolerance_s:g} s)')
        if self._force > self.settings.force_limit_n:
            self._abort = (f'force {self._force:.2f} N over the limit '
                           f'{self.settings.force_limit_n:g} N')
        self._set_active(time_s, in_segment and self._in_contact)
        return self.status(time_s)

    def update_joints(self, time_s: float, joints) -> MonitorStatus:
        """Measured joint1..joint4 (rad) at `time_s` (since sending)."""
        joints = np.asarray(joints, dtype=float)[:4]
        if not np.all(np.isfinite(joints)):
            return self.status(time_s)
        measured, _ = ARM.tool_pose(joints)
        if self._offset_s is None:
            if self._rest_edge is None:
                self._rest_edge = measured
            elif self._departed(measured):
                self._offset_s = time_s - self._planned_departure_s
        t_s = self.trajectory_time(time_s)
        commanded, _ = ARM.tool_pose(self._interpolant(
            min(max(t_s, 0.0), self.plan.trajectory.duration_s)))
        self._tracking = float(np.linalg.norm(measured - commanded))
        # The free-space move is fast: there a little latency is a large distance, and
        # nothing is near the surface; tracking is watched from the descent on.
        near_surface = t_s >= self.plan.phase('descend').start_s
        if near_surface and self._tracking > self.settings.tracking_tolerance_m:
            self._abort = (f'the edge is {self._tracking * 1e3:.1f} mm from where it is '
                           f'commanded {t_s:.2f} s into the trajectory '
                           f'({self.plan.phase_at(t_s)}; tolerance '
                           f'{self.settings.tracking_tolerance_m * 1e3:g} mm)')
        slide = self.plan.phase('slide')
        if slide.start_s <= t_s <= slide.end_s:
            travel = float(self.plan.path.travel_of(measured)[0])
            if self._last_travel is not None and t_s > self._last_travel[0]:
                dt = t_s - self._last_travel[0]
                instant = (travel - self._last_travel[1]) / dt
                weight = min(1.0, dt / SPEED_SMOOTHING_S)
                self._speed += weight * (instant - self._speed)
            self._last_travel = (t_s, travel)
            if self._active:
                self._edges.times.append(time_s)
                self._edges.values.append((travel, self._held_depth(measured, travel)))
        else:
            self._speed = 0.0
        return self.status(time_s)

    def _held_depth(self, edge: np.ndarray, travel: float) -> float:
        path = self.plan.path
        point = np.array([np.interp(travel, path.arclength_m, path.points[:, k])
                          for k in range(3)])
        normal = np.array([np.interp(travel, path.arclength_m, path.normals[:, k])
                           for k in range(3)])
        return EDGE_TIP_RADIUS_M - float((edge - point) @ (normal / np.linalg.norm(normal)))

    def _set_active(self, t_s: float, active: bool) -> None:
        if active and not self._active:
            self._spans.append([t_s, t_s])
        if active:
            self._spans[-1][1] = t_s
        self._active = active

    def status(self, time_s: float) -> MonitorStatus:
        """The state at `time_s` (since sending)."""
        length = self.plan.path.length_m
        travel = self.plan.travel_at(self.trajectory_time(time_s))
        return MonitorStatus(self._in_contact, self._active, self._force, self._tracking,
                             self._speed, travel / length if length else 0.0, self._abort)

    def result(self) -> SweepResult:
        """The numbers so far (NaN where nothing was measured)."""
        contact = self._contact_samples.values
        travel = np.array([v[0] for v in self._edges.values])
        depth = np.array([v[1] for v in self._edges.values])
        speeds = window_speeds(np.array(self._edges.times), travel, self._spans)
        asked = self.plan.settings.pose.press_depth_m
        return SweepResult(
            contact_fraction=float(np.mean(contact)) if contact else 0.0,
            speed_mean_m_s=float(np.mean(speeds)) if speeds.size else math.nan,
            speed_std_m_s=float(np.std(speeds)) if speeds.size else math.nan,
            press_depth_error_m=float(np.sqrt(np.mean((depth - asked) ** 2)))
            if depth.size else math.nan,
            active_spans_s=tuple((float(a), float(b)) for a, b in self._spans))


def window_speeds(times_s: np.ndarray, travel_m: np.ndarray, spans_s) -> np.ndarray:
    """Speed (m/s) over each whole `SPEED_WINDOW_S` window inside each span."""
    speeds = []
    for start, end in spans_s:
        inside = (times_s >= start) & (times_s <= end)
        if np.count_nonzero(inside) < 2:
            continue
        edges = np.arange(start, end + 1e-9, SPEED_WINDOW_S)
        if len(edges) < 2:
            continue
        moved = np.interp(edges, times_s[inside], travel_m[inside])
        speeds.append(np.diff(moved) / SPEED_WINDOW_S)
    return np.concatenate(speeds) if speeds else np.zeros(0)
