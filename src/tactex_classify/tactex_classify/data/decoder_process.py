# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""A recording's tactile messages decoded in a second process, while the caller uses them."""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager, suppress
import fcntl
import multiprocessing
from pathlib import Path
import signal

from tactex_classify.data.bags import ROLE_CHANNELS, sample_values
from tactex_classify.data.sources import decoded_messages, UnreadablePart
from tactex_classify.errors import BagError
from tactex_common.stamps import stamp_ns, stamp_or_log_ns

BATCH = 2048  # messages sent at once
SPAWN_FROM = 30_000  # messages (~80 s at 120 Hz): fewer decode faster here than spawning (~0.6 s)
POLL_S = 1.0  # seconds between checks that the decoder still runs
PIPE_BYTES = 1024**2  # the pipe holds this much (Linux's default limit): several batches


@contextmanager
def decoded_samples(path: Path, parts: Sequence[Path], by_topic: Mapping[str, str],
                    messages: int) -> Iterator[Iterator[tuple[str, int, int, object]]]:
    """(role, stamp, log time, data) of each message on a topic of `by_topic`, in logged order.

    A sensor role's data is its `sample_values` and its stamp the header's (or the log time,
    `stamp_or_log_ns`); 'active' gives its bool, 'metadata' its text, at their log time.
    From SPAWN_FROM `messages` on, `decoded_messages` runs in a spawned process (no torch or
    thread state forked) sending batches through a pipe of PIPE_BYTES: decoding overlaps
    the caller's work, a few batches ahead at most. Leaving the block ends that process.

    Args:
        path: the recording (named in errors).
        parts: its parts to read, in order.
        by_topic: topic -> role.
        messages: how many messages those topics hold, as the index says.

    Raises:
        UnreadablePart: a part cannot be read (as `decoded_messages` raises it).
        BagError: the decoder failed otherwise, or its process died (naming the recording).
    """
    if messages < SPAWN_FROM:
        yield _unbatched(_batches(parts, by_topic), path)
        return
    context = multiprocessing.get_context('spawn')
    receiver, sender = context.Pipe(duplex=False)
    with suppress(AttributeError, OSError):  # not Linux, or a lower limit: it evens out less
        fcntl.fcntl(receiver.fileno(), fcntl.F_SETPIPE_SZ, PIPE_BYTES)
    process = context.Process(target=_decode, args=(list(parts), dict(by_topic), sender),
                              name='tactex decoder', daemon=True)
    process.start()
    sender.close()  # the child's end only: the pipe ends when the child does
    try:
        yield _unbatched(_received(receiver, process, path), path)
    finally:
        receiver.close()
        process.terminate()
        process.join()


def _decode(parts: list[Path], by_topic: dict[str, str], sender) -> None:
    """The child: `_batches` into the pipe."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's, which ends this
    try:
        for batch in _batches(parts, by_topic):
            sender.send(batch)
    except BrokenPipeError:
        pass  # the parent stopped reading


def _batches(parts: Sequence[Path], by_topic: Mapping[str, str]) -> Iterator:
    """Lists of up to BATCH samples, then None, or at the end what stopped the decoding."""
    batch, part = [], None
    try:
        for part in parts:
            for topic, log_ns, message in decoded_messages(part, by_topic):
                role = by_topic[topic]
                if role in ROLE_CHANNELS:
                    batch.append((role, stamp_or_log_ns(stamp_ns(message.header.stamp), log_ns),
                                  log_ns, sample_values(role, message)))
                else:
                    batch.append((role, log_ns, log_ns,
                                  bool(message.data) if role == 'active' else message.data))
                if len(batch) == BATCH:
                    yield batch
                    batch = []
    except UnreadablePart as err:
        end = ('unreadable', part, err.reason)
    except BagError as err:
        end = ('bag', str(err))
    except Exception as err:  # noqa: BLE001 - reaches the caller as a BagError
        end = ('failed', f'{type(err).__name__}: {err}')
    else:
        end = None
    yield batch
    yield end


def _unbatched(batches: Iterator, path: Path) -> Iterator[tuple[str, int, int, object]]:
    """The samples of `_batches`' lists; what stopped them raised as the caller's error."""
    for batch in batches:
        if isinstance(batch, list):
            yield from batch
        elif batch is None:
            return
        elif batch[0] == 'unreadable':
            raise UnreadablePart(*batch[1:])
        elif batch[0] == 'bag':
            raise BagError(batch[1])
        else:
            raise BagError(f'{path}: decoding failed: {batch[1]}')


def _received(receiver, process, path: Path) -> Iterator:
    """What the child sends, until it ends; its death is a BagError, never a hang."""
    while True:
        while not receiver.poll(POLL_S):
            if not process.is_alive() and not receiver.poll():
                raise _stopped(process, path)
        try:
            batch = receiver.recv()
        except EOFError:
            raise _stopped(process, path) from None
        yield batch


def _stopped(process, path: Path) -> BagError:
    process.join(POLL_S)
    return BagError(f'{path}: the process decoding it stopped (exit code {process.exitcode})')
