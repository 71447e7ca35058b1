# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What the explorer is told and what it answers: its configuration, phases and events.

`tactex_probe.exploration.Explorer` takes an `ExplorerConfig` and returns, from each
`step`, `Command`, `Stop`, `Feedback`, `Recorded` and finally `Finished` events; its
`Phase` values are tactex_msgs/action/Probe's PHASE_* codes.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import enum
import math

from tactex_probe.detection import DetectorConfig
from tactex_probe.motion import JointPath
from tactex_probe.normals import NormalEstimate
from tactex_probe.pathway import Pathway, ProbeRecord


class Phase(enum.IntEnum):
    """What the arm is doing; the values are tactex_msgs/action/Probe's PHASE_* codes."""

    MOVING = 0
    DESCENDING = 1
    MEASURING = 2
    RETRACTING = 3


class Outcome(enum.Enum):
    """How a goal ended."""

    SUCCEEDED = 'succeeded'
    ABORTED = 'aborted'
    CANCELED = 'canceled'


class Method(enum.Enum):
    """How a probe point is found and measured (see the module docstring)."""

    TIP_THEN_FACE = 'tip_then_face'
    FACE_ONLY = 'face_only'


@dataclass(frozen=True)
class ExplorerConfig:
    """Tuning of the exploration beyond the goal's parameters (SI units).

    Attributes:
        method: two passes (locate with the tip, measure with the face) or the face only.
        press_force_n: force proxy to press to before measuring (at most 75 % of the
            goal's force limit, which wins when lower).
        press_speed_m_s: speed along the tool axis while pressing.
        max_press_m: press travel after first contact before measuring anyway.
        move_speed_m_s: speed of every motion in free air.
        baseline_s: free-air hold before each touch (baseline and undeformed attitude).
        settle_s: hold after pressing before each measuring window.
        measure_s: length of a measuring window.
        refinements: touches again when the face did not lie flat.
        refine_tolerance_rad: the face lies flat when it turned less than this.
        refine_lift_m: lift off the surface between touches.
        tip_margin_rad: how far the tool leans past the predicted surface tilt when
            locating, so that its tip touches first.
        align_tool: FACE_ONLY: turn the tool to the normal extrapolated from the
            previous contacts (else it stays vertical, as in the original).
        max_tilt_rad: largest tilt of the tool from vertical.
        joint_timeout_s: abort when no joint state came for this long.
        tracking_tolerance_rad: a motion has ended once every joint is this close to its
            last goal (the next one starts from there).
        motion_timeout_s: how long after its end a motion may still be arriving; then the
            goal aborts (the arm does not follow).
        detector: the contact detector's tuning.
    """

    method: Method = Method.TIP_THEN_FACE
    press_force_n: float = 1.5
    press_speed_m_s: float = 0.004
    max_press_m: float = 0.008
    move_speed_m_s: float = 0.03
    baseline_s: float = 0.3
    settle_s: float = 0.3
    measure_s: float = 0.2
    refinements: int = 2
    refine_tolerance_rad: float = math.radians(0.5)
    refine_lift_m: float = 0.004
    tip_margin_rad: float = math.radians(30.0)
    align_tool: bool = True
    max_tilt_rad: float = math.radians(40.0)
    joint_timeout_s: float = 0.5
    tracking_tolerance_rad: float = 0.01
    motion_timeout_s: float = 2.0
    detector: DetectorConfig = field(default_factory=DetectorConfig)

    def __post_init__(self) -> None:
        """Reject settings the explorer cannot use."""
        for name in ('press_force_n', 'press_speed_m_s', 'max_press_m', 'move_speed_m_s',
                     'baseline_s', 'settle_s', 'measure_s', 'refine_lift_m', 'joint_timeout_s',
                     'tracking_tolerance_rad', 'motion_timeout_s'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f'{name} must be finite and > 0, got {value!r}')
        if isinstance(self.refinements, bool) or not isinstance(self.refinements, int) \
                or self.refinements < 0:
            raise ValueError(f'refinements must be an integer >= 0, got {self.refinements!r}')
        for name in ('refine_tolerance_rad', 'tip_margin_rad', 'max_tilt_rad'):
            value = getattr(self, name)
            if not 0.0 <= value < math.pi / 2:
                raise ValueError(f'{name} must be in [0, pi/2), got {value!r}')
        Method(self.method)


@dataclass(frozen=True)
class Command:
    """A joint path for the arm, to replace whatever it executes now."""

    path: JointPath


@dataclass(frozen=True)
class Stop:
    """Stop the arm where its driver commands it when this arrives, and hold there."""


@dataclass(frozen=True)
class Feedback:
    """Progress (tactex_msgs/action/Probe feedback)."""

    phase: Phase
    probe_index: int
    probe_count: int
    contacts_found: int
    last_record: ProbeRecord | None


@dataclass(frozen=True)
class Recorded:
    """A probe ended; its outcome."""

    record: ProbeRecord


@dataclass(frozen=True)
class Finished:
    """The goal ended; the pathway holds every probe finished so far."""

    pathway: Pathway
    outcome: Outcome
    message: str


@dataclass(frozen=True)
class Measurement:
    """How a successful probe was measured (for diagnostics and error budgets).

    Attributes:
        onset_ns: the contact's onset behind the recorded position.
        window_ns: start and end of the measuring window behind the recorded normal.
        estimate: that window's estimate.
    """

    onset_ns: int
    window_ns: tuple[int, int]
    estimate: NormalEstimate
