# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Madgwick orientation filter (IMU and MARG) that bad input cannot poison.

One scalar kernel, `_step`, holds the algorithm. `MadgwickFilter` calls it as plain
Python sample by sample; `filter_batch` runs the same function compiled by numba over a
whole recording, so the two agree to rounding.

Each step first rotates the attitude exactly (cos and sin of the half angle) by the
bias-corrected gyro over dt, then corrects it towards the measurements of that same
instant: tilt by Madgwick's normalised gravity gradient (gain beta), limited to half the
error per step so a high gain cannot chatter, and heading only by the magnetometer (a
turn about world up towards magnetic north), so accel disturbances and nearby magnets
stay out of each other's axes. The gain starts high and ramps down (fast convergence
from any attitude); the first valid sample sets the attitude; the gyro bias integrates
the direction errors (their sines, so zero-mean texture vibration averages out, where
Madgwick's zeta term would integrate a unit vector of noise).

Every input is checked, and a rejected one is flagged (and counted by the streaming
filter): a gyro axis beyond `max_rate_rad_s` (default: the LSM9DS0's widest range, so
only a corrupted frame gets there) or non-finite skips the prediction; an accel axis
beyond `max_accel_m_s2`, a non-finite accel or one weaker than `min_accel_m_s2` (free
fall, a dead chip: its direction is noise) skips the correction; an invalid
magnetometer or one nearly parallel to gravity leaves heading alone; dt <= 0, a
non-finite dt or a gap longer than `max_dt_s` never integrates the gyro over it.
Readings are scaled by their largest axis before they are normalised, so neither
float32-max nor subnormal values overflow or lose their direction. A rejected sample
leaves the attitude where it was. Whatever state bad input left behind (in-range garbage
can turn the attitude anywhere), a tilt disagreeing with the accel by more than
`recovery_angle_rad` for `recovery_s` restarts the gain ramp, so the filter is back
within 1 degree of a resting sensor's tilt 6 s after bad input stops
(tests/tactex_sensor/test_madgwick_hard.py checks it).

Internally the world frame is north-west-up; the MARG output is turned into ENU (x east,
y north, z up; REP-145). With the IMU only, heading is free and the first sample defines
yaw 0.
"""

from __future__ import annotations

from dataclasses import dataclass
import math
import sys

import numba
import numpy as np

from tactex_common import chips
from tactex_common.constants import STANDARD_GRAVITY_M_S2
from tactex_sensor.errors import ReadingError
from tactex_sensor.orientation import gravity_alignment, unit_direction

# Flags returned by the kernel: which parts of the update ran, and what was rejected.
USED_GYRO = 1
USED_ACCEL = 2
USED_MAG = 4
INITIALISED = 8
REJECTED_GYRO = 16
REJECTED_ACCEL = 32
REJECTED_DT = 64
RESTARTED = 128

_SQRT_HALF = math.sqrt(0.5)
_FLOAT_MAX = sys.float_info.max
# Heading errors above this are corrected at the full rate, smaller ones in proportion.
HEADING_SATURATION_RAD = math.radians(2.0)


@dataclass(frozen=True)
class MadgwickConfig:
    """Tuning of the filter.

    Attributes:
        gain: beta (rad/s), weight of the accel/mag correction after start-up; the one
            default of the library, the node and config/sensor.yaml (bench/bench_madgwick.py
            compares it with gains tuned on a seed it does not score).
        initial_gain: beta at start-up, ramping linearly down to `gain`.
        ramp_s: duration of the start-up ramp (s).
        bias_gain: integral gain (1/s) from direction error to gyro bias; 0 turns it off.
        max_bias: largest gyro bias the filter will learn (rad/s).
        use_mag: fuse the magnetometer (MARG) when it is valid.
        min_dip_sin: a magnetometer within asin(min_dip_sin) of gravity is ignored.
        max_dt_s: a longer step is a gap: no gyro integration over it.
        max_rate_rad_s: a gyro axis reading more is a corrupted sample: rejected.
        max_accel_m_s2: an accel axis reading more is a corrupted sample: rejected.
        min_accel_m_s2: a weaker accel (free fall, zero, subnormal) tells no direction:
            rejected.
        recovery_angle_rad: a tilt disagreement between accel and attitude above this ...
        recovery_s: ... for longer than this (s) restarts the start-up ramp and forgets
            the bias (a gain of 0.04 alone would need 40 s to undo 180 deg); with the
            defaults a resting sensor's tilt is back within 1 deg 6 s after bad input.
        start_from_first_sample: take the attitude of the first valid accel (+mag)
            sample; False starts from identity and lets the start-up ramp converge.
    """

    gain: float = 0.04
    initial_gain: float = 2.5
    ramp_s: float = 1.0
    bias_gain: float = 1.0
    max_bias: float = 0.1
    use_mag: bool = False
    min_dip_sin: float = 0.1
    max_dt_s: float = 0.1
    # The LSM9DS0's widest full scales: no axis of a healthy chip reads more, whichever
    # range the firmware selects.
    max_rate_rad_s: float = max(r.full_scale_si for r in chips.GYRO_RANGES.values())
    max_accel_m_s2: float = max(r.full_scale_si for r in chips.ACCEL_RANGES.values())
    min_accel_m_s2: float = 0.1 * STANDARD_GRAVITY_M_S2
    recovery_angle_rad: float = math.radians(10.0)
    recovery_s: float = 1.0
    start_from_first_sample: bool = True

    def __post_init__(self) -> None:
        """Reject settings the kernel cannot use."""
        for name in ('gain', 'initial_gain', 'bias_gain', 'max_bias'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f'{name} must be finite and >= 0, got {value!r}')
        for name in ('ramp_s', 'max_dt_s', 'max_rate_rad_s', 'max_accel_m_s2',
                     'min_accel_m_s2', 'recovery_angle_rad', 'recovery_s'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'{name} must be finite and > 0, got {value!r}')
        if not 0.0 <= self.min_dip_sin < 1.0:
            raise ValueError(f'min_dip_sin must be in [0, 1), got {self.min_dip_sin!r}')

    @property
    def recovery_error_sq(self) -> float:
        """|measured - predicted gravity|^2 (unit vectors) at `recovery_angle_rad`."""
        return (2.0 * math.sin(0.5 * min(self.recovery_angle_rad, math.pi))) ** 2


@numba.njit(cache=True)
def _gains(elapsed: float, gain: float, initial_gain: float, ramp_s: float,
           bias_gain: float) -> tuple[float, float]:
    """Return (beta, zeta) at `elapsed` seconds after initialisation.

    The start-up gain holds for the first half of the ramp and falls linearly to `gain`
    over the second half; the bias is learnt only after the ramp.
    """
    if elapsed >= ramp_s:
        return gain, bias_gain
    fraction = min(1.0, 2.0 * (1.0 - elapsed / ramp_s))
    return gain + (initial_gain - gain) * fraction, 0.0


@numba.njit(cache=True)
def _initial_attitude(ux: float, uy: float, uz: float, mag_ok: bool, mx: float, my: float,
                      mz: float, min_dip_sin: float) -> tuple[float, float, float, float]:
    """Attitude (NWU) from one unit accel direction, with heading from a unit mag if usable."""
    if mag_ok:
        # West = up x m, north = west x up: rows of the body -> world matrix.
        wx, wy, wz = uy * mz - uz * my, uz * mx - ux * mz, ux * my - uy * mx
        w_norm = math.sqrt(wx * wx + wy * wy + wz * wz)
        if w_norm > min_dip_sin:
            wx, wy, wz = wx / w_norm, wy / w_norm, wz / w_norm
            nx, ny, nz = wy * uz - wz * uy, wz * ux - wx * uz, wx * uy - wy * ux
            return _matrix_to_quaternion(nx, ny, nz, wx, wy, wz, ux, uy, uz)
    return gravity_alignment(ux, uy, uz)


@numba.njit(cache=True)
def _gravity_direction(ax: float, ay: float, az: float, min_accel: float, max_accel: float
                       ) -> tuple[bool, float, float, float]:
    """(valid, unit vector) of an accel: every axis within max_accel, its norm >= min_accel."""
    valid, ux, uy, uz = unit_direction(ax, ay, az, max_accel)
    # |a| = max |a_i| / max |u_i|, with no overflow and no underflow.
    if valid and max(abs(ax), abs(ay), abs(az)) < min_accel * max(abs(ux), abs(uy), abs(uz)):
        return False, 0.0, 0.0, 0.0
    return valid, ux, uy, uz


@numba.njit(cache=True)
def _first_attitude(ax: float, ay: float, az: float, mx: float, my: float, mz: float,
                    use_mag: bool, min_dip_sin: float, min_accel: float, max_accel: float
                    ) -> tuple[bool, float, float, float, float]:
    """(found, attitude) from a sample: found when its accel is valid."""
    accel_ok, ux, uy, uz = _gravity_direction(ax, ay, az, min_accel, max_accel)
    if not accel_ok:
        return False, 1.0, 0.0, 0.0, 0.0
    mag_ok = False
    if use_mag:
        mag_ok, mx, my, mz = unit_direction(mx, my, mz, _FLOAT_MAX)
    q0, q1, q2, q3 = _initial_attitude(ux, uy, uz, mag_ok, mx, my, mz, min_dip_sin)
    return True, q0, q1, q2, q3


@numba.njit(cache=True)
def _matrix_to_quaternion(r00: float, r01: float, r02: float, r10: float, r11: float,
                          r12: float, r20: float, r21: float, r22: float
                          ) -> tuple[float, float, float, float]:
    """Quaternion of a rotation matrix given row by row (Shepperd's method)."""
    trace = r00 + r11 + r22
    if trace > 0.0:
        s = 2.0 * math.sqrt(trace + 1.0)
        return 0.25 * s, (r21 - r12) / s, (r02 - r20) / s, (r10 - r01) / s
    if r00 > r11 and r00 > r22:
        s = 2.0 * math.sqrt(1.0 + r00 - r11 - r22)
        return (r21 - r12) / s, 0.25 * s, (r01 + r10) / s, (r02 + r20) / s
    if r11 > r22:
        s = 2.0 * math.sqrt(1.0 + r11 - r00 - r22)
        return (r02 - r20) / s, (r01 + r10) / s, 0.25 * s, (r12 + r21) / s
    s = 2.0 * math.sqrt(1.0 + r22 - r00 - r11)
    return (r10 - r01) / s, (r02 + r20) / s, (r12 + r21) / s, 0.25 * s


@numba.njit(cache=True)
def _step(q0: float, q1: float, q2: float, q3: float, b0: float, b1: float, b2: float,
          gx: float, gy: float, gz: float, ax: float, ay: float, az: float,
          mx: float, my: float, mz: float, dt: float, beta: float, zeta: float,
          max_bias: float, use_mag: bool, min_dip_sin: float, max_dt: float,
          max_rate: float, min_accel: float, max_accel: float, disagree_s: float,
          recovery_s: float,
          recovery_error_sq: float):
    """One filter update; returns (q0, q1, q2, q3, b0, b1, b2, disagree_s, flags).

    `disagree_s` is how long the tilt has disagreed with the accel by more than the
    recovery angle; past `recovery_s` the bias is dropped and RESTARTED flagged (the
    caller restarts the gain ramp).
    """
    flags = 0
    step_ok = dt > 0.0 and dt <= max_dt  # False for NaN too
    if not step_ok:
        flags |= REJECTED_DT
    rate_ok = abs(gx) <= max_rate and abs(gy) <= max_rate and abs(gz) <= max_rate
    if step_ok and not rate_ok:
        flags |= REJECTED_GYRO
    gyro_ok = step_ok and rate_ok
    # Correction rate of q (from accel and mag), accumulated below.
    d0 = d1 = d2 = d3 = 0.0
    # A gap or a bad dt still lets the correction act, over one nominal step at most.
    h = dt if step_ok else max_dt
    if gyro_ok:
        # Predict: exact rotation by the bias-corrected rate over dt (q * exp(w dt / 2)),
        # at any rate. The correction below then compares the measurements with the
        # attitude of their own instant.
        flags |= USED_GYRO
        wx, wy, wz = gx - b0, gy - b1, gz - b2
        rate = math.sqrt(wx * wx + wy * wy + wz * wz)
        half_angle = 0.5 * rate * h
        c = math.cos(half_angle)
        # sin(half angle) / rate, which tends to h / 2 (exactly, in doubles, below 1e-8).
        k = math.sin(half_angle) / rate if half_angle > 1e-8 else 0.5 * h
        rx, ry, rz = wx * k, wy * k, wz * k
        q0, q1, q2, q3 = (q0 * c - q1 * rx - q2 * ry - q3 * rz,
                          q0 * rx + q1 * c + q2 * rz - q3 * ry,
                          q0 * ry - q1 * rz + q2 * c + q3 * rx,
                          q0 * rz + q1 * ry - q2 * rx + q3 * c)
    accel_ok, ax, ay, az = _gravity_direction(ax, ay, az, min_accel, max_accel)
    if not accel_ok:
        flags |= REJECTED_ACCEL
    else:
        flags |= USED_ACCEL
        _2q0, _2q1, _2q2, _2q3 = 2.0 * q0, 2.0 * q1, 2.0 * q2, 2.0 * q3
        q0q0, q1q1, q2q2, q3q3 = q0 * q0, q1 * q1, q2 * q2, q3 * q3
        f0 = _2q1 * q3 - _2q0 * q2 - ax
        f1 = _2q0 * q1 + _2q2 * q3 - ay
        f2 = 1.0 - 2.0 * (q1q1 + q2q2) - az
        # Gradient J_g^T f_g of the gravity objective.
        s0 = _2q1 * f1 - _2q2 * f0
        s1 = _2q3 * f0 + _2q0 * f1 - 2.0 * _2q1 * f2
        s2 = _2q3 * f1 - _2q0 * f0 - 2.0 * _2q2 * f2
        s3 = _2q1 * f0 + _2q2 * f1
        s_sq = s0 * s0 + s1 * s1 + s2 * s2 + s3 * s3
        error_sq = f0 * f0 + f1 * f1 + f2 * f2
        disagree_s = disagree_s + h if error_sq > recovery_error_sq else 0.0
        if s_sq > 1e-24:
            # A unit step of beta * h would overshoot an error smaller than the step
            # and chatter (1.2 deg per sample at the start-up gain and 120 Hz): never
            # move q by more than half the tilt error (|f| ~ the angle) in one step.
            step = min(beta, 0.5 * math.sqrt(error_sq) / h)
            s_inv = step / math.sqrt(s_sq)
            d0 -= s0 * s_inv
            d1 -= s1 * s_inv
            d2 -= s2 * s_inv
            d3 -= s3 * s_inv
        heading_error = 0.0
        mag_ok = False
        if use_mag:
            mag_ok, mx, my, mz = unit_direction(mx, my, mz, _FLOAT_MAX)
        if mag_ok:
            cx, cy, cz = ay * mz - az * my, az * mx - ax * mz, ax * my - ay * mx
            if cx * cx + cy * cy + cz * cz > min_dip_sin * min_dip_sin:
                flags |= USED_MAG
                # The magnetometer corrects heading only, so an accel disturbance cannot
                # tilt through it, nor a magnet tilt the sensor: the field in the world
                # frame must point north (+x of north-west-up); turn about up to get there.
                hx = (mx * (q0q0 + q1q1 - q2q2 - q3q3) + 2.0 * my * (q1 * q2 - q0 * q3)
                      + 2.0 * mz * (q1 * q3 + q0 * q2))
                hy = (2.0 * mx * (q1 * q2 + q0 * q3) + my * (q0q0 - q1q1 + q2q2 - q3q3)
                      + 2.0 * mz * (q2 * q3 - q0 * q1))
                heading_error = math.atan2(hy, hx)
                # Same pace as the tilt, proportional below the saturation, and never
                # past the error in one step (q turns by twice half_rate * h).
                size = abs(heading_error)
                half_rate = -math.copysign(
                    min(beta * min(1.0, size / HEADING_SATURATION_RAD), 0.5 * size / h),
                    heading_error)
                d0 -= half_rate * q3
                d1 -= half_rate * q2
                d2 += half_rate * q1
                d3 += half_rate * q0
        if gyro_ok and zeta > 0.0:
            # Integral of the direction errors into the gyro bias, bounded. Tilt error:
            # measured x predicted gravity (its sine, so zero-mean vibration averages
            # out, unlike the unit gradient of Madgwick's zeta term); heading error:
            # about world up, which the body sees along the predicted gravity f + a.
            k = zeta * h
            b0 += k * (heading_error * (f0 + ax) - (ay * f2 - az * f1))
            b1 += k * (heading_error * (f1 + ay) - (az * f0 - ax * f2))
            b2 += k * (heading_error * (f2 + az) - (ax * f1 - ay * f0))
            if b0 * b0 + b1 * b1 + b2 * b2 > max_bias * max_bias:
                k = max_bias / math.sqrt(b0 * b0 + b1 * b1 + b2 * b2)
                b0, b1, b2 = b0 * k, b1 * k, b2 * k
        if disagree_s > recovery_s:
            flags |= RESTARTED
            disagree_s, b0, b1, b2 = 0.0, 0.0, 0.0, 0.0
    q0, q1, q2, q3 = q0 + d0 * h, q1 + d1 * h, q2 + d2 * h, q3 + d3 * h
    q_inv = 1.0 / math.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
    return q0 * q_inv, q1 * q_inv, q2 * q_inv, q3 * q_inv, b0, b1, b2, disagree_s, flags




# The streaming filter runs the kernels as plain Python: cheaper than a numba call
# per sample. The batch loop runs the compiled versions.
_step_py = _step.py_func
_gains_py = _gains.py_func
_first_attitude_py = _first_attitude.py_func
# What each rejection flag counts in `MadgwickFilter.rejected`.
_REJECTIONS = {'gyro': REJECTED_GYRO, 'accel': REJECTED_ACCEL, 'dt': REJECTED_DT}


def _to_enu(q0: float, q1: float, q2: float, q3: float) -> tuple[float, float, float, float]:
    """Turn a north-west-up attitude into east-north-up (rotate the world by +90 deg)."""
    c = _SQRT_HALF
    return c * q0 - c * q3, c * q1 - c * q2, c * q2 + c * q1, c * q3 + c * q0


class MadgwickFilter:
    """Streaming filter: feed samples with `update`, read `quaternion` (w, x, y, z)."""

    def __init__(self, config: MadgwickConfig = MadgwickConfig()) -> None:
        self.config = config
        self.reset()

    def reset(self) -> None:
        """Forget the attitude, bias, start-up ramp and rejection counts.

        `rejected` counts the samples whose gyro (beyond `max_rate_rad_s` or not finite),
        accel (beyond `max_accel_m_s2`, below `min_accel_m_s2` or not finite) or dt (<= 0,
        not finite or a gap) the filter refused since the reset; `restarts` how often a lasting
        disagreement with the accel restarted the gain ramp.
        """
        self._q = (1.0, 0.0, 0.0, 0.0)
        self._bias = (0.0, 0.0, 0.0)
        self._elapsed = 0.0
        self._disagree_s = 0.0
        self.initialised = not self.config.start_from_first_sample
        self.last_flags = 0
        self.rejected = dict.fromkeys(_REJECTIONS, 0)
        self.restarts = 0

    @property
    def quaternion(self) -> np.ndarray:
        """Attitude of the sensor in the world frame (ENU with the mag), (w, x, y, z)."""
        q = _to_enu(*self._q) if self.config.use_mag else self._q
        return np.array(q)

    @property
    def gyro_bias(self) -> np.ndarray:
        """Learnt gyro bias (rad/s)."""
        return np.array(self._bias)

    def update(self, gyro, accel, dt_s: float, mag=None) -> None:
        """Fuse one sample; read the result from `quaternion`.

        Args:
            gyro: angular rate (rad/s), sensor frame.
            accel: specific force (m/s^2), sensor frame.
            dt_s: time since the previous sample (s).
            mag: magnetic field (any unit), sensor frame, or None.
        """
        config = self.config
        gx, gy, gz = gyro
        ax, ay, az = accel
        mx, my, mz = (math.nan, math.nan, math.nan) if mag is None else mag
        if not self.initialised:
            found, *q = _first_attitude_py(ax, ay, az, mx, my, mz, config.use_mag,
                                           config.min_dip_sin, config.min_accel_m_s2,
                                           config.max_accel_m_s2)
            if found:
                self._q = tuple(q)
                self.initialised = True
                self.last_flags = INITIALISED
            else:
                self.last_flags = REJECTED_ACCEL
                self.rejected['accel'] += 1
            return
        beta, zeta = _gains_py(self._elapsed, config.gain, config.initial_gain, config.ramp_s,
                               config.bias_gain)
        *q, b0, b1, b2, self._disagree_s, flags = _step_py(
            *self._q, *self._bias, gx, gy, gz, ax, ay, az, mx, my, mz, dt_s, beta, zeta,
            config.max_bias, config.use_mag, config.min_dip_sin, config.max_dt_s,
            config.max_rate_rad_s, config.min_accel_m_s2, config.max_accel_m_s2,
            self._disagree_s,
            config.recovery_s, config.recovery_error_sq)
        self._q = tuple(q)
        self._bias = (b0, b1, b2)
        if flags & RESTARTED:
            self._elapsed = 0.0
            self.restarts += 1
        elif not flags & REJECTED_DT:
            self._elapsed += dt_s
        self.last_flags = flags
        for name, flag in _REJECTIONS.items():
            if flags & flag:
                self.rejected[name] += 1


@numba.njit(cache=True)
def _run_batch(gyro, accel, mag, dt, gain, initial_gain, ramp_s, bias_gain, max_bias,
               use_mag, min_dip_sin, max_dt, max_rate, min_accel, max_accel, recovery_s,
               recovery_error_sq, initialised):
    n = gyro.shape[0]
    out = np.empty((n, 4))
    flags = np.zeros(n, dtype=np.int64)
    q0, q1, q2, q3 = 1.0, 0.0, 0.0, 0.0
    b0 = b1 = b2 = 0.0
    elapsed = disagree_s = 0.0
    for i in range(n):
        ax, ay, az = accel[i, 0], accel[i, 1], accel[i, 2]
        if not initialised:
            found, p0, p1, p2, p3 = _first_attitude(ax, ay, az, mag[i, 0], mag[i, 1],
                                                    mag[i, 2], use_mag, min_dip_sin, min_accel,
                                                    max_accel)
            if found:
                q0, q1, q2, q3 = p0, p1, p2, p3
                initialised = True
                flags[i] = INITIALISED
            else:
                flags[i] = REJECTED_ACCEL
        else:
            beta, zeta = _gains(elapsed, gain, initial_gain, ramp_s, bias_gain)
            q0, q1, q2, q3, b0, b1, b2, disagree_s, flags[i] = _step(
                q0, q1, q2, q3, b0, b1, b2, gyro[i, 0], gyro[i, 1], gyro[i, 2], ax, ay, az,
                mag[i, 0], mag[i, 1], mag[i, 2], dt[i], beta, zeta, max_bias, use_mag,
                min_dip_sin, max_dt, max_rate, min_accel, max_accel, disagree_s, recovery_s,
                recovery_error_sq)
            if flags[i] & RESTARTED:
                elapsed = 0.0
            elif not flags[i] & REJECTED_DT:
                elapsed += dt[i]
        out[i, 0], out[i, 1], out[i, 2], out[i, 3] = q0, q1, q2, q3
    return out, flags


def filter_batch(gyro, accel, dt_s, mag=None, config: MadgwickConfig = MadgwickConfig(), *,
                 return_flags: bool = False):
    """Run the filter over a whole recording; same result as `MadgwickFilter.update` per row.

    Args:
        gyro: (n, 3) angular rates (rad/s).
        accel: (n, 3) specific forces (m/s^2).
        dt_s: (n,) time since the previous sample (s); the first entry is unused.
        mag: (n, 3) array or None.
        config: the filter settings.
        return_flags: also return each sample's flags (USED_*, REJECTED_*, INITIALISED).

    Returns:
        (n, 4) attitudes (w, x, y, z) after each sample, and with `return_flags` the
        (n,) int flags.

    Raises:
        ReadingError: an array of the wrong shape (a ValueError).
    """
    gyro = np.ascontiguousarray(gyro, dtype=np.float64)
    accel = np.ascontiguousarray(accel, dtype=np.float64)
    n = gyro.shape[0]
    dt = np.ascontiguousarray(np.broadcast_to(np.asarray(dt_s, dtype=np.float64), (n,)))
    mag = np.full((n, 3), np.nan) if mag is None else np.ascontiguousarray(mag, np.float64)
    for name, array in (('gyro', gyro), ('accel', accel), ('mag', mag)):
        if array.shape != (n, 3):
            raise ReadingError(f'{name} must have shape ({n}, 3), got {array.shape!r}')
    out, flags = _run_batch(gyro, accel, mag, dt, config.gain, config.initial_gain,
                            config.ramp_s, config.bias_gain, config.max_bias, config.use_mag,
                            config.min_dip_sin, config.max_dt_s, config.max_rate_rad_s,
                            config.min_accel_m_s2, config.max_accel_m_s2, config.recovery_s,
                            config.recovery_error_sq, not config.start_from_first_sample)
    if config.use_mag:
        out = np.stack(_to_enu(*out.T), axis=1)
    return (out, flags) if return_flags else out
