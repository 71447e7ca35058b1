# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What a recording holds, like `ros2 bag info`, for every format tactex reads.

The summary (storage, span, topics, types, counts) comes from the parts' indexes. The
timing (each topic's median rate, the jitter of its periods, and the gaps longer than
`GAP_PERIODS` median periods) needs every message's log time: a ROS 1 bag's index and an
MCAP file's message indexes hold them; of other files (sqlite3, zstd-compressed files,
MCAP without message indexes) the messages are read but not decoded. The label and
metadata come from the recording/metadata topic.
"""

from __future__ import annotations

from array import array
from dataclasses import asdict, dataclass, field
from datetime import datetime, timezone
import json
from pathlib import Path

import numpy as np

from tactex_classify.data.bags import TOPIC_ROLES
from tactex_classify.data.mcap_index import log_times
from tactex_classify.data.recording_metadata import parse_metadata
from tactex_classify.data.sources import (
    bag_parts,
    explain,
    kind,
    LOGGED_PAST_INT64,
    MAX_METADATA_BYTES,
    open_part,
    read_messages,
    reason,
    storage_files,
)
from tactex_classify.errors import BagError
from tactex_common.files import read_text

GAP_PERIODS = 5  # a gap: a step longer than this many median periods
MIN_TIMED_MESSAGES = 10  # fewer (segment markers, metadata) have no rate to speak of
MAX_GAPS_KEPT = 1000  # per topic, in the JSON; the text shows the first few


@dataclass
class TopicInfo:
    """One topic: its type and count; with timing, its rate, jitter and gaps."""

    topic: str
    msgtype: str
    count: int
    rate_hz: float | None = None  # from the median period of the log times
    jitter_ms: float | None = None  # standard deviation of the periods, gaps left out
    gaps: list[tuple[float, float]] = field(default_factory=list)  # (start s, length s)
    gap_count: int = 0


@dataclass
class Part:
    """One file or folder of the recording."""

    path: str
    storage: str
    size_bytes: int
    error: str = ''


@dataclass
class RecordingInfo:
    """A recording's summary, timing and metadata."""

    path: str
    parts: list[Part]
    start_ns: int | None
    end_ns: int | None
    messages: int
    topics: list[TopicInfo]
    metadata: dict = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)

    @property
    def duration_s(self) -> float:
        """Seconds from the first message to the last (0 without messages)."""
        return 0.0 if self.start_ns is None else (self.end_ns - self.start_ns) / 1e9

    def as_json(self) -> dict:
        """A JSON-ready dict (what `tactex bag info --json` prints)."""
        return {**asdict(self), 'duration_s': self.duration_s}


def describe(path: Path, *, timing: bool = True, progress=None) -> RecordingInfo:
    """The summary of one recording; with `timing`, per-topic rates, jitter and gaps.

    Args:
        path: a recording (see `tactex_classify.data.sources`).
        timing: read every message's log time for rates, jitter and gaps (else the
            index's summary only).
        progress: called with the number of messages read since the last call.

    Raises:
        BagError: not a recording, or none of its parts can be read.
    """
    path = Path(path)
    parts, topics, times = [], {}, {}
    start, end, metadata, notes = None, None, {}, []
    for unit in bag_parts(path):
        part_times, part_metadata = {}, {}
        try:  # a part counts only once all of it was read
            with open_part(unit, readable=None if timing else _is_metadata) as reader:
                _read_messages(reader, unit, part_times if timing else None, part_metadata,
                               notes, progress)
                parts.append(Part(str(unit), _storage(unit, reader), _size(unit)))
                for connection in reader.connections:
                    known = topics.setdefault(connection.topic, TopicInfo(
                        connection.topic, connection.msgtype, 0))
                    known.count += connection.msgcount
                if reader.message_count:
                    first, last = reader.start_time, reader.end_time - 1
                    start = first if start is None else min(start, first)
                    end = last if end is None else max(end, last)
        except BagError as err:
            parts.append(Part(str(unit), kind(unit), _size(unit), reason(err)))
            continue
        except OverflowError:  # a log time past int64 (arrays of 'q')
            parts.append(Part(str(unit), kind(unit), _size(unit), LOGGED_PAST_INT64))
            continue
        metadata.update(part_metadata)
        for topic, stamps in part_times.items():
            times.setdefault(topic, array('q')).extend(stamps)
    if all(part.error for part in parts):
        raise BagError(f'{path}: cannot read: {parts[0].error}' if len(parts) == 1 else
                       f'{path}: cannot read any of its {len(parts)} parts')
    # With timing every message's log time was read: a topic without any holds none.
    sorted_times = {topic: np.sort(np.frombuffer(times.get(topic, b''), dtype=np.int64))
                    for topic in topics} if timing else {}
    for topic, stamps in sorted_times.items():  # the file's counts and span, not the index's
        if stamps.size != topics[topic].count:  # a metadata.yaml that lies, or is stale
            notes.append(f'{topic}: the metadata lists {topics[topic].count} message(s), the '
                         f"file holds {stamps.size}: the file's count shown")
            topics[topic].count = int(stamps.size)
    read = [stamps for stamps in sorted_times.values() if stamps.size]
    if read:
        start, end = min(int(s[0]) for s in read), max(int(s[-1]) for s in read)
    for topic, stamps in sorted_times.items():
        _timing(topics[topic], stamps, start)
    return RecordingInfo(str(path), parts, start, end, sum(t.count for t in topics.values()),
                         sorted(topics.values(), key=lambda t: t.topic), metadata, notes)


def _read_messages(reader, unit: Path, times: dict | None, metadata: dict, notes: list[str],
                   progress) -> None:
    """Log times per topic (when `times` is a dict) and the recording's metadata messages."""
    metadata_topics = {c.topic for c in reader.connections if _is_metadata(c)}
    if times is not None and not reader.is2:  # a ROS 1 bag's index holds every log time
        for connection in reader.connections:
            times.setdefault(connection.topic, array('q')).extend(
                entry.time for entry in connection.owner.indexes[connection.id])
        times = None
    elif times is not None and (indexed := _mcap_log_times(reader, unit)) is not None:
        times.update(indexed)
        times = None
    wanted = reader.connections if times is not None else [
        c for c in reader.connections if c.topic in metadata_topics]
    done = 0
    for connection, log_ns, raw in read_messages(reader, unit, wanted):
        if times is not None:
            times.setdefault(connection.topic, array('q')).append(log_ns)
        if connection.topic in metadata_topics:
            try:
                metadata.update(parse_metadata(reader.deserialize(
                    raw, connection.msgtype).data, unit))
            except BagError as err:
                notes.append(str(err))
            except Exception as err:  # noqa: BLE001 - one undecodable metadata message: a note
                notes.append(f'{unit}: recording/metadata: {explain(err, unit)}')
        done += 1
        if progress is not None and done % 65536 == 0:
            progress(65536)
    if progress is not None:
        progress(done % 65536)


def _mcap_log_times(reader, unit: Path) -> dict[str, array] | None:
    """The log times in an MCAP part's message indexes, when they list every message."""
    storage = storage_files(unit)
    if not storage or any(f.suffix != '.mcap' for f in storage):
        return None
    indexed = log_times(storage)
    counts: dict[str, int] = {}
    for connection in reader.connections:
        counts[connection.topic] = counts.get(connection.topic, 0) + connection.msgcount
    if indexed is None or {t: len(v) for t, v in indexed.items() if len(v)} != {
            t: n for t, n in counts.items() if n}:
        return None
    return indexed


def _is_metadata(connection) -> bool:
    """Whether a connection carries the recording's metadata (a JSON string)."""
    topic, msgtype = TOPIC_ROLES['metadata']
    return connection.topic.strip('/').endswith(topic) and connection.msgtype == msgtype


def _timing(info: TopicInfo, stamps: np.ndarray, start_ns: int | None) -> None:
    """Rate, jitter and gaps of one topic from its sorted log times."""
    if stamps.size < MIN_TIMED_MESSAGES:
        return
    periods = np.diff(stamps)
    median = float(np.median(periods))
    if median <= 0:
        return  # every message at one instant: no rate to speak of
    long = periods > GAP_PERIODS * median
    info.rate_hz = 1e9 / median
    steady = periods[~long]
    info.jitter_ms = float(np.std(steady)) / 1e6 if steady.size else 0.0
    info.gap_count = int(long.sum())
    at = np.flatnonzero(long)[:MAX_GAPS_KEPT]
    info.gaps = [(round((int(stamps[i]) - (start_ns or 0)) / 1e9, 6),
                  round(int(periods[i]) / 1e9, 6)) for i in at]


def _storage(part: Path, reader) -> str:
    """The storage in words: format, version, compression."""
    if part.suffix == '.bag':
        return 'ROS 1 bag, format 2.0'
    if not part.is_dir():
        return kind(part) + (', ros2 profile' if part.suffix == '.mcap' else '')
    try:
        import yaml
        meta = yaml.safe_load(read_text(part / 'metadata.yaml', max_bytes=MAX_METADATA_BYTES))
        meta = meta['rosbag2_bagfile_information']
        text = f'rosbag2 version {meta["version"]}, {meta["storage_identifier"]}'
    except Exception:  # noqa: BLE001 - rosbags opened it; the words are a courtesy
        text = kind(part)
    bag = reader.readers[0]
    if bag.compression_mode:
        text += f', {bag.compression_format} compression by {bag.compression_mode}'
    return text


def _size(part: Path) -> int:
    try:
        files = [p for p in part.iterdir()] if part.is_dir() else [part]
        return sum(p.stat().st_size for p in files if p.is_file())
    except OSError:
        return 0


def _when(ns: int) -> str:
    """A stamp as UTC date and time (ms), and its exact seconds (a float would round them)."""
    moment = datetime.fromtimestamp(ns / 1e9, tz=timezone.utc)
    seconds, nanoseconds = divmod(abs(int(ns)), 10**9)
    return (f'{moment:%Y-%m-%d %H:%M:%S.%f}'[:-3]
            + f' UTC ({"-" if ns < 0 else ""}{seconds}.{nanoseconds:09d})')


def format_text(info: RecordingInfo, gaps_shown: int = 3) -> str:
    """The summary as `ros2 bag info` lays it out, with tactex's timing columns."""
    lines = [f'Recording:   {info.path}']
    for part in info.parts:
        state = f'   UNREADABLE: {part.error}' if part.error else ''
        lines.append(f'  {Path(part.path).name}  {part.storage}, '
                     f'{part.size_bytes / 1024**2:.1f} MiB{state}')
    if info.start_ns is not None:
        lines += [f'Duration:    {info.duration_s:.3f} s', f'Start:       {_when(info.start_ns)}',
                  f'End:         {_when(info.end_ns)}']
    lines.append(f'Messages:    {info.messages:,}')
    if info.metadata:
        label = info.metadata.get('label')
        if label is not None:
            lines.append(f'Label:       {label}' + (f' (trial {info.metadata["trial"]})'
                                                    if 'trial' in info.metadata else ''))
        lines.append(f'Metadata:    {json.dumps(info.metadata, sort_keys=True)}')
    lines.append('Topics:')
    width = max((len(t.topic) for t in info.topics), default=5)
    type_width = max((len(t.msgtype) for t in info.topics), default=4)
    for topic in info.topics:
        row = f'  {topic.topic:<{width}}  {topic.msgtype:<{type_width}}  {topic.count:>10,} msgs'
        if topic.rate_hz is not None:
            row += f'  {topic.rate_hz:9.2f} Hz  jitter {topic.jitter_ms:7.3f} ms'
            row += '  gaps: ' + (', '.join(f'{length:.3f} s at {at:.3f} s' for at, length
                                           in topic.gaps[:gaps_shown])
                                 + (f' (+{topic.gap_count - gaps_shown} more)'
                                    if topic.gap_count > gaps_shown else '')
                                 if topic.gap_count else 'none')
        lines.append(row)
    lines += [f'note: {note}' for note in info.notes]
    return '\n'.join(lines)
