# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Recordings read from rosbag2 (rosbags, no ROS): the 10 channels aligned on the sensor clock.

A recording is one bag directory, or a directory of part bags written one after the
other (the recorder splits every second so a crash loses at most the last part). The
IMU stream is the reference: magnetometer and pressure samples are joined to each IMU
sample by header stamp (nearest within half a period). Out-of-order and duplicated
stamps are sorted out, samples with NaN in any channel are dropped and counted.
"""

from __future__ import annotations

from array import array
from dataclasses import dataclass, field
import json
from pathlib import Path

import numpy as np
from rosbags.highlevel import AnyReader

from tactex_classify.errors import BagError
from tactex_common import topics
from tactex_common.channels import CHANNELS
from tactex_common.interfaces import typestore
from tactex_common.stamps import gaps, stamp_ns

PART_PREFIX = 'part_'
_WANTED = {f'/{topics.IMU_RAW}', f'/{topics.MAG}', f'/{topics.PRESSURE}',
           f'/{topics.SWEEP_ACTIVE}', f'/{topics.RECORDING_METADATA}', f'/{topics.JOINT_STATES}'}


@dataclass
class Recording:
    """One recording's aligned samples and what was dropped on the way."""

    path: Path
    stamps_ns: np.ndarray  # (n,) int64, header stamps of the IMU samples
    values: np.ndarray  # (n, 10) float64 in CHANNELS order, SI units
    metadata: dict
    active_ns: list[tuple[int, int]] | None  # sweep/active intervals, None if no such topic
    joint_stamps_ns: np.ndarray
    joint_speed: np.ndarray  # norm of the joint velocities (rad/s) at joint_stamps_ns
    dropped: dict[str, int] = field(default_factory=dict)
    messages: int = 0

    @property
    def rate_hz(self) -> float:
        """Mean sampling rate of the aligned samples, gaps left out."""
        if self.stamps_ns.size < 2:
            return float('nan')
        steps = np.diff(self.stamps_ns)
        steady = steps[~gaps(self.stamps_ns)]  # gaps excluded, jitter averaged
        return 1e9 / float(np.mean(steady))


def is_recording(path: Path) -> bool:
    """True for a bag directory (even a truncated one) or a directory of part bags."""
    return path.is_dir() and ((path / 'metadata.yaml').is_file()
                              or any(path.glob('*.mcap')) or any(path.glob('*.db3'))
                              or any(path.glob(f'{PART_PREFIX}*/')))


def bag_parts(path: Path) -> list[Path]:
    """The bag directories of a recording: itself, or its part bags in name order.

    Raises:
        BagError: not a recording.
    """
    parts = sorted(path.glob(f'{PART_PREFIX}*/')) if path.is_dir() else []
    if parts:
        return parts
    if is_recording(path):
        return [path]
    raise BagError(f'{path}: not a rosbag2 directory nor a directory of part bags')


def read_recording(path: Path) -> Recording:
    """Read and align one recording.

    Raises:
        BagError: the bag (or every part of it) cannot be read; the message says why.
    """
    path = Path(path)
    parts = bag_parts(path)
    readable = [p for p in parts if (p / 'metadata.yaml').is_file()]
    dropped = {'unreadable_parts': len(parts) - len(readable)}
    if not readable:
        raise BagError(f'{path}: truncated or corrupt bag (no metadata.yaml)')
    # Flat arrays: 8 bytes a value however long the recording is; stamps stay int64.
    imu, mag, pressure = array('d'), array('d'), array('d')
    imu_ns, mag_ns, pressure_ns = array('q'), array('q'), array('q')
    active: list[tuple[int, bool]] = []
    joints: list[tuple[int, float]] = []
    metadata: dict = {}
    has_segments = False
    messages = 0
    try:
        # Bags without type definitions (ROS 2 Humble's) decode with the standard types
        # and tactex_msgs, read from the package's .msg files.
        with AnyReader(readable, default_typestore=typestore()) as reader:
            connections = [c for c in reader.connections if c.topic in _WANTED]
            has_segments = any(c.topic == f'/{topics.SWEEP_ACTIVE}' for c in connections)
            for connection, log_ns, raw in reader.messages(connections=connections):
                messages += 1
                message = reader.deserialize(raw, connection.msgtype)
                topic = connection.topic[1:]
                if topic == topics.IMU_RAW:
                    a, w = message.linear_acceleration, message.angular_velocity
                    imu_ns.append(stamp_ns(message.header.stamp))
                    imu.extend((a.x, a.y, a.z, w.x, w.y, w.z))
                elif topic == topics.MAG:
                    m = message.magnetic_field
                    mag_ns.append(stamp_ns(message.header.stamp))
                    mag.extend((m.x, m.y, m.z))
                elif topic == topics.PRESSURE:
                    pressure_ns.append(stamp_ns(message.header.stamp))
                    pressure.append(message.fluid_pressure)
                elif topic == topics.SWEEP_ACTIVE:
                    active.append((log_ns, bool(message.data)))
                elif topic == topics.JOINT_STATES:
                    speed = float(np.linalg.norm(message.velocity[:4])) if len(
                        message.velocity) else float('nan')
                    joints.append((stamp_ns(message.header.stamp) or log_ns, speed))
                elif topic == topics.RECORDING_METADATA:
                    metadata.update(_parse_metadata(message.data, path))
    except Exception as err:  # rosbags raises several unrelated types for a broken file
        raise BagError(f'{path}: cannot read: {type(err).__name__}: {err}') from err
    if not imu:
        raise BagError(f'{path}: no messages on /{topics.IMU_RAW}')
    stamps, values = _align(
        (np.frombuffer(imu_ns, dtype=np.int64), np.frombuffer(imu).reshape(-1, 6)),
        (np.frombuffer(mag_ns, dtype=np.int64), np.frombuffer(mag).reshape(-1, 3)),
        (np.frombuffer(pressure_ns, dtype=np.int64), np.frombuffer(pressure).reshape(-1, 1)),
        dropped)
    joint_array = np.array(joints).reshape(-1, 2)
    order = np.argsort(joint_array[:, 0], kind='stable')
    return Recording(path, stamps, values, metadata,
                     _intervals(sorted(active)) if has_segments else None,
                     joint_array[order, 0].astype(np.int64), joint_array[order, 1],
                     dropped, messages)


def _parse_metadata(text: str, path: Path) -> dict:
    try:
        value = json.loads(text)
    except json.JSONDecodeError as err:
        raise BagError(f'{path}: recording/metadata is not JSON: {err}') from None
    if not isinstance(value, dict):
        raise BagError(f'{path}: recording/metadata must be a JSON object')
    return value


Stream = tuple[np.ndarray, np.ndarray]  # (stamps_ns int64, values (n, k))


def _sorted_unique(stream: Stream, dropped: dict, name: str) -> Stream:
    """Samples sorted by stamp, duplicates of a stamp dropped (first kept), both counted."""
    stamps, values = stream
    dropped[f'{name}_out_of_order'] = int(np.sum(np.diff(stamps) < 0))
    order = np.argsort(stamps, kind='stable')
    stamps, values = stamps[order], values[order]
    keep = np.concatenate([[True], np.diff(stamps) > 0]) if stamps.size else \
        np.zeros(0, dtype=bool)
    dropped[f'{name}_duplicates'] = int(np.sum(~keep))
    return stamps[keep], values[keep]


def _align(imu: Stream, mag: Stream, pressure: Stream, dropped: dict
           ) -> tuple[np.ndarray, np.ndarray]:
    """Join mag and pressure to each IMU sample by nearest stamp; drop what cannot join."""
    stamps, imu_values = _sorted_unique(imu, dropped, 'imu')
    period = float(np.median(np.diff(stamps))) if stamps.size > 1 else 1e9
    values = np.full((stamps.size, len(CHANNELS)), np.nan)
    values[:, :6] = imu_values
    joined = np.ones(stamps.size, dtype=bool)
    for columns, (name, stream) in ((slice(6, 9), ('mag', mag)),
                                    (slice(9, 10), ('pressure', pressure))):
        other_stamps, other_values = _sorted_unique(stream, dropped, name)
        if other_stamps.size == 0:
            joined[:] = False
            continue
        index = np.clip(np.searchsorted(other_stamps, stamps), 0, other_stamps.size - 1)
        previous = np.maximum(index - 1, 0)
        nearer = np.abs(stamps - other_stamps[previous]) <= np.abs(other_stamps[index] - stamps)
        index = np.where(nearer, previous, index)
        close = np.abs(other_stamps[index] - stamps) <= period / 2
        values[close, columns] = other_values[index[close]]
        joined &= close
    finite = np.all(np.isfinite(values), axis=1)
    dropped['nan_samples'] = int(np.sum(joined & ~finite))
    dropped['unaligned_samples'] = int(np.sum(~joined))
    finite &= joined
    return stamps[finite], values[finite]


def _intervals(transitions: list[tuple[int, bool]]) -> list[tuple[int, int]]:
    """[(start, end)] of the true spans of a sorted on/off message sequence."""
    spans, start = [], None
    for stamp, state in transitions:
        if state and start is None:
            start = stamp
        elif not state and start is not None:
            spans.append((start, stamp))
            start = None
    if start is not None:
        spans.append((start, np.iinfo(np.int64).max))
    return spans
