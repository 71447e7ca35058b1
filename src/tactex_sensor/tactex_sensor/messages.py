# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The four raw tactile messages of one sample, serialised (CDR) without a ROS install.

One builder for everyone who emits a tactile sample: the sensor node and the simulator
bridge publish these bytes as they are (rclpy publishes serialised messages), and the
simulator's bag writer records them. Messages are built with rosbags' type store
(`tactex_common.interfaces`: the standard types and tactex_msgs).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tactex_common import topics
from tactex_common.interfaces import typestore

TYPESTORE = typestore()  # the Kilted types and tactex_msgs
_T = TYPESTORE.types
IMU_TYPE = 'sensor_msgs/msg/Imu'
MAG_TYPE = 'sensor_msgs/msg/MagneticField'
PRESSURE_TYPE = 'sensor_msgs/msg/FluidPressure'
TEMPERATURE_TYPE = 'sensor_msgs/msg/Temperature'
# (topic, message type) of the four raw messages, in the order tactile_cdr returns them.
TACTILE_TOPICS = ((topics.IMU_RAW, IMU_TYPE), (topics.MAG, MAG_TYPE),
                  (topics.PRESSURE, PRESSURE_TYPE), (topics.TEMPERATURE, TEMPERATURE_TYPE))


@dataclass(frozen=True)
class NoiseVariances:
    """Diagonal covariances of the channels (REP-145), defaults for the LSM9DS0 + MPL115A2.

    Gyro: the datasheet's rate noise density behind the 100 Hz cut-off; pressure: one
    10-bit code of noise plus its rounding (tactex_common.chips); accelerometer (2 mg),
    magnetometer and temperature: assumptions, the datasheets state no noise for them.
    """

    accel: float = 4e-4  # (m/s^2)^2
    gyro: float = 4.3e-5  # (rad/s)^2
    mag: float = 4e-14  # T^2
    pressure: float = 4.4e3  # Pa^2
    temperature: float = 0.25  # degC^2


_NO_ORIENTATION = np.zeros(9)
_NO_ORIENTATION[0] = -1.0  # REP-145: raw data carries no orientation


def header(stamp_ns: int, frame_id: str):
    """A std_msgs/Header of the type store."""
    sec, nanosec = divmod(int(stamp_ns), 1_000_000_000)
    return _T['std_msgs/msg/Header'](
        stamp=_T['builtin_interfaces/msg/Time'](sec=sec, nanosec=nanosec), frame_id=frame_id)


def vector3(values):
    """A geometry_msgs/Vector3 of the type store."""
    x, y, z = (float(v) for v in values)
    return _T['geometry_msgs/msg/Vector3'](x=x, y=y, z=z)


def tactile_cdr(stamp_ns: int, frame_id: str, accel, gyro, mag, pressure_pa: float,
                temperature_c: float, noise: NoiseVariances = NoiseVariances()
                ) -> tuple[bytes, bytes, bytes, bytes]:
    """Serialised raw IMU, magnetic field, pressure and temperature of one sample.

    Args:
        stamp_ns: the sample's stamp (ns).
        frame_id: the frame of the sample (`sensor_link`).
        accel: acceleration (m/s^2), three values in the sensor frame.
        gyro: angular rate (rad/s), three values in the sensor frame.
        mag: magnetic field (T), three values in the sensor frame.
        pressure_pa: barometer (Pa).
        temperature_c: the barometer's temperature (degC).
        noise: the diagonal covariances the messages carry.
    """
    stamped = header(stamp_ns, frame_id)
    imu = _T[IMU_TYPE](
        header=stamped,
        orientation=_T['geometry_msgs/msg/Quaternion'](x=0.0, y=0.0, z=0.0, w=1.0),
        orientation_covariance=_NO_ORIENTATION,
        angular_velocity=vector3(gyro),
        angular_velocity_covariance=_diagonal(noise.gyro),
        linear_acceleration=vector3(accel),
        linear_acceleration_covariance=_diagonal(noise.accel))
    field = _T[MAG_TYPE](header=stamped, magnetic_field=vector3(mag),
                         magnetic_field_covariance=_diagonal(noise.mag))
    pressure = _T[PRESSURE_TYPE](header=stamped, fluid_pressure=float(pressure_pa),
                                 variance=float(noise.pressure))
    temperature = _T[TEMPERATURE_TYPE](header=stamped, temperature=float(temperature_c),
                                       variance=float(noise.temperature))
    return (serialize(imu, IMU_TYPE), serialize(field, MAG_TYPE),
            serialize(pressure, PRESSURE_TYPE), serialize(temperature, TEMPERATURE_TYPE))


def serialize(message, msgtype: str) -> bytes:
    """CDR bytes of a type-store message, as rclpy publishes and rosbag2 stores them."""
    return bytes(TYPESTORE.serialize_cdr(message, msgtype))


def _diagonal(variance: float) -> np.ndarray:
    return np.eye(3).ravel() * float(variance)
