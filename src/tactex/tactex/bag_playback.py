# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What `tactex bag play` publishes and when: recordings as a timed stream of ROS 2 messages.

No ROS here (the publishing is `tactex.bag_player`). The messages of each recording come
in the order they were logged, as CDR bytes ready for `publish_raw`: rosbag2 messages as
they are stored, ROS 1 messages migrated to their ROS 2 types by rosbags' converter
(`header.seq` dropped). Each carries the instant it is due, in seconds from the start of
its recording's playback: (log time - first log time - start offset) / rate factor.
Topics are chosen by name, renamed by `OLD:=NEW` remaps, and put under a namespace.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
import math
from pathlib import Path

from tactex_classify.data.sources import bag_parts, open_part, read_messages
from tactex_classify.errors import BagError
from tactex_common.interfaces import typestore

LATE_S = 0.005  # a publish this much after its instant is reported as late
LATENESS_BIN_S = 1e-5  # resolution of the lateness percentiles
LATENESS_BINS = 100_000  # up to one second; later ones share the last bin


@dataclass(frozen=True)
class PlayOptions:
    """How recordings are played (`ros2 bag play`'s options, `--rate` as rate_factor)."""

    rate_factor: float = 1.0
    start_offset_s: float = 0.0
    duration_s: float | None = None
    topics: tuple[str, ...] = ()
    remaps: tuple[tuple[str, str], ...] = ()
    namespace: str = ''


@dataclass(frozen=True)
class Outgoing:
    """One message to publish.

    Attributes:
        due_s: when, in seconds from the start of its recording's playback.
        log_ns: its log time (what /clock says while it is published).
        topic: the name it is published under.
        msgtype: its ROS 2 type ('sensor_msgs/msg/Imu').
        data: its CDR bytes.
    """

    due_s: float
    log_ns: int
    topic: str
    msgtype: str
    data: bytes


def parse_remap(text: str) -> tuple[str, str]:
    """'OLD:=NEW' -> ('/OLD', '/NEW').

    Raises:
        ValueError: not OLD:=NEW with two topic names, or NEW not a ROS topic name.
    """
    from tactex.options import is_ros_name
    old, sep, new = text.partition(':=')
    if not sep or not old.strip('/ ') or not new.strip('/ '):
        raise ValueError(f'--remap {text!r} is not OLD:=NEW, e.g. '
                         '/imu/data:=/tactile/imu/data_raw')
    new = new.strip().strip('/')
    if not is_ros_name(new):
        raise ValueError(f'--remap {text!r}: {new!r} is not a ROS topic name (segments of '
                         'letters, digits and _, not starting with a digit, split by /)')
    return '/' + old.strip().strip('/'), '/' + new


def output_topic(topic: str, options: PlayOptions) -> str:
    """The name a recorded topic is published under: remapped, then namespaced."""
    name = '/' + topic.strip('/')
    name = dict(options.remaps).get(name, name)
    namespace = options.namespace.strip('/')
    return f'/{namespace}{name}' if namespace else name


def chosen(topic: str, options: PlayOptions) -> bool:
    """Whether a recorded topic is played (all, or those named by --topics)."""
    return not options.topics or '/' + topic.strip('/') in {
        '/' + t.strip('/') for t in options.topics}


def messages(path: Path, options: PlayOptions,
             skipped: Callable[[str], None] = lambda why: None) -> Iterator[Outgoing]:
    """The messages of one recording to publish, in logged order, each with its instant.

    Args:
        path: a recording (see `tactex_classify.data.sources`).
        options: topics, remaps, namespace, offset, duration and rate factor.
        skipped: told once per topic that cannot be played, and why.

    Raises:
        BagError: a part cannot be read.
    """
    ros2 = typestore()
    first_ns = None
    start_ns = end_ns = None
    cache: dict = {}
    refused: set[str] = set()
    for part in bag_parts(path):
        with open_part(part) as reader:
            wanted = [c for c in reader.connections if chosen(c.topic, options)]
            ros1 = not reader.is2
            for connection in wanted:
                if connection.msgtype not in ros2.types and connection.topic not in refused:
                    refused.add(connection.topic)
                    skipped(f'{connection.topic}: {connection.msgtype} is not a ROS 2 type here')
            wanted = [c for c in wanted if c.topic not in refused]
            for connection, log_ns, raw in read_messages(reader, part, wanted):
                if first_ns is None:
                    first_ns = log_ns
                    start_ns = first_ns + int(options.start_offset_s * 1e9)
                    end_ns = (math.inf if options.duration_s is None
                              else start_ns + int(options.duration_s * 1e9))
                if log_ns < start_ns:
                    continue
                if log_ns > end_ns:
                    return
                data = (_ros1_to_cdr(reader, ros2, connection.msgtype, raw, cache) if ros1
                        else bytes(raw))
                yield Outgoing((log_ns - start_ns) / 1e9 / options.rate_factor, log_ns,
                               output_topic(connection.topic, options), connection.msgtype,
                               data)


def _ros1_to_cdr(reader, ros2, msgtype: str, raw: bytes, cache: dict) -> bytes:
    """A ROS 1 message as the CDR bytes of its ROS 2 type (rosbags' own migration)."""
    from rosbags.convert.converter import migrate_message
    message = reader.deserialize(raw, msgtype)
    migrated = migrate_message(reader.typestore, ros2, msgtype, msgtype, cache, message)
    return bytes(ros2.serialize_cdr(migrated, msgtype))


class Lateness:
    """How late each publish was after its instant, in bounded memory (a histogram).

    Lateness is counted in LATENESS_BIN_S bins up to LATENESS_BINS of them (the last
    holds everything later), so a loop played for days keeps the same few kilobytes;
    percentiles are the upper edges of their bins, the largest lateness is exact.
    """

    def __init__(self) -> None:
        self.counts = [0] * (LATENESS_BINS + 1)
        self.published = self.late = 0
        self.max_s = 0.0

    def add(self, seconds: float) -> None:
        """One publish, `seconds` after its instant (negative: early, counted as 0)."""
        seconds = max(seconds, 0.0)
        self.counts[min(int(seconds / LATENESS_BIN_S), LATENESS_BINS)] += 1
        self.published += 1
        self.late += seconds > LATE_S
        self.max_s = max(self.max_s, seconds)

    def percentile_ms(self, percent: float) -> float:
        """The lateness (ms) that `percent` of the publishes did not exceed."""
        needed = percent / 100 * self.published
        seen = 0
        for index, count in enumerate(self.counts):
            seen += count
            if seen >= needed:
                return min((index + 1) * LATENESS_BIN_S, self.max_s) * 1e3
        return self.max_s * 1e3

    def summary(self) -> dict:
        """Count, p50, p99 and max lateness (ms), and how many were later than LATE_S."""
        if not self.published:
            return {'published': 0}
        return {'published': self.published, 'p50_ms': self.percentile_ms(50),
                'p99_ms': self.percentile_ms(99), 'max_ms': self.max_s * 1e3,
                'late': self.late}


def topics_of(paths: Sequence[Path], options: PlayOptions) -> dict[str, str]:
    """Output topic -> ROS 2 type of everything the recordings will publish.

    Raises:
        BagError: a part cannot be read, or one output topic would carry two types (a ROS 1
            topic logged with two, or a remap onto a topic of another type): a ROS 2
            topic has one.
    """
    ros2 = typestore()
    found: dict[str, str] = {}
    for path in paths:
        for part in bag_parts(path):
            with open_part(part) as reader:
                for connection in reader.connections:
                    if not (chosen(connection.topic, options)
                            and connection.msgtype in ros2.types):
                        continue
                    topic = output_topic(connection.topic, options)
                    if found.setdefault(topic, connection.msgtype) != connection.msgtype:
                        raise BagError(f'{part}: {topic} would carry two types, '
                                       f'{found[topic]} and {connection.msgtype}; a ROS 2 '
                                       'topic has one: leave one out with --topics, or '
                                       'give it another name with --remap')
    return found
