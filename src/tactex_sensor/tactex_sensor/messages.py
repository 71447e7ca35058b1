# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The four raw tactile messages of one sample, as the sensor node and the simulator send them."""

from __future__ import annotations

from dataclasses import dataclass

from sensor_msgs.msg import FluidPressure, Imu, MagneticField, Temperature


@dataclass(frozen=True)
class NoiseVariances:
    """Diagonal covariances of the channels (REP-145), defaults for the LSM9DS0 + MPL115A2."""

    accel: float = 4e-4  # (m/s^2)^2
    gyro: float = 4e-6  # (rad/s)^2
    mag: float = 4e-14  # T^2
    pressure: float = 4.0  # Pa^2
    temperature: float = 0.25  # degC^2


def _diagonal(variance: float) -> list[float]:
    return [variance, 0.0, 0.0, 0.0, variance, 0.0, 0.0, 0.0, variance]


def tactile_messages(stamp, frame_id: str, accel, gyro, mag, pressure_pa: float,
                     temperature_c: float, noise: NoiseVariances = NoiseVariances()
                     ) -> tuple[Imu, MagneticField, FluidPressure, Temperature]:
    """Raw IMU (no orientation), magnetic field, pressure and temperature of one sample."""
    imu = Imu()
    imu.header.stamp, imu.header.frame_id = stamp, frame_id
    imu.orientation_covariance[0] = -1.0  # REP-145: raw data carries no orientation
    w, a = imu.angular_velocity, imu.linear_acceleration
    w.x, w.y, w.z = (float(v) for v in gyro)
    a.x, a.y, a.z = (float(v) for v in accel)
    imu.angular_velocity_covariance = _diagonal(noise.gyro)
    imu.linear_acceleration_covariance = _diagonal(noise.accel)
    field = MagneticField(header=imu.header, magnetic_field_covariance=_diagonal(noise.mag))
    m = field.magnetic_field
    m.x, m.y, m.z = (float(v) for v in mag)
    return (imu, field,
            FluidPressure(header=imu.header, fluid_pressure=float(pressure_pa),
                          variance=noise.pressure),
            Temperature(header=imu.header, temperature=float(temperature_c),
                        variance=noise.temperature))
