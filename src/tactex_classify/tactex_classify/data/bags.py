# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Recordings read without ROS (rosbags): the tactile channels aligned on the IMU.

A recording is a rosbag2 folder, a folder of part bags, a ROS 1 bag or a lone MCAP or
sqlite3 file (`tactex_classify.data.sources`). Each part is read on its own: a corrupt
part is named and left out, the others are kept.

Topics are found by role (`TOPIC_ROLES`): under any ROS namespace
(`/left_arm/tactile/imu/data_raw`), with or without the leading slash, or where the
caller remaps a role to a name of its own (`{'imu': '/my/imu'}`); a topic of another
name is never taken silently: the error lists the topics of the role's type, with counts
and rates. The IMU stream is the reference: magnetometer and pressure samples are joined
to each IMU sample by `tactex_classify.data.stream_alignment.align`. A recording without
a magnetometer (or barometer) topic has no such channels, with a note. Header stamps of
0 (drivers that never set them) fall back to the log time, with a note. Metadata whose
label is not text or whose trial is not an integer is refused by bag and key.
"""

from __future__ import annotations

from array import array
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from tactex_classify.data.recording_metadata import check_metadata, parse_metadata
from tactex_classify.data.sources import bag_parts, decoded_messages, LOGGED_PAST_INT64, reason
from tactex_classify.data.stream_alignment import align, Stream
from tactex_classify.data.topic_inventory import survey, TopicInventory
from tactex_classify.errors import BagError, DatasetError
from tactex_common import topics
from tactex_common.channels import ACCEL, BARO, CHANNELS, GYRO, MAG
from tactex_common.stamps import after_clock_resets, mean_rate_hz, stamp_ns, stamp_or_log_ns
from tactex_description.geometry import ARM_JOINT_NAMES

# Role -> (topic relative to the recording's namespace, message type).
TOPIC_ROLES = {
    'imu': (topics.IMU_RAW, 'sensor_msgs/msg/Imu'),
    'mag': (topics.MAG, 'sensor_msgs/msg/MagneticField'),
    'pressure': (topics.PRESSURE, 'sensor_msgs/msg/FluidPressure'),
    'active': (topics.SWEEP_ACTIVE, 'std_msgs/msg/Bool'),
    'metadata': (topics.RECORDING_METADATA, 'std_msgs/msg/String'),
    'joints': (topics.JOINT_STATES, 'sensor_msgs/msg/JointState'),
    'contact': (topics.GROUND_TRUTH_CONTACT, 'geometry_msgs/msg/PoseStamped'),
    'edge': (topics.GROUND_TRUTH_SENSOR, 'geometry_msgs/msg/PoseStamped'),
    'texture': (topics.GROUND_TRUTH_TEXTURE, 'std_msgs/msg/String'),
}
# The channels each sensor role gives, in CHANNELS order.
ROLE_CHANNELS = {'imu': ACCEL + GYRO, 'mag': MAG, 'pressure': BARO}


@dataclass
class GroundTruth:
    """What the simulator says happened (topics `sim/ground_truth/*`).

    Attributes:
        contact_ns: stamps at which the sensor touched the surface.
        edge_ns: stamps of the sensor edge positions.
        edge_m: (n, 3) world positions of the sensor edge.
        sensor_q: (n, 4) attitudes (w, x, y, z) of sensor_link in world, at edge_ns.
        texture_ns: stamps of the texture names.
        texture: the texture under the edge at each of those stamps ('' for none).
    """

    contact_ns: np.ndarray
    edge_ns: np.ndarray
    edge_m: np.ndarray
    texture_ns: np.ndarray
    texture: np.ndarray
    sensor_q: np.ndarray


@dataclass
class Recording:
    """One recording's aligned samples and what was dropped on the way."""

    path: Path
    stamps_ns: np.ndarray  # (n,) int64, header stamps of the IMU samples
    values: np.ndarray  # (n, len(channels)) float64 in `channels` order, SI units
    metadata: dict
    active_ns: list[tuple[int, int]] | None  # sweep/active intervals, None if no such topic
    joint_stamps_ns: np.ndarray
    joint_speed: np.ndarray  # norm of the joint velocities (rad/s) at joint_stamps_ns
    channels: tuple[str, ...] = CHANNELS
    truth: GroundTruth | None = None
    dropped: dict[str, int] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    messages: int = 0
    # (len(joint_stamps_ns), arm joints) positions (rad), NaN where a message lacked one
    joint_positions: np.ndarray = field(
        default_factory=lambda: np.zeros((0, len(ARM_JOINT_NAMES))))
    reordered: dict[str, int] = field(default_factory=dict)  # per stream, samples sorted
    clock_resets: int = 0  # the most times a stream's header stamps restarted

    @property
    def rate_hz(self) -> float:
        """Mean sampling rate of the aligned samples, gaps left out."""
        return mean_rate_hz(self.stamps_ns)

    def channel(self, name: str) -> np.ndarray:
        """The samples of one channel."""
        return self.values[:, self.channels.index(name)]


def sample_values(role: str, message) -> tuple[float, ...]:
    """The values of a sensor message (rclpy's or rosbags'), in ROLE_CHANNELS[role] order."""
    if role == 'imu':
        a, w = message.linear_acceleration, message.angular_velocity
        return (a.x, a.y, a.z, w.x, w.y, w.z)
    if role == 'mag':
        m = message.magnetic_field
        return (m.x, m.y, m.z)
    return (message.fluid_pressure,)


def parse_topic_remaps(items: Sequence[str]) -> dict[str, str]:
    """['imu=/my/imu', ...] -> {'imu': '/my/imu'}.

    Raises:
        BagError: not ROLE=TOPIC, an unknown role, or a role given twice.
    """
    remaps: dict[str, str] = {}
    for item in items:
        role, sep, topic = item.partition('=')
        role, topic = role.strip(), topic.strip()
        if not sep or not topic.strip('/'):
            raise BagError(f'--topic {item!r} is not ROLE=TOPIC, e.g. imu=/my/imu')
        if role not in TOPIC_ROLES:
            raise BagError(f'--topic {item!r}: unknown role {role!r}; roles: '
                           f'{", ".join(TOPIC_ROLES)}')
        if role in remaps:
            raise BagError(f'--topic gives {role!r} twice')
        remaps[role] = '/' + topic.strip('/')
    return remaps


def resolve_topics(available: Mapping[str, str], remaps: Mapping[str, str] | None = None
                   ) -> dict[str, str]:
    """Role -> topic name in the bag, for every role the bag has.

    Args:
        available: topic name as stored -> message type.
        remaps: role -> topic name given by the user (with or without leading slash).

    Raises:
        BagError: a role is found under several namespaces (pick one with a remap), or a
            topic's message type is not the role's.
    """
    remaps = remaps or {}
    by_name = {'/' + name.strip('/'): name for name in available}
    found: dict[str, str] = {}
    for role in sorted(TOPIC_ROLES, key=lambda r: r != 'imu'):  # imu first: its namespace
        relative, msgtype = TOPIC_ROLES[role]
        if role in remaps:
            candidates = [remaps[role]] if remaps[role] in by_name else []
        else:
            candidates = [n for n in by_name if n == f'/{relative}' or n.endswith(f'/{relative}')]
            if len(candidates) > 1 and 'imu' in found:
                namespace = found['imu'][:-len(TOPIC_ROLES['imu'][0])]
                candidates = [n for n in candidates if n == namespace + relative] or candidates
        if len(candidates) > 1:
            raise BagError(f'{relative} appears under several namespaces '
                           f'({", ".join(sorted(candidates))}); pick one with --topic '
                           f'{role}=NAME')
        if candidates:
            stored = by_name[candidates[0]]
            if available[stored] != msgtype:
                raise BagError(f'topic {stored} is {available[stored]}, expected {msgtype} '
                               f'for {role}; remap with --topic {role}=NAME')
            found[role] = stored
    return found


class _Collected:
    """Samples of one part, kept in flat arrays (8 bytes a value at any length)."""

    def __init__(self) -> None:
        self.values = {role: array('d') for role in ROLE_CHANNELS}
        self.stamps = {role: array('q') for role in (*ROLE_CHANNELS, 'contact', 'edge',
                                                     'texture')}
        self.logged = {role: array('q') for role in ROLE_CHANNELS}  # when a sample was logged
        self.edge = array('d')
        self.attitude = array('d')
        self.texture: list[str] = []
        self.active: list[tuple[int, bool]] = []
        self.joints: list[tuple] = []  # (stamp, speed, the four arm joints' positions)
        self.metadata: dict = {}
        self.messages = 0
        self.zero_stamps = 0  # header stamps of 0, replaced by the log time

    def merge(self, other: _Collected) -> None:
        for role in self.values:
            self.values[role].extend(other.values[role])
        for role in self.stamps:
            self.stamps[role].extend(other.stamps[role])
        for role in self.logged:
            self.logged[role].extend(other.logged[role])
        self.edge.extend(other.edge)
        self.attitude.extend(other.attitude)
        self.texture += other.texture
        self.active += other.active
        self.joints += other.joints
        self.metadata.update(other.metadata)
        self.messages += other.messages
        self.zero_stamps += other.zero_stamps

    def stamp(self, message, log_ns: int) -> int:
        """The header stamp, or the log time where a driver left it 0."""
        header = stamp_ns(message.header.stamp)
        stamp = stamp_or_log_ns(header, log_ns)
        if stamp != header:
            self.zero_stamps += 1
        return stamp

    def add(self, role: str, message, log_ns: int, path: Path) -> None:
        if log_ns > np.iinfo(np.int64).max:
            raise BagError(f'{path}: {LOGGED_PAST_INT64}')
        self.messages += 1
        if role in ROLE_CHANNELS:
            self.stamps[role].append(self.stamp(message, log_ns))
            self.logged[role].append(log_ns)
            self.values[role].extend(sample_values(role, message))
        elif role == 'active':
            self.active.append((log_ns, bool(message.data)))
        elif role == 'joints':
            speed = float(np.linalg.norm(message.velocity[:4])) if len(
                message.velocity) else float('nan')
            by_name = dict(zip(message.name, message.position, strict=False))
            self.joints.append((self.stamp(message, log_ns), speed,
                                *(float(by_name.get(name, 'nan')) for name in ARM_JOINT_NAMES)))
        elif role == 'metadata':
            self.metadata.update(parse_metadata(message.data, path))
        elif role in ('contact', 'edge'):
            self.stamps[role].append(self.stamp(message, log_ns))
            if role == 'edge':
                p, q = message.pose.position, message.pose.orientation
                self.edge.extend((p.x, p.y, p.z))
                self.attitude.extend((q.w, q.x, q.y, q.z))
        elif role == 'texture':
            self.stamps[role].append(log_ns)
            self.texture.append(str(message.data))

    def stream(self, role: str) -> tuple[Stream, int]:
        """A sensor stream, each part after a device clock reset put back by the log times.

        Returns the stream and the number of resets.
        """
        channels = ROLE_CHANNELS[role]
        stamps, resets = after_clock_resets(np.frombuffer(self.stamps[role], dtype=np.int64),
                                            np.frombuffer(self.logged[role], dtype=np.int64))
        return Stream(role, channels, stamps,
                      np.frombuffer(self.values[role]).reshape(-1, len(channels))), resets


def recording_topics(path: Path, remaps: Mapping[str, str] | None = None) -> dict[str, str]:
    """Role -> topic of a recording, from the readable parts' indexes (no messages read).

    Raises:
        BagError: not a recording, or ambiguous topics.
    """
    return resolve_topics(_inventory(path).types, remaps)


def missing_role(path: Path, role: str) -> str:
    """Why a recording has no topic for `role`, and which topics could be it (with --topic).

    Raises:
        BagError: not a recording.
    """
    relative, msgtype = TOPIC_ROLES[role]
    return _inventory(path).missing(role, relative, msgtype)


def _inventory(path: Path) -> TopicInventory:
    """The topics of a recording's readable parts (an unreadable one is named when read)."""
    inventory = TopicInventory()
    for part in bag_parts(Path(path)):
        try:
            inventory.merge(survey(part))
        except BagError:
            continue
    return inventory


def readable_parts(path: Path, notes: list[str]) -> tuple[TopicInventory, list[Path]]:
    """The inventory of a recording's readable parts, and those parts; notes name the rest.

    Raises:
        BagError: not a recording, or no part can be read (naming why).
    """
    parts = bag_parts(path)
    inventory, readable, reasons = TopicInventory(), [], []
    for part in parts:
        try:
            inventory.merge(survey(part))
            readable.append(part)
        except BagError as err:
            reasons.append(reason(err))
            notes.append(f'part {part.name} skipped: {reasons[-1]}')
    if not readable:
        raise BagError(f'{path}: cannot read: {reasons[0]}' if len(parts) == 1 else
                       f'{path}: cannot read any of its {len(parts)} parts ({notes[0]})')
    return inventory, readable


def read_recording(path: Path, *, remaps: Mapping[str, str] | None = None,
                   channels: Sequence[str] | None = None) -> Recording:
    """Read and align one recording.

    Args:
        path: a recording (see `tactex_classify.data.sources`).
        remaps: role -> topic name, for bags whose topics have other names.
        channels: the channels wanted (a subset of CHANNELS); default every channel the
            recording has.

    Raises:
        BagError: no part can be read, no IMU messages, a wanted channel has no topic,
            or the metadata has the wrong types; the message says which.
    """
    path = Path(path)
    parts = bag_parts(path)
    notes, dropped = [], {'unreadable_parts': 0}
    inventory, readable = readable_parts(path, notes)
    dropped['unreadable_parts'] = len(parts) - len(readable)
    roles = resolve_topics(inventory.types, remaps)
    if 'imu' not in roles:
        expected = (remaps or {}).get('imu', topics.IMU_RAW)
        raise BagError(f'{path}: {inventory.missing("imu", expected, TOPIC_ROLES["imu"][1])}')
    wanted_roles = _roles_for(channels, roles, path)
    by_topic = {topic: role for role, topic in roles.items()
                if role in wanted_roles or role not in ROLE_CHANNELS}
    collected = _Collected()
    for part in readable:
        try:
            collected.merge(_read_part(part, by_topic, path))
        except BagError as err:
            if len(parts) == 1:
                raise
            dropped['unreadable_parts'] += 1
            notes.append(f'part {part.name} skipped: {reason(err)}')
    if collected.zero_stamps:
        notes.append(f'{collected.zero_stamps} message(s) had header stamp 0 (a driver that '
                     'never sets it): their log times used instead')
    if not collected.stamps['imu']:
        raise BagError(f'{path}: no readable messages on {roles["imu"]}')
    for role in ('mag', 'pressure'):
        if role not in wanted_roles and channels is None:
            notes.append(f'no {TOPIC_ROLES[role][0]} topic: channels '
                         f'{", ".join(ROLE_CHANNELS[role])} absent')
    streams = {role: collected.stream(role) for role in ROLE_CHANNELS if role in wanted_roles}
    resets = {roles[role]: count for role, (_, count) in streams.items() if count}
    if resets:
        notes.append('header stamps went back (a device clock restarting): '
                     + ', '.join(f'{topic} {count} time(s)' for topic, count in resets.items())
                     + '; each part after a reset put after the one before by the log times')
    aligned = align(streams.pop('imu')[0], [stream for stream, _ in streams.values()])
    dropped.update(aligned.dropped)
    order = [aligned.channels.index(c) for c in CHANNELS if c in aligned.channels]
    if channels is not None:
        order = [aligned.channels.index(c) for c in channels]
    joint_array = np.array(collected.joints, dtype=np.float64).reshape(
        -1, 2 + len(ARM_JOINT_NAMES))
    joint_order = np.argsort(joint_array[:, 0], kind='stable')
    return Recording(
        path, aligned.stamps_ns, aligned.values[:, order], check_metadata(
            collected.metadata, path),
        segments(sorted(collected.active)) if 'active' in roles else None,
        joint_array[joint_order, 0].astype(np.int64), joint_array[joint_order, 1],
        tuple(aligned.channels[i] for i in order), _truth(collected, roles), dropped, notes,
        collected.messages, joint_array[joint_order, 2:], aligned.reordered,
        max(resets.values(), default=0))


def _read_part(part: Path, by_topic: Mapping[str, str], path: Path) -> _Collected:
    """The messages of one part on the topics of `by_topic` (topic -> role).

    Raises:
        BagError: the part cannot be read (UnreadablePart), or its metadata is refused.
    """
    data = _Collected()
    for topic, log_ns, message in decoded_messages(part, by_topic):
        data.add(by_topic[topic], message, log_ns, path)
    return data


def _roles_for(channels: Sequence[str] | None, roles: Mapping[str, str], path: Path
               ) -> set[str]:
    """The sensor roles to read for the wanted channels."""
    if channels is None:
        return {role for role in ROLE_CHANNELS if role in roles}
    unknown = [c for c in channels if c not in CHANNELS]
    if unknown:
        raise BagError(f'channel(s) {unknown} are not recorded in bags; bag channels: '
                       f'{", ".join(CHANNELS)}')
    wanted = {role for role, names in ROLE_CHANNELS.items() if set(names) & set(channels)}
    missing = sorted(wanted - set(roles), key=list(ROLE_CHANNELS).index)
    if missing:
        role = missing[0]
        raise BagError(f'{path}: no {TOPIC_ROLES[role][0]} topic, so no channels '
                       f'{", ".join(ROLE_CHANNELS[role])}; leave them out of --channels or '
                       f'remap with --topic {role}=NAME')
    return wanted | {'imu'}


def _truth(collected: _Collected, roles: Mapping[str, str]) -> GroundTruth | None:
    if not {'edge', 'texture'} <= set(roles):
        return None  # no simulator ground truth (a contact topic is absent when never touching)

    def ordered(role: str, *values: np.ndarray) -> list[np.ndarray]:
        stamps = np.frombuffer(collected.stamps[role], dtype=np.int64)
        order = np.argsort(stamps, kind='stable')
        return [stamps[order]] + [v[order] for v in values]

    contact_ns, = ordered('contact')
    edge_ns, edge_m, sensor_q = ordered('edge', np.frombuffer(collected.edge).reshape(-1, 3),
                                        np.frombuffer(collected.attitude).reshape(-1, 4))
    texture_ns, texture = ordered('texture', np.array(collected.texture, dtype=str))
    return GroundTruth(contact_ns, edge_ns, edge_m, texture_ns, texture, sensor_q)


def inside(stamps_ns: np.ndarray, spans: Sequence[tuple[int, int]]) -> np.ndarray:
    """True for the stamps within a span (both ends included): the converter's segment rule."""
    keep = np.zeros(np.shape(stamps_ns), dtype=bool)
    for start, end in spans:
        keep |= (stamps_ns >= start) & (stamps_ns <= end)
    return keep


def segments(transitions: Sequence[tuple[int, bool]]) -> list[tuple[int, int]]:
    """[(start, end)] of the true spans of a sorted on/off message sequence (sweep/active).

    A span still open at the end runs to the largest int64.
    """
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


def common_channels(recordings: Sequence[Path], remaps: Mapping[str, str] | None,
                     notes: list[str]) -> list[str]:
    """The channels every recording with an IMU topic has; notes say what was left out.

    Raises:
        DatasetError: a topic named with --topic that a recording lacks (a typo would
            otherwise drop its channels with a note only).
    """
    lacking: dict[str, list[Path]] = {role: [] for role in ROLE_CHANNELS}
    for path in recordings:
        try:
            roles = recording_topics(path, remaps)
        except BagError:
            continue  # reported when read
        if 'imu' in roles:
            for role in ROLE_CHANNELS:
                if role not in roles:
                    lacking[role].append(path)
    for role, paths in lacking.items():
        if paths and role in (remaps or {}):
            raise DatasetError(f'--topic {role}={remaps[role]}: {len(paths)} recording(s) have '
                               f'no such topic ({_first_names(paths)}); check its name with '
                               '`tactex bag info`')
    channels = list(CHANNELS)
    for role, paths in lacking.items():
        if paths:
            channels = [c for c in channels if c not in ROLE_CHANNELS[role]]
            notes.append(f'note: {len(paths)} recording(s) have no {role} topic '
                         f'({_first_names(paths)}): channels {", ".join(ROLE_CHANNELS[role])} '
                         f'left out of the dataset (choose with --channels); {paths[0].name}: '
                         f'{missing_role(paths[0], role)}')
    return channels


def _first_names(paths: Sequence[Path]) -> str:
    """The names of the first three paths, and '...' when there are more."""
    return ', '.join(path.name for path in paths[:3]) + (', ...' if len(paths) > 3 else '')
