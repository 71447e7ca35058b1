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

from dataclasses import dataclass, field
import json
from pathlib import Path

import numpy as np
from rosbags.highlevel import AnyReader

from tactex_classify.errors import BagError
from tactex_sensor import topics

CHANNELS = ('ax', 'ay', 'az', 'gx', 'gy', 'gz', 'mx', 'my', 'mz', 'baro')
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
        """Median sampling rate of the aligned samples."""
        if self.stamps_ns.size < 2:
            return float('nan')
        return 1e9 / float(np.median(np.diff(self.stamps_ns)))


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
    imu: list[tuple] = []
    mag: list[tuple] = []
    pressure: list[tuple] = []
    active: list[tuple[int, bool]] = []
    joints: list[tuple[int, float]] = []
    metadata: dict = {}
    has_segments = False
    messages = 0
    try:
        with AnyReader(readable) as reader:
            connections = [c for c in reader.connections if c.topic in _WANTED]
            has_segments = any(c.topic == f'/{topics.SWEEP_ACTIVE}' for c in connections)
            for connection, log_ns, raw in reader.messages(connections=connections):
                messages += 1
                message = reader.deserialize(raw, connection.msgtype)
                topic = connection.topic[1:]
                if topic == topics.IMU_RAW:
                    a, w = message.linear_acceleration, message.angular_velocity
                    imu.append((_ns(message.header.stamp), a.x, a.y, a.z, w.x, w.y, w.z))
                elif topic == topics.MAG:
                    m = message.magnetic_field
                    mag.append((_ns(message.header.stamp), m.x, m.y, m.z))
                elif topic == topics.PRESSURE:
                    pressure.append((_ns(message.header.stamp), message.fluid_pressure))
                elif topic == topics.SWEEP_ACTIVE:
                    active.append((log_ns, bool(message.data)))
                elif topic == topics.JOINT_STATES:
                    speed = float(np.linalg.norm(message.velocity[:4])) if len(
                        message.velocity) else float('nan')
                    joints.append((_ns(message.header.stamp) or log_ns, speed))
                elif topic == topics.RECORDING_METADATA:
                    metadata.update(_parse_metadata(message.data, path))
    except Exception as err:  # rosbags raises several unrelated types for a broken file
        raise BagError(f'{path}: cannot read: {type(err).__name__}: {err}') from err
    if not imu:
        raise BagError(f'{path}: no messages on /{topics.IMU_RAW}')
    stamps, values = _align(np.array(imu), np.array(mag).reshape(-1, 4),
                            np.array(pressure).reshape(-1, 2), dropped)
    joint_array = np.array(joints).reshape(-1, 2)
    order = np.argsort(joint_array[:, 0], kind='stable')
    return Recording(path, stamps, values, metadata,
                     _intervals(sorted(active)) if has_segments else None,
                     joint_array[order, 0].astype(np.int64), joint_array[order, 1],
                     dropped, messages)


def _ns(stamp) -> int:
    return int(stamp.sec) * 1_000_000_000 + int(stamp.nanosec)


def _parse_metadata(text: str, path: Path) -> dict:
    try:
        value = json.loads(text)
    except json.JSONDecodeError as err:
        raise BagError(f'{path}: recording/metadata is not JSON: {err}') from None
    if not isinstance(value, dict):
        raise BagError(f'{path}: recording/metadata must be a JSON object')
    return value


def _sorted_unique(table: np.ndarray, dropped: dict, name: str) -> np.ndarray:
    """Rows sorted by stamp (column 0), duplicates of a stamp dropped (first kept)."""
    if table.size == 0:
        return table
    out_of_order = int(np.sum(np.diff(table[:, 0]) < 0))
    table = table[np.argsort(table[:, 0], kind='stable')]
    keep = np.concatenate([[True], np.diff(table[:, 0]) > 0])
    dropped[f'{name}_out_of_order'] = out_of_order
    dropped[f'{name}_duplicates'] = int(np.sum(~keep))
    return table[keep]


def _align(imu: np.ndarray, mag: np.ndarray, pressure: np.ndarray, dropped: dict
           ) -> tuple[np.ndarray, np.ndarray]:
    """Join mag and pressure to each IMU sample by nearest stamp; drop what cannot join."""
    imu = _sorted_unique(imu, dropped, 'imu')
    mag = _sorted_unique(mag, dropped, 'mag')
    pressure = _sorted_unique(pressure, dropped, 'pressure')
    stamps = imu[:, 0]
    period = float(np.median(np.diff(stamps))) if stamps.size > 1 else 1e9
    values = np.full((stamps.size, len(CHANNELS)), np.nan)
    values[:, :6] = imu[:, 1:7]
    joined = np.ones(stamps.size, dtype=bool)
    for columns, table in ((slice(6, 9), mag), (slice(9, 10), pressure)):
        if table.size == 0:
            joined[:] = False
            continue
        index = np.clip(np.searchsorted(table[:, 0], stamps), 0, len(table) - 1)
        previous = np.maximum(index - 1, 0)
        nearer = np.abs(stamps - table[previous, 0]) <= np.abs(table[index, 0] - stamps)
        index = np.where(nearer, previous, index)
        close = np.abs(table[index, 0] - stamps) <= period / 2
        values[close, columns] = table[index[close], 1:]
        joined &= close
    finite = np.all(np.isfinite(values), axis=1)
    dropped['nan_samples'] = int(np.sum(joined & ~finite))
    dropped['unaligned_samples'] = int(np.sum(~joined))
    finite &= joined
    return stamps[finite].astype(np.int64), values[finite]


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
