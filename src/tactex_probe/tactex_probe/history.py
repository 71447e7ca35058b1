# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The last seconds of joint states, IMU and pressure samples, and windows averaged from them.

Streams arrive separately and at their own rates; a window joins them by stamp: the IMU
samples inside it, the arm joints interpolated to each of their stamps, the pressure
samples inside it. A sample that arrives late is slotted in by its stamp; non-finite or
repeated samples are dropped on arrival and counted. Lookups bisect the stamps, so a
window costs what it holds, not what the history holds.
"""

from __future__ import annotations

import bisect
import math

import numpy as np

from tactex_probe.normals import mean_quaternion, SensorWindow

KEEP_S = 15.0

# How far from 1 a filter's attitude quaternion's norm may be (its rounding is far less).
UNIT_QUATERNION_TOLERANCE = 0.01


class _Stream:
    """Stamps (ns, increasing) and their values, trimmed to the last `keep_ns`."""

    def __init__(self, keep_ns: int) -> None:
        self.keep_ns = keep_ns
        self.stamps: list[int] = []
        self.values: list = []

    def add(self, stamp_ns: int, value) -> bool:
        """Insert in stamp order; False for a repeated stamp or one older than kept."""
        stamps = self.stamps
        if stamps and stamp_ns <= stamps[-1]:
            position = bisect.bisect_left(stamps, stamp_ns)
            if (position < len(stamps) and stamps[position] == stamp_ns) or \
                    stamp_ns < stamps[-1] - self.keep_ns:
                return False
            stamps.insert(position, stamp_ns)
            self.values.insert(position, value)
            return True
        stamps.append(stamp_ns)
        self.values.append(value)
        old = bisect.bisect_left(stamps, stamp_ns - self.keep_ns)
        if old > len(stamps) // 2:  # trim in bulk, now and then
            del stamps[:old]
            del self.values[:old]
        return True

    def between(self, start_ns: int, end_ns: int) -> tuple[list[int], list]:
        """Stamps and values within [start_ns, end_ns]."""
        low = bisect.bisect_left(self.stamps, start_ns)
        high = bisect.bisect_right(self.stamps, end_ns)
        return self.stamps[low:high], self.values[low:high]

    @property
    def last(self) -> int | None:
        """The newest stamp, or None."""
        return self.stamps[-1] if self.stamps else None


class SampleHistory:
    """Recent samples of the three streams (stamps in ns)."""

    def __init__(self, keep_s: float = KEEP_S) -> None:
        keep_ns = int(keep_s * 1e9)
        self._joints = _Stream(keep_ns)
        self._imu = _Stream(keep_ns)
        self._pressure = _Stream(keep_ns)
        self.dropped = 0

    def _add(self, stream: _Stream, stamp_ns: int, value) -> bool:
        if stream.add(int(stamp_ns), value):
            return True
        self.dropped += 1
        return False

    def add_joints(self, stamp_ns: int, positions) -> bool:
        """Add arm joints (joint1..joint4, rad); False (and counted) when not finite."""
        q = np.asarray(positions, dtype=float)
        if q.shape != (4,) or not np.all(np.isfinite(q)):
            self.dropped += 1
            return False
        return self._add(self._joints, stamp_ns, q)

    def add_imu(self, stamp_ns: int, accel, quaternion) -> bool:
        """Add an accel reading (m/s^2) with the filter's attitude (w, x, y, z).

        A quaternion that is not a unit one (REP-145's all-zero "no orientation", or
        garbage) is no attitude: the sample is dropped and counted, as a non-finite one is.
        """
        a = np.asarray(accel, dtype=float)
        q = np.asarray(quaternion, dtype=float)
        if a.shape != (3,) or q.shape != (4,) or not (np.all(np.isfinite(a))
                                                     and np.all(np.isfinite(q))) \
                or abs(float(np.linalg.norm(q)) - 1.0) > UNIT_QUATERNION_TOLERANCE:
            self.dropped += 1
            return False
        return self._add(self._imu, stamp_ns, (a, q))

    def add_pressure(self, stamp_ns: int, pressure_pa: float) -> bool:
        """Add a barometer reading (Pa)."""
        if not math.isfinite(pressure_pa):
            self.dropped += 1
            return False
        return self._add(self._pressure, stamp_ns, float(pressure_pa))

    def caught_up(self, stamp_ns: int) -> bool:
        """True once the IMU and the barometer have both delivered samples up to `stamp_ns`."""
        return all(stream.last is not None and stream.last >= stamp_ns
                   for stream in (self._imu, self._pressure))

    @property
    def latest_joints(self) -> tuple[int, np.ndarray] | None:
        """(stamp, joints) of the newest joint state, or None."""
        stream = self._joints
        return (stream.stamps[-1], stream.values[-1]) if stream.stamps else None

    def joints_between(self, start_ns: int, end_ns: int) -> np.ndarray:
        """The arm joints stamped within [start_ns, end_ns], (n, 4)."""
        return np.asarray(self._joints.between(start_ns, end_ns)[1], dtype=float).reshape(-1, 4)

    def joints_at(self, stamps_ns) -> np.ndarray:
        """Arm joints linearly interpolated to `stamps_ns` (held beyond the ends), (n, 4)."""
        stamps = np.atleast_1d(np.asarray(stamps_ns, dtype=np.int64))
        stream = self._joints
        if not stream.stamps:
            return np.full((stamps.size, 4), np.nan)
        # Only the joint states around the requested stamps are needed.
        low = max(bisect.bisect_left(stream.stamps, int(stamps.min())) - 1, 0)
        high = bisect.bisect_right(stream.stamps, int(stamps.max())) + 1
        known = np.asarray(stream.stamps[low:high], dtype=np.int64)
        values = np.asarray(stream.values[low:high])
        relative = (stamps - known[0]) * 1e-9
        grid = (known - known[0]) * 1e-9
        return np.stack([np.interp(relative, grid, values[:, j]) for j in range(4)], axis=1)

    def pressures(self, start_ns: int, end_ns: int) -> np.ndarray:
        """Pressure readings with stamps in [start_ns, end_ns]."""
        return np.asarray(self._pressure.between(start_ns, end_ns)[1], dtype=float)

    def accels(self, start_ns: int, end_ns: int) -> list[np.ndarray]:
        """Accelerometer readings with stamps in [start_ns, end_ns]."""
        return [a for a, _ in self._imu.between(start_ns, end_ns)[1]]

    def window(self, start_ns: int, end_ns: int, compression_m: float = 0.0
               ) -> SensorWindow | None:
        """Average of the IMU samples in [start_ns, end_ns] with the joints at their stamps.

        The accel is the per-axis median, so a burst of a few wild samples cannot drag it.
        Returns None when the window holds no valid IMU sample.
        """
        stamps, inside = self._imu.between(start_ns, end_ns)
        if not inside:
            return None
        return SensorWindow(
            quaternion=mean_quaternion([q for _, q in inside]),
            accel=np.median([a for a, _ in inside], axis=0),
            joints=np.mean(self.joints_at(stamps), axis=0),
            compression_m=compression_m)
