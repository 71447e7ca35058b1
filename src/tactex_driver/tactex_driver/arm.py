# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What the arm should do at each control tick: hold, play a trajectory, or stay stopped.

No ROS and no bus here: the driver node feeds in measurements, commands and faults with
explicit times, and asks for the goal to send. Every goal is within the joint limits.
"""

from __future__ import annotations

from collections.abc import Sequence
import enum

import numpy as np

from tactex_driver.errors import TrajectoryRejected
from tactex_driver.playback import hold, JointLimits, plan, Trajectory, trajectory_arrays


class Mode(enum.Enum):
    """The controller's state."""

    HOLDING = 'holding'
    EXECUTING = 'executing'
    FAULT = 'fault'  # a servo reported a hardware error: no motion until reset
    TORQUE_OFF = 'torque off'


class ArmController:
    """Trajectory playback with hold, stop, fault and torque states.

    Args:
        limits: the joint limits every goal obeys.
        start_tolerance: how far a trajectory's first point may be from the state.
    """

    def __init__(self, limits: JointLimits, *, start_tolerance: float = 0.1) -> None:
        self.limits = limits
        self.start_tolerance = start_tolerance
        self.mode = Mode.TORQUE_OFF
        self.measured: np.ndarray | None = None
        self.fault_reason = ''
        self.last_event = ''
        self.rejected = 0
        self._trajectory: Trajectory | None = None
        self._start_s = 0.0
        self._last_goal: np.ndarray | None = None

    def update_measured(self, positions: Sequence[float]) -> None:
        """Record the present joint positions."""
        self.measured = np.asarray(positions, dtype=float)

    def torque_on(self, now_s: float) -> None:
        """Torque was enabled: hold where the arm is."""
        if self.mode is Mode.FAULT:
            raise TrajectoryRejected(f'in fault ({self.fault_reason}); reset first')
        self._hold_measured(now_s)

    def torque_off(self) -> None:
        """Torque was disabled: no goals are sent."""
        self.mode = Mode.TORQUE_OFF
        self._trajectory = None

    def execute(self, joint_names, times_s, positions, velocities, now_s: float) -> float:
        """Replace whatever runs by a new trajectory; return its duration (s).

        Raises:
            TrajectoryRejected: the trajectory is unsafe, or the arm cannot move now; what
                ran before stops and holds, and `rejected` counts it.
        """
        try:
            trajectory = self._plan(joint_names, times_s, positions, velocities)
        except TrajectoryRejected as err:
            self.reject(str(err), now_s)
            raise
        self._trajectory, self._start_s = trajectory, now_s
        self.mode = Mode.EXECUTING
        self.last_event = f'executing a {trajectory.duration_s:.2f} s trajectory'
        return trajectory.duration_s

    def execute_message(self, message, now_s: float) -> tuple[bool, str]:
        """Execute a JointTrajectory message; return (accepted, a line for the log).

        A message without points stops the arm where it is commanded now (`stop`), as an
        empty trajectory stops ROS's joint_trajectory_controller: a sender that cannot
        know where a moving arm is commanded when its message arrives stops it this way.
        """
        if not message.points:
            self.stop(now_s, 'an empty trajectory asked to stop')
            return True, 'stopping: an empty trajectory (holding where commanded now)'
        try:
            arrays = trajectory_arrays(message)
            duration = self.execute(arrays.joint_names, arrays.times_s, arrays.positions,
                                    arrays.velocities, now_s)
        except TrajectoryRejected as err:
            return False, f'trajectory rejected: {err}'
        return True, f'executing {len(arrays.times_s)} points over {duration:.2f} s'

    def reject(self, reason: str, now_s: float | None = None) -> None:
        """Count a refused command and record why; what ran before it stops and holds.

        A refused command still stops the running motion (the sender wanted a change);
        without `now_s` (the arm cannot be commanded at all) only the count and reason change.
        """
        self.rejected += 1
        if now_s is not None:
            self.stop(now_s, 'new trajectory was rejected')
        self.last_event = f'rejected trajectory: {reason}'

    def _plan(self, joint_names, times_s, positions, velocities) -> Trajectory:
        if self.mode is Mode.FAULT:
            raise TrajectoryRejected(f'in fault ({self.fault_reason}); reset first')
        if self.mode is Mode.TORQUE_OFF:
            raise TrajectoryRejected('torque is off; enable it with arm/torque')
        if self.measured is None:
            raise TrajectoryRejected('no joint state read yet')
        # Start from where the arm is commanded to be, so a replacement is smooth.
        start = self._last_goal if self._last_goal is not None else self.measured
        return plan(joint_names, times_s, positions, velocities, start, self.limits,
                    start_tolerance=self.start_tolerance)

    def stop(self, now_s: float, reason: str = 'stop requested') -> None:
        """Stop where the arm is commanded now and hold there."""
        if self.mode is Mode.EXECUTING:
            goal = self.goal(now_s)
            self._trajectory = hold(goal, self.limits)
            self.mode = Mode.HOLDING
            self.last_event = f'stopped: {reason}'

    def fault(self, reason: str) -> None:
        """A hardware error: abandon the trajectory and send nothing until `reset`."""
        self.mode = Mode.FAULT
        self.fault_reason = reason
        self._trajectory = None
        self.last_event = f'fault: {reason}'

    def reset(self) -> None:
        """Leave the fault state, with torque off (the servos were rebooted)."""
        self.fault_reason = ''
        self.mode = Mode.TORQUE_OFF
        self.last_event = 'fault cleared; enable torque to move'

    def goal(self, now_s: float) -> np.ndarray | None:
        """Positions to command now, or None when nothing may be sent."""
        if self.mode in (Mode.FAULT, Mode.TORQUE_OFF) or self._trajectory is None:
            return None
        elapsed = now_s - self._start_s
        goal = self._trajectory.sample(elapsed)
        if self.mode is Mode.EXECUTING and elapsed >= self._trajectory.duration_s:
            self.mode = Mode.HOLDING
            self.last_event = 'trajectory finished'
        self._last_goal = goal
        return goal

    def _hold_measured(self, now_s: float) -> None:
        if self.measured is None:
            raise TrajectoryRejected('no joint state read yet')
        self._trajectory = hold(self.measured, self.limits)
        self._start_s = now_s
        self._last_goal = self._trajectory.sample(0.0)
        self.mode = Mode.HOLDING
