# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The last seconds of joint states, IMU and pressure samples, and windows averaged from them.

Streams arrive separately and at their own rates; a window joins them by stamp: the IMU
samples inside it, the arm joints interpolated to each of their stamps, the pressure
samples inside it. Non-finite samples are dropped on arrival and counted.
"""

from __future__ import annotations

from collections import deque
import math

import numpy as np

from tactex_probe.normals import mean_quaternion, SensorWindow

KEEP_S = 30.0


class SampleHistory:
    """Recent samples of the three streams, oldest first (stamps in ns)."""

    def __init__(self, keep_s: float = KEEP_S) -> None:
        self._keep_ns = int(keep_s * 1e9)
        self._joints: deque[tuple[int, np.ndarray]] = deque()
        self._imu: deque[tuple[int, np.ndarray, np.ndarray]] = deque()
        self._pressure: deque[tuple[int, float]] = deque()
        self.dropped = 0

    def add_joints(self, stamp_ns: int, positions) -> bool:
        """Add arm joints (joint1..joint4, rad); False (and counted) when not finite."""
        q = np.asarray(positions, dtype=float)
        if q.shape != (4,) or not np.all(np.isfinite(q)):
            self.dropped += 1
            return False
        self._append(self._joints, (int(stamp_ns), q))
        return True

    def add_imu(self, stamp_ns: int, accel, quaternion) -> bool:
        """Add an accel reading (m/s^2) with the filter's attitude (w, x, y, z)."""
        a = np.asarray(accel, dtype=float)
        q = np.asarray(quaternion, dtype=float)
        if a.shape != (3,) or q.shape != (4,) or not (np.all(np.isfinite(a))
                                                     and np.all(np.isfinite(q))):
            self.dropped += 1
            return False
        self._append(self._imu, (int(stamp_ns), a, q))
        return True

    def add_pressure(self, stamp_ns: int, pressure_pa: float) -> bool:
        """Add a barometer reading (Pa)."""
        if not math.isfinite(pressure_pa):
            self.dropped += 1
            return False
        self._append(self._pressure, (int(stamp_ns), float(pressure_pa)))
        return True

    def _append(self, queue: deque, item: tuple) -> None:
        if queue and item[0] < queue[-1][0]:
            self.dropped += 1  # out of order: the stream went back in time
            return
        queue.append(item)
        while queue and queue[0][0] < item[0] - self._keep_ns:
            queue.popleft()

    @property
    def latest_joints(self) -> tuple[int, np.ndarray] | None:
        """(stamp, joints) of the newest joint state, or None."""
        return self._joints[-1] if self._joints else None

    def joints_at(self, stamps_ns) -> np.ndarray:
        """Arm joints linearly interpolated to `stamps_ns` (held beyond the ends), (n, 4)."""
        stamps = np.atleast_1d(np.asarray(stamps_ns, dtype=np.int64))
        if not self._joints:
            return np.full((stamps.size, 4), np.nan)
        known = np.array([s for s, _ in self._joints], dtype=np.int64)
        values = np.array([q for _, q in self._joints])
        relative = (stamps - known[0]) * 1e-9
        grid = (known - known[0]) * 1e-9
        return np.stack([np.interp(relative, grid, values[:, j]) for j in range(4)], axis=1)

    def pressures(self, start_ns: int, end_ns: int) -> np.ndarray:
        """Pressure readings with stamps in [start_ns, end_ns]."""
        return np.array([p for s, p in self._pressure if start_ns <= s <= end_ns])

    def accels(self, start_ns: int, end_ns: int) -> list[np.ndarray]:
        """Accelerometer readings with stamps in [start_ns, end_ns]."""
        return [a for s, a, _ in self._imu if start_ns <= s <= end_ns]

    def window(self, start_ns: int, end_ns: int, compression_m: float = 0.0
               ) -> SensorWindow | None:
        """Average of the IMU samples in [start_ns, end_ns] with the joints at their stamps.

        The accel is the per-axis median, so a burst of a few wild samples cannot drag it.
        Returns None when the window holds no valid IMU sample.
        """
        inside = [(s, a, q) for s, a, q in self._imu if start_ns <= s <= end_ns]
        if not inside:
            return None
        stamps = np.array([s for s, _, _ in inside], dtype=np.int64)
        return SensorWindow(
            quaternion=mean_quaternion([q for _, _, q in inside]),
            accel=np.median([a for _, a, _ in inside], axis=0),
            joints=np.mean(self.joints_at(stamps), axis=0),
            compression_m=compression_m)
