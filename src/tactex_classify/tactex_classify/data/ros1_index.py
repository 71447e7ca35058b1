# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""A ROS 1 bag opened for a few topics: only the chunks holding them are indexed.

rosbags' ROS 1 reader reads the index entry of every message when it opens a bag (about
10 s for a 1-hour 350 Hz recording: 3.8 million entries). What a summary needs (the
connections, and each connection's count, first and last time) is in the chunk
records at the end of the file, read in a fraction of a second. This reader, a
subclass of rosbags' own, reads every index entry of the chunks holding the wanted
connections' messages and none of the others'; the counts come from the chunk records,
so they stay true for every connection. Reading messages of a connection that was not
indexed is refused, never answered with nothing.
"""

from __future__ import annotations

from collections.abc import Callable, Collection

from rosbags.interfaces import Connection
from rosbags.rosbag1 import Reader


class PartialIndexReader(Reader):
    """The ROS 1 reader of rosbags, indexing only the connections `wanted` accepts."""

    def __init__(self, path, wanted: Callable[[Connection], bool]) -> None:
        super().__init__(path)
        self._wanted = wanted
        self._indexed_chunks: set[int] | None = None
        self.indexed: set[int] = set()  # ids of the connections whose messages can be read

    def open(self) -> None:
        """Open the bag, index the wanted connections' chunks, count every connection."""
        super().open()
        if self._indexed_chunks is None:  # a bag without chunks
            self._choose()
        counts: dict[int, int] = {}
        for chunk in self.chunk_infos:
            for connection_id, count in chunk.connection_counts.items():
                counts[connection_id] = counts.get(connection_id, 0) + count
        self.connections = [c._replace(msgcount=counts.get(c.id, 0)) for c in self.connections]

    def read_index_data(self, pos: int, indexes: dict) -> None:
        """Read a chunk's index entries only when it holds a wanted connection's messages."""
        if self._indexed_chunks is None:
            self._choose()
        if pos in self._indexed_chunks:
            super().read_index_data(pos, indexes)

    def _choose(self) -> None:
        """The wanted connections, and the chunks holding their messages."""
        self.indexed = {c.id for c in self.connections if self._wanted(c)}
        self._indexed_chunks = {chunk.pos for chunk in self.chunk_infos
                                if self.indexed & chunk.connection_counts.keys()}

    def messages(self, connections: Collection[Connection] = (), start: int | None = None,
                 stop: int | None = None):
        """Messages as rosbags reads them; refused for a connection that was not indexed."""
        refused = sorted({c.topic for c in connections or self.connections
                          if c.id not in self.indexed})
        if refused:
            raise ValueError(f'{", ".join(refused)} not opened for reading')
        return super().messages(connections, start, stop)
