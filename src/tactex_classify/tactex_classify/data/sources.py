# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Where a recording's messages are: rosbag2 folders, ROS 1 bags, lone MCAP and sqlite3 files.

A recording is one of:
- a rosbag2 folder (its metadata.yaml; sqlite3 or MCAP storage, zstd in file or message mode);
- a rosbag2 folder that lost its metadata.yaml: its storage files are read as they are;
- a folder of part bags (`part_0000/`, ...: the recorder's), read one after the other;
- a ROS 1 bag (`.bag`, format 2.0), a lone `.mcap` or a lone `.db3` file.

Each part is opened by rosbags' AnyReader (no bag format is parsed here) after the checks
that keep a reader from blocking or inflating without bound (`check_part`,
`tactex_classify.data.inflation`). What rosbags cannot read is explained by `explain`:
the file, what is wrong with it and the fix.
"""

from __future__ import annotations

from collections.abc import Callable, Collection, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
import re

from tactex_classify.data import inflation
from tactex_classify.errors import BagError
from tactex_common.errors import RefusedFileError
from tactex_common.files import check_regular
from tactex_common.interfaces import typestore
from tactex_common.naming import natural_sorted

PART_PREFIX = 'part_'
MAX_METADATA_BYTES = 16 * 1024**2  # a bag's metadata.yaml
LOGGED_PAST_INT64 = ('a message was logged past int64 nanoseconds (the year 2262): the file '
                     'is damaged')
STORAGE_SUFFIXES = ('.mcap', '.db3')  # rosbag2 storage files
FILE_KINDS = {'.bag': 'ROS 1 bag', '.mcap': 'MCAP file', '.db3': 'rosbag2 sqlite3 file'}
UNINDEXED_SUFFIX = '.bag.active'  # a ROS 1 bag whose recorder never closed it


def is_recording(path: Path) -> bool:
    """True for a recording (see the module docstring), even one that turns out unreadable."""
    path = Path(path)
    if path.is_dir():
        return ((path / 'metadata.yaml').is_file() or any(path.glob(f'{PART_PREFIX}*/'))
                or _lost_metadata(path))
    return path.suffix in FILE_KINDS or path.name.endswith(UNINDEXED_SUFFIX)


def _lost_metadata(folder: Path) -> bool:
    """A rosbag2 folder without metadata.yaml: storage files named after it, or just one."""
    storage = [p for p in folder.iterdir() if p.suffix in STORAGE_SUFFIXES]
    if not storage or any(p.suffix == '.bag' or p.is_dir() and is_recording(p)
                          for p in folder.iterdir()):
        return False
    split = re.compile(re.escape(folder.name) + r'(_\d+)?')
    return len(storage) == 1 or all(split.fullmatch(p.stem) for p in storage)


def bag_parts(path: Path) -> list[Path]:
    """What AnyReader opens for a recording, one after the other, in natural order.

    Raises:
        BagError: not a recording.
    """
    path = Path(path)
    if not path.exists():
        raise BagError(f'{path}: does not exist')
    if not is_recording(path):
        raise BagError(f'{path}: not a recording (a rosbag2 folder, a folder of part bags, '
                       'or a .bag, .mcap or .db3 file)')
    if not path.is_dir():
        return [path]
    parts = natural_sorted(path.glob(f'{PART_PREFIX}*/'))
    if parts:
        return [unit for part in parts for unit in _units(part)]
    return _units(path)


def _units(folder: Path) -> list[Path]:
    if (folder / 'metadata.yaml').is_file() or not folder.is_dir():
        return [folder]
    return natural_sorted(p for p in folder.iterdir() if p.suffix in STORAGE_SUFFIXES)


def storage_files(part: Path) -> list[Path]:
    """A part's storage files: a file part itself; a folder's .mcap, .db3 and .zstd files."""
    if not part.is_dir():
        return [part]
    return sorted(p for p in part.iterdir()
                  if p.suffix in STORAGE_SUFFIXES or p.name.endswith('.zstd'))


def kind(part: Path) -> str:
    """What a part is, in words."""
    if part.is_dir():
        storage = {p.suffix for p in storage_files(part)}
        return 'rosbag2 folder' + (f' ({", ".join(sorted(storage))})' if storage else '')
    return FILE_KINDS.get(part.suffix, 'file')


def check_part(part: Path) -> None:
    """Refuse what no reader should open: FIFOs, unindexed bags, empty or oversized metadata.

    Raises:
        RefusedFileError, BagError: naming the file and the fix.
    """
    if part.name.endswith(UNINDEXED_SUFFIX):
        raise BagError(f'{part}: an unindexed ROS 1 bag (still .active: its recorder never '
                       'closed it); run `rosbag reindex` on it on a ROS 1 machine and rename '
                       'it to .bag')
    files = list(part.iterdir()) if part.is_dir() else [part]
    for item in files:
        if item.name == 'metadata.yaml':
            check_regular(item, max_bytes=MAX_METADATA_BYTES)
        elif item.suffix in FILE_KINDS or item.name.endswith('.zstd'):
            if check_regular(item) == 0:
                raise BagError(f'{item}: empty file')


class UnreadablePart(BagError):
    """A part of a recording no reader can read; `reason` says what is wrong and the fix."""

    def __init__(self, part: Path, reason: str) -> None:
        super().__init__(f'{part}: cannot read: {reason}')
        self.reason = reason


def reason(err: BagError) -> str:
    """Why a part was refused: an UnreadablePart's reason, else the whole message."""
    return err.reason if isinstance(err, UnreadablePart) else str(err)


@contextmanager
def open_part(part: Path, *, readable: Callable[[object], bool] | None = None):
    """An open AnyReader on one part; its failures become one UnreadablePart.

    Bags without type definitions (ROS 2 Humble's) decode with the standard types and
    tactex_msgs, read from the package's .msg files. With `readable`, a ROS 1 bag's
    index is read only for the connections it accepts (the others' messages cannot be
    read; their counts and times stay: `tactex_classify.data.ros1_index`).
    """
    from rosbags.highlevel import AnyReader

    inflation.install()
    try:
        check_part(part)
        reader = AnyReader([part], default_typestore=typestore())
        if readable is not None and not reader.is2:
            from tactex_classify.data.ros1_index import PartialIndexReader
            reader.readers = [PartialIndexReader(part, readable)]
        reader.open()
    except Exception as err:  # noqa: BLE001 - rosbags raises many unrelated types
        raise UnreadablePart(part, explain(err, part)) from err
    try:
        yield reader
    finally:
        reader.close()


def read_messages(reader, part: Path, connections: Sequence) -> Iterator[tuple]:
    """`reader.messages` of `connections` in logged order, failures as one UnreadablePart.

    No connection gives no message (rosbags reads every message for an empty list). What
    the caller does with a message is outside the error mapping.
    """
    if not connections:
        return
    messages = reader.messages(connections=connections)
    while True:
        try:
            item = next(messages)
        except StopIteration:
            return
        except Exception as err:  # noqa: BLE001 - rosbags raises many unrelated types
            raise UnreadablePart(part, explain(err, part)) from err
        yield item


def decoded_messages(part: Path, topics: Collection[str]) -> Iterator[tuple[str, int, object]]:
    """(topic, log time, decoded message) of one part's `topics`, in logged order.

    Raises:
        UnreadablePart: the part cannot be opened, or a message cannot be read or decoded.
    """
    with open_part(part) as reader:
        connections = [c for c in reader.connections if c.topic in topics]
        for connection, log_ns, raw in read_messages(reader, part, connections):
            try:
                message = reader.deserialize(raw, connection.msgtype)
            except Exception as err:  # noqa: BLE001 - rosbags raises many unrelated types
                raise UnreadablePart(part, explain(err, part)) from err
            yield connection.topic, log_ns, message


def explain(err: Exception, part: Path) -> str:
    """What is wrong with a part rosbags failed on, and the fix, in one sentence."""
    if isinstance(err, (RefusedFileError, BagError, inflation.InflationError)):
        return str(err).replace(f'{part}: ', '').replace(f'{part} ', 'it ')
    text = ' '.join(str(err).replace(str(part), part.name).split()).strip(' :.')
    storage = {part.suffix} | ({p.suffix for p in part.iterdir()} if part.is_dir() else set())
    if 'seems to be empty' in text:
        return 'empty file'
    if '.bag' in storage and ('magic is invalid' in text or isinstance(err, UnicodeError)):
        return 'not a ROS 1 bag (it does not start with "#ROSBAG V2.0")'
    if 'metadata.yaml' in text or 'Invalid bag metadata' in text or 'files are missing' in text:
        return metadata_problem(text)
    if '.bag' in storage and ('index' in text or 'Header could not be read' in text
                              or 'requested' in text):
        return ('a truncated or unindexed ROS 1 bag (its index is missing or damaged); run '
                '`rosbag reindex` on it on a ROS 1 machine')
    if '.mcap' in storage and 'end magic is invalid' in text:
        return 'a truncated MCAP file (it ends before its footer: it was never closed)'
    if '.mcap' in storage and 'Truncated record' in text:
        return ('a truncated or damaged MCAP file (a record runs past the end of the file); '
                'copy it again from where it was recorded')
    if '.mcap' in storage and 'File magic is invalid' in text:
        return 'not an MCAP file (it does not start with the MCAP magic)'
    if 'Profile is not ros2' in text or 'Serialization format' in text:
        return non_ros_mcap(part)
    if 'database' in text.lower() and '.db3' not in storage and part.is_dir():
        return (f'its metadata.yaml names sqlite3 storage, the folder holds '
                f'{", ".join(sorted(s for s in storage if s)) or "no storage file"}: correct '
                'storage_identifier, or delete metadata.yaml and tactex reads the files present')
    if '.db3' in storage or 'database' in text.lower():
        return f'not a readable rosbag2 sqlite3 file ({text})'
    return f'{type(err).__name__}: {text}'


def metadata_problem(text: str) -> str:
    """What is wrong with a rosbag2 folder's metadata.yaml, and the fix, from rosbags' error."""
    fix = ('; restore it, or delete metadata.yaml and tactex reads the storage files the '
           'folder holds')
    if 'files are missing' in text:
        missing = re.search(r'\[(.*)\]', text)
        return (f'its metadata.yaml lists files the folder lacks '
                f'({missing.group(1) if missing else text}){fix}')
    if 'Could not load YAML' in text:
        line = re.search(r'line (\d+)', text)
        return (f"its metadata.yaml cannot be read as plain YAML"
                f"{f' (line {line.group(1)})' if line else ''}{fix}")
    return f'its metadata.yaml is empty or not a rosbag2 description{fix}'


def non_ros_mcap(path: Path) -> str:
    """Why an MCAP file holds no ROS 2 messages: its profile and message encodings."""
    from mcap.reader import make_reader

    encodings: set[str] = set()
    profile = ''
    try:
        with open(path, 'rb') as stream:
            reader = make_reader(stream)
            profile = reader.get_header().profile
            summary = reader.get_summary()
            channels = summary.channels.values() if summary else []
            encodings = {channel.message_encoding for channel in channels}
    except Exception:  # noqa: BLE001 - the encodings are a courtesy; the verdict stands
        pass
    found = (f'{", ".join(sorted(encodings))} messages' if encodings
             else 'messages of another encoding')
    return (f'an MCAP file of profile {profile or "(none)"} holding {found}, not ROS 2 (cdr); '
            'tactex reads ROS 2 and ROS 1 recordings: export or record it as ROS 2 messages')
