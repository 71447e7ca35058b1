# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Crash-safe rosbag2 recording with rosbags: serialised messages in one-second part bags.

A recording is a directory of part bags (`part_0000`, `part_0001`, ...), each a
complete mcap bag closed after `split_s` seconds, so a crash or kill loses at most the
part being written and every closed part stays readable. Messages are written as the
serialised bytes they arrived as. The recording's metadata (label, trial, surface and
anything else) is the first message of every part, on `recording/metadata`, and in the
bags' custom data.
"""

from __future__ import annotations

import json
from pathlib import Path

from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.rosbag2.writer import CompressionFormat, CompressionMode

from tactex_classify.data.sources import PART_PREFIX
from tactex_classify.errors import ClassifyError
from tactex_common import topics
from tactex_common.interfaces import typestore

TYPESTORE = typestore()  # the Kilted types and tactex_msgs
# What a recording holds: (topic, message type, QoS: 'sensor', 'command' or 'latched').
# The metadata topic carries what a sweep node publishes (label, trial, parameters); it
# updates the recorder's own metadata when a recording is converted.
RECORDED_TOPICS = (
    (topics.IMU_RAW, 'sensor_msgs/msg/Imu', 'sensor'),
    (topics.MAG, 'sensor_msgs/msg/MagneticField', 'sensor'),
    (topics.PRESSURE, 'sensor_msgs/msg/FluidPressure', 'sensor'),
    (topics.TEMPERATURE, 'sensor_msgs/msg/Temperature', 'sensor'),
    (topics.JOINT_STATES, 'sensor_msgs/msg/JointState', 'command'),
    (topics.PROBE_CONTACTS, 'geometry_msgs/msg/PoseArray', 'command'),
    (topics.SWEEP_ACTIVE, 'std_msgs/msg/Bool', 'command'),
    (topics.RECORDING_METADATA, 'std_msgs/msg/String', 'latched'),
)


class SplitRecorder:
    """Write messages into part bags under `root`; use as a context manager.

    Args:
        root: the recording directory (created; must not hold a recording yet).
        metadata: JSON-serialisable facts of the recording (label, trial, surface, ...).
        split_s: seconds of messages per part (the most a crash can lose).
        compress: zstd-compress each message.
    """

    def __init__(self, root: Path, metadata: dict, *, split_s: float = 1.0,
                 compress: bool = False) -> None:
        if not split_s > 0:
            raise ClassifyError(f'split_s must be > 0, got {split_s!r}')
        self.root = Path(root)
        if self.root.exists() and any(self.root.iterdir()):
            raise ClassifyError(f'{self.root} already holds files; choose a new directory')
        self._metadata_text = json.dumps(metadata, sort_keys=True)
        self._split_ns = int(split_s * 1e9)
        self._compress = compress
        self._types: dict[str, str] = {}
        self._writer: Writer | None = None
        self._connections: dict = {}
        self._part = -1
        self._part_start_ns = 0
        self.messages = 0

    def __enter__(self) -> SplitRecorder:
        self.root.mkdir(parents=True, exist_ok=True)
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()

    def add_topic(self, topic: str, msgtype: str) -> None:
        """Declare a topic (e.g. 'tactile/pressure', 'sensor_msgs/msg/FluidPressure')."""
        if msgtype not in TYPESTORE.types:
            raise ClassifyError(f'unknown message type {msgtype!r}')
        self._types[topic.lstrip('/')] = msgtype
        if self._writer is not None:
            self._connect(topic.lstrip('/'))

    def write(self, topic: str, time_ns: int, data: bytes) -> None:
        """Write one serialised message received at `time_ns`."""
        topic = topic.lstrip('/')
        if topic not in self._types:
            raise ClassifyError(f'topic {topic!r} was not declared with add_topic')
        if self._writer is None or time_ns - self._part_start_ns >= self._split_ns:
            self._next_part(time_ns)
        self._writer.write(self._connections[topic], int(time_ns), data)
        self.messages += 1

    @property
    def parts(self) -> int:
        """Part bags begun so far."""
        return self._part + 1

    def close(self) -> None:
        """Close the current part; safe to call twice."""
        if self._writer is not None:
            self._writer.close()
            self._writer = None

    def _next_part(self, time_ns: int) -> None:
        self.close()
        self._part += 1
        self._part_start_ns = int(time_ns)
        writer = Writer(self.root / f'{PART_PREFIX}{self._part:04d}', version=9,
                        storage_plugin=StoragePlugin.MCAP)
        if self._compress:
            writer.set_compression(CompressionMode.MESSAGE, CompressionFormat.ZSTD)
        writer.set_custom_data('tactex.metadata', self._metadata_text)
        writer.open()
        self._writer = writer
        self._connections = {}
        metadata_topic = topics.RECORDING_METADATA
        self._types.setdefault(metadata_topic, 'std_msgs/msg/String')
        for topic in self._types:
            self._connect(topic)
        message = TYPESTORE.types['std_msgs/msg/String'](data=self._metadata_text)
        writer.write(self._connections[metadata_topic], int(time_ns),
                     TYPESTORE.serialize_cdr(message, 'std_msgs/msg/String'))

    def _connect(self, topic: str) -> None:
        self._connections[topic] = self._writer.add_connection(
            f'/{topic}', self._types[topic], typestore=TYPESTORE)
