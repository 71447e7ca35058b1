# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Every message's log time from an MCAP file's message indexes, without reading messages.

An indexed MCAP file (rosbag2's, Foxglove's, the `mcap` CLI's) follows each chunk with a
message index per channel: the log time and offset of each of the chunk's messages. The
`mcap` library finds them through the summary's chunk indexes and reads them, so a
recording's timing costs a read of some bytes per message instead of inflating and
walking every chunk. A file without a summary or without message indexes gives None:
its messages are read instead.
"""

from __future__ import annotations

from array import array
from collections.abc import Sequence
import io
from pathlib import Path
import struct


def log_times(files: Sequence[Path]) -> dict[str, array] | None:
    """Per topic, the log times the files' message indexes list (None: no usable index)."""
    from mcap.exceptions import McapError
    from mcap.reader import make_reader
    from mcap.records import MessageIndex
    from mcap.stream_reader import StreamReader

    times: dict[str, array] = {}
    try:
        for path in files:
            size = path.stat().st_size
            with open(path, 'rb') as stream:
                summary = make_reader(stream).get_summary()
                if summary is None or not summary.chunk_indexes:
                    return None
                topics = {key: channel.topic for key, channel in summary.channels.items()}
                for chunk in summary.chunk_indexes:
                    if not chunk.message_index_offsets:
                        return None
                    start = min(chunk.message_index_offsets.values())
                    stream.seek(start)
                    block = stream.read(max(0, min(chunk.message_index_length, size - start)))
                    records = StreamReader(io.BytesIO(block), skip_magic=True).records
                    for record in _until_end(records):
                        if isinstance(record, MessageIndex):
                            times.setdefault(topics[record.channel_id], array('q')).extend(
                                log_ns for log_ns, _ in record.records)
    except (McapError, OSError, KeyError, ValueError, struct.error):
        return None
    return times


def _until_end(records):
    """The records of a block, ending where its bytes end (the library raises there)."""
    from mcap.exceptions import EndOfFile

    while True:
        try:
            yield next(records)
        except (StopIteration, EndOfFile):
            return
