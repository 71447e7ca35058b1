# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What a recording's topics are, from its parts' indexes: types, counts, rates, fields.

No message is read: the counts and the time span come from the bag's index (metadata.yaml,
the MCAP summary, the ROS 1 chunk records), so the survey of a long recording takes a moment.
It answers "which topic holds the IMU?" when the expected name is not there.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

from tactex_classify.data.sources import open_part, storage_files
from tactex_common.interfaces import typestore


@dataclass
class TopicInventory:
    """Per topic: message type and count; the span the parts cover; custom types' fields."""

    types: dict[str, str] = field(default_factory=dict)
    counts: dict[str, int] = field(default_factory=dict)
    duration_ns: int = 0
    fields: dict[str, tuple[str, ...]] = field(default_factory=dict)

    def merge(self, other: TopicInventory) -> None:
        """Add another part's topics (parts follow each other, so spans add up)."""
        self.types.update(other.types)
        for topic, count in other.counts.items():
            self.counts[topic] = self.counts.get(topic, 0) + count
        self.duration_ns += other.duration_ns
        self.fields.update(other.fields)

    def rate_hz(self, topic: str) -> float:
        """Mean message rate of a topic over the recording's span (nan when unknown)."""
        count = self.counts.get(topic, 0)
        return (count - 1) * 1e9 / self.duration_ns if count > 1 and self.duration_ns else float(
            'nan')

    def describe(self, topic: str) -> str:
        """'sensor_msgs/msg/Imu on /imu/data (11,865 messages, 30.0 Hz)'."""
        rate = self.rate_hz(topic)
        return (f'{self.types[topic]} on {topic} ({self.counts.get(topic, 0):,} messages'
                + (f', {rate:.1f} Hz)' if rate == rate else ')'))

    def of_type(self, msgtype: str) -> list[str]:
        """The topics holding `msgtype`, most messages first."""
        return sorted((t for t, m in self.types.items() if m == msgtype),
                      key=lambda t: (-self.counts.get(t, 0), t))

    def missing(self, role: str, expected: str, msgtype: str) -> str:
        """Why no topic was taken for a role, and which ones could be: a sentence or two."""
        candidates = self.of_type(msgtype)
        if candidates:
            return (f'no {expected}; ' + '; '.join(
                f'{self.describe(topic)}: use --topic {role}={topic}'
                for topic in candidates[:5]))
        held = ', '.join(self._held(topic) for topic in sorted(self.types)[:8])
        return (f'no {expected} and no topic of type {msgtype}; the recording holds '
                f'{held or "no messages"}')

    def _held(self, topic: str) -> str:
        msgtype = self.types[topic]
        names = self.fields.get(msgtype)
        return f'{topic} ({msgtype}' + (f'; fields {", ".join(names)})' if names else ')')


def survey(part: Path) -> TopicInventory:
    """The inventory of one part (topics holding messages only).

    A part surveyed before whose storage files have the same sizes and modification times
    is not opened again: convert surveys every recording for its common channels and then
    once more as it reads it, and a recorder's recording is many one-second parts, each
    costing an open of its metadata and type definitions.

    Raises:
        BagError: the part cannot be opened (see `tactex_classify.data.sources.open_part`).
    """
    part = Path(part)
    try:
        files = storage_files(part) + ([part / 'metadata.yaml'] if part.is_dir() else [])
        signature = tuple((str(f), f.stat().st_size, f.stat().st_mtime_ns)
                          for f in files if f.exists())
    except OSError:  # unreadable: open_part says why
        return _survey(part)
    return copy.deepcopy(_surveyed(part, signature))


@lru_cache(maxsize=8192)
def _surveyed(part: Path, signature: tuple) -> TopicInventory:
    """`_survey(part)` once per signature of its storage files."""
    del signature  # the cache key only
    return _survey(part)


def _survey(part: Path) -> TopicInventory:
    """The inventory of one part, read from its index."""
    inventory = TopicInventory()
    known = typestore().fielddefs  # the standard types and tactex_msgs: no fields listed
    with open_part(part, readable=lambda connection: False) as reader:  # counts only
        for connection in reader.connections:
            if connection.msgcount == 0:
                continue
            topic = connection.topic
            inventory.types[topic] = connection.msgtype
            inventory.counts[topic] = inventory.counts.get(topic, 0) + connection.msgcount
            if connection.msgtype not in known:
                definition = reader.typestore.fielddefs.get(connection.msgtype)
                if definition is not None:
                    inventory.fields[connection.msgtype] = tuple(
                        name for name, _ in definition[1])
        inventory.duration_ns = max(0, reader.end_time - reader.start_time)
    return inventory
