# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Joint units (joint1..4 in rad, gripper in m) to servo angles and back."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# XM430-W350: stall torque 4.1 N m at 2.3 A (12 V); used to report effort from current.
NEWTON_METRE_PER_AMPERE = 4.1 / 2.3


@dataclass(frozen=True)
class JointMap:
    """The last joint is the gripper: its travel is `gripper_m_per_rad` of servo angle."""

    gripper_m_per_rad: float = 0.015

    def __post_init__(self) -> None:
        """Reject a zero or negative gripper ratio."""
        if not self.gripper_m_per_rad > 0:
            raise ValueError(f'gripper_m_per_rad must be > 0, got {self.gripper_m_per_rad!r}')

    def _scale(self, count: int) -> np.ndarray:
        scale = np.ones(count)
        scale[-1] = self.gripper_m_per_rad
        return scale

    def to_servo(self, joint_values) -> np.ndarray:
        """Joint positions or velocities -> servo rad or rad/s."""
        values = np.asarray(joint_values, dtype=float)
        return values / self._scale(values.size)

    def to_joint(self, servo_values) -> np.ndarray:
        """Servo rad or rad/s -> joint positions or velocities."""
        values = np.asarray(servo_values, dtype=float)
        return values * self._scale(values.size)

    def to_joint_effort(self, servo_torques) -> np.ndarray:
        """Servo torques (N m) -> joint efforts: N m, and N for the prismatic gripper.

        The gripper turns torque into force at its travel per radian (power balance:
        torque x rate = force x speed).
        """
        values = np.asarray(servo_torques, dtype=float)
        return values / self._scale(values.size)
