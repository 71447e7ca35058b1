# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Simulated samples as serialised ROS messages, and sweeps written as rosbag2 (mcap).

`sample_messages` is the one builder of what the simulator emits per sample (the raw
tactile topics, joint_states and the ground truth): the bridge node publishes these
bytes and `SweepBag` records them, with rosbags' type store, so no ROS install is
needed. Besides those, a bag carries the sweep segment (`sweep/active`) and the
recording's metadata (label, trial, surface, ... as JSON on `recording/metadata`).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from rosbags.rosbag2 import StoragePlugin, Writer

from tactex_common import frames, topics
from tactex_description.geometry import JOINT_STATE_NAMES
from tactex_sensor.messages import (
    header,
    NoiseVariances,
    serialize,
    tactile_cdr,
    TACTILE_TOPICS,
    TYPESTORE,
)
from tactex_sensor.orientation import gravity_alignment
from tactex_sim.world import Sample

_T = TYPESTORE.types
FRAME = frames.SENSOR
NOISE = NoiseVariances()
JOINT_STATE_TYPE = 'sensor_msgs/msg/JointState'
POSE_TYPE = 'geometry_msgs/msg/PoseStamped'
STRING_TYPE = 'std_msgs/msg/String'
BOOL_TYPE = 'std_msgs/msg/Bool'
# Every topic a simulated sample may produce, with its type, in emission order.
SAMPLE_TOPICS = TACTILE_TOPICS + (
    (topics.JOINT_STATES, JOINT_STATE_TYPE),
    (topics.GROUND_TRUTH_CONTACT, POSE_TYPE),
    (topics.GROUND_TRUTH_SENSOR, POSE_TYPE),
    (topics.GROUND_TRUTH_TEXTURE, STRING_TYPE))


def _pose_stamped(time_ns: int, position, quaternion_wxyz):
    w, x, y, z = (float(v) for v in quaternion_wxyz)
    px, py, pz = (float(v) for v in position)
    return _T[POSE_TYPE](header=header(time_ns, frames.WORLD), pose=_T['geometry_msgs/msg/Pose'](
        position=_T['geometry_msgs/msg/Point'](x=px, y=py, z=pz),
        orientation=_T['geometry_msgs/msg/Quaternion'](x=x, y=y, z=z, w=w)))


def quaternion_z_to(normal) -> np.ndarray:
    """Quaternion (w, x, y, z) turning +z onto `normal` (the inverse of aligning it to z)."""
    n = np.asarray(normal, dtype=float)
    w, x, y, z = gravity_alignment(*(n / np.linalg.norm(n)))
    return np.array([w, -x, -y, -z])


def tactile_messages(sample: Sample, time_ns: int) -> list[tuple[str, bytes]]:
    """(topic, CDR bytes) of the raw tactile topics of one sample, stamped `time_ns`."""
    return list(zip((topic for topic, _ in TACTILE_TOPICS), tactile_cdr(
        time_ns, FRAME, sample.accel, sample.gyro, sample.mag, sample.pressure,
        sample.temperature, NOISE), strict=True))


def sample_messages(sample: Sample, time_ns: int, joints: np.ndarray,
                    joint_velocities: np.ndarray, *, tactile: bool = True
                    ) -> list[tuple[str, bytes]]:
    """(topic, CDR bytes) of everything one simulated sample emits, stamped `time_ns`.

    The contact ground truth is emitted only while the sensor touches the surface;
    `tactile=False` leaves out the tactile topics (the bridge plays faults on them).
    """
    emitted = tactile_messages(sample, time_ns) if tactile else []
    emitted.append((topics.JOINT_STATES, serialize(_T[JOINT_STATE_TYPE](
        header=header(time_ns, ''), name=list(JOINT_STATE_NAMES),
        position=np.asarray(joints, dtype=float),
        velocity=np.asarray(joint_velocities, dtype=float), effort=np.zeros(0)),
        JOINT_STATE_TYPE)))
    truth = sample.truth
    if truth.contact.touching:
        emitted.append((topics.GROUND_TRUTH_CONTACT, serialize(_pose_stamped(
            time_ns, truth.contact.point, quaternion_z_to(truth.contact.normal)), POSE_TYPE)))
    emitted.append((topics.GROUND_TRUTH_SENSOR, serialize(_pose_stamped(
        time_ns, truth.edge_position, truth.sensor_quaternion), POSE_TYPE)))
    emitted.append((topics.GROUND_TRUTH_TEXTURE,
                    serialize(_T[STRING_TYPE](data=truth.texture), STRING_TYPE)))
    return emitted


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
        for topic, msgtype in ((topics.RECORDING_METADATA, STRING_TYPE),
                               (topics.SWEEP_ACTIVE, BOOL_TYPE), *SAMPLE_TOPICS):
            self._connections[topic] = self._writer.add_connection(
                f'/{topic}', msgtype, typestore=TYPESTORE)
        self._write(topics.RECORDING_METADATA, self._offset, serialize(
            _T[STRING_TYPE](data=json.dumps(self._metadata, sort_keys=True)), STRING_TYPE))
        return self

    def __exit__(self, *exc_info) -> None:
        self._writer.close()

    def _write(self, topic: str, time_ns: int, data: bytes) -> None:
        self._writer.write(self._connections[topic], time_ns, data)

    def add(self, sample: Sample, joints: np.ndarray, joint_velocities: np.ndarray,
            sliding: bool) -> None:
        """Write one sensor sample, the joint state and the ground truth at its time."""
        t = self._offset + int(round(sample.time_s * 1e9))
        if sliding != self._active:
            self._active = sliding
            self._write(topics.SWEEP_ACTIVE, t, serialize(_T[BOOL_TYPE](data=sliding),
                                                          BOOL_TYPE))
        for topic, data in sample_messages(sample, t, joints, joint_velocities):
            self._write(topic, t, data)
