# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Simulated sweeps written as rosbag2 (mcap) with exactly the topics a real recording has.

Messages are built and CDR-serialised with rosbags' Kilted type store, so no ROS
install is needed. Besides the tactile topics and joint_states, a bag carries the
sweep segment (`sweep/active`), the recording's metadata (label, trial, surface, ...
as JSON on `recording/metadata`) and the simulator's ground truth.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import get_typestore, Stores

from tactex_description.geometry import JOINT_STATE_NAMES
from tactex_sensor import topics
from tactex_sensor.messages import NoiseVariances
from tactex_sensor.orientation import gravity_alignment
from tactex_sim.world import Sample

TYPESTORE = get_typestore(Stores.ROS2_KILTED)
_T = TYPESTORE.types
FRAME = 'sensor_link'
NOISE = NoiseVariances()


def _stamp(time_ns: int):
    sec, nanosec = divmod(int(time_ns), 1_000_000_000)
    return _T['builtin_interfaces/msg/Time'](sec=sec, nanosec=nanosec)


def _header(time_ns: int, frame: str):
    return _T['std_msgs/msg/Header'](stamp=_stamp(time_ns), frame_id=frame)


def _vector(values):
    x, y, z = (float(v) for v in values)
    return _T['geometry_msgs/msg/Vector3'](x=x, y=y, z=z)


def _pose(position, quaternion_wxyz):
    w, x, y, z = (float(v) for v in quaternion_wxyz)
    px, py, pz = (float(v) for v in position)
    return _T['geometry_msgs/msg/Pose'](
        position=_T['geometry_msgs/msg/Point'](x=px, y=py, z=pz),
        orientation=_T['geometry_msgs/msg/Quaternion'](x=x, y=y, z=z, w=w))


def quaternion_z_to(normal) -> np.ndarray:
    """Quaternion (w, x, y, z) turning +z onto `normal` (the inverse of aligning it to z)."""
    n = np.asarray(normal, dtype=float)
    w, x, y, z = gravity_alignment(*(n / np.linalg.norm(n)))
    return np.array([w, -x, -y, -z])


class SweepBag:
    """Write one recording; use as a context manager.

    Args:
        path: the bag directory to create (must not exist).
        metadata: label, trial, surface and anything else, written once at the start.
        time_offset_ns: added to simulated time, so recordings do not all start at 0.
    """

    def __init__(self, path: Path, metadata: dict, *, time_offset_ns: int = 0) -> None:
        self.path = Path(path)
        self._metadata = metadata
        self._offset = int(time_offset_ns)
        self._writer = Writer(self.path, version=9, storage_plugin=StoragePlugin.MCAP)
        self._connections = {}
        self._active: bool | None = None

    def __enter__(self) -> SweepBag:
        self._writer.open()
        for topic, msgtype in (
                (topics.RECORDING_METADATA, 'std_msgs/msg/String'),
                (topics.IMU_RAW, 'sensor_msgs/msg/Imu'),
                (topics.MAG, 'sensor_msgs/msg/MagneticField'),
                (topics.PRESSURE, 'sensor_msgs/msg/FluidPressure'),
                (topics.TEMPERATURE, 'sensor_msgs/msg/Temperature'),
                (topics.JOINT_STATES, 'sensor_msgs/msg/JointState'),
                (topics.SWEEP_ACTIVE, 'std_msgs/msg/Bool'),
                (topics.GROUND_TRUTH_CONTACT, 'geometry_msgs/msg/PoseStamped'),
                (topics.GROUND_TRUTH_SENSOR, 'geometry_msgs/msg/PoseStamped'),
                (topics.GROUND_TRUTH_TEXTURE, 'std_msgs/msg/String')):
            self._connections[topic] = self._writer.add_connection(
                f'/{topic}', msgtype, typestore=TYPESTORE)
        self._write(topics.RECORDING_METADATA, self._offset,
                    _T['std_msgs/msg/String'](data=json.dumps(self._metadata, sort_keys=True)))
        return self

    def __exit__(self, *exc_info) -> None:
        self._writer.close()

    def _write(self, topic: str, time_ns: int, message) -> None:
        connection = self._connections[topic]
        self._writer.write(connection, time_ns,
                           TYPESTORE.serialize_cdr(message, connection.msgtype))

    def add(self, sample: Sample, joints: np.ndarray, joint_velocities: np.ndarray,
            sliding: bool) -> None:
        """Write one sensor sample, the joint state and the ground truth at its time."""
        t = self._offset + int(round(sample.time_s * 1e9))
        header = _header(t, FRAME)
        if sliding != self._active:
            self._active = sliding
            self._write(topics.SWEEP_ACTIVE, t, _T['std_msgs/msg/Bool'](data=sliding))
        orientation_covariance = np.zeros(9)
        orientation_covariance[0] = -1.0  # REP-145: raw data carries no orientation
        self._write(topics.IMU_RAW, t, _T['sensor_msgs/msg/Imu'](
            header=header,
            orientation=_T['geometry_msgs/msg/Quaternion'](x=0.0, y=0.0, z=0.0, w=1.0),
            orientation_covariance=orientation_covariance,
            angular_velocity=_vector(sample.gyro),
            angular_velocity_covariance=np.eye(3).ravel() * NOISE.gyro,
            linear_acceleration=_vector(sample.accel),
            linear_acceleration_covariance=np.eye(3).ravel() * NOISE.accel))
        self._write(topics.MAG, t, _T['sensor_msgs/msg/MagneticField'](
            header=header, magnetic_field=_vector(sample.mag),
            magnetic_field_covariance=np.eye(3).ravel() * NOISE.mag))
        self._write(topics.PRESSURE, t, _T['sensor_msgs/msg/FluidPressure'](
            header=header, fluid_pressure=float(sample.pressure), variance=NOISE.pressure))
        self._write(topics.TEMPERATURE, t, _T['sensor_msgs/msg/Temperature'](
            header=header, temperature=float(sample.temperature), variance=NOISE.temperature))
        self._write(topics.JOINT_STATES, t, _T['sensor_msgs/msg/JointState'](
            header=_header(t, ''), name=list(JOINT_STATE_NAMES),
            position=np.asarray(joints, dtype=float),
            velocity=np.asarray(joint_velocities, dtype=float), effort=np.zeros(0)))
        truth = sample.truth
        contact = truth.contact
        if contact.touching:
            self._write(topics.GROUND_TRUTH_CONTACT, t, _T['geometry_msgs/msg/PoseStamped'](
                header=_header(t, 'world'),
                pose=_pose(contact.point, quaternion_z_to(contact.normal))))
        self._write(topics.GROUND_TRUTH_SENSOR, t, _T['geometry_msgs/msg/PoseStamped'](
            header=_header(t, 'world'), pose=_pose(truth.edge_position,
                                                   truth.sensor_quaternion)))
        self._write(topics.GROUND_TRUTH_TEXTURE, t, _T['std_msgs/msg/String'](data=truth.texture))
