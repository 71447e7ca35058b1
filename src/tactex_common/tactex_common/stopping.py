# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""How every long-running tactex process stops: SIGINT, SIGTERM or SIGHUP, however started.

A process started in the background of a non-interactive shell, under nohup, systemd or
a CI runner inherits SIGINT as *ignored*; Python then installs no KeyboardInterrupt
handler and a Ctrl-C-only process can never be stopped gently. Every tactex command and
node therefore installs its handlers for all three stop signals explicitly.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
import signal

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


class Stopped(KeyboardInterrupt):
    """A stop signal arrived; a KeyboardInterrupt, so code written for Ctrl-C handles it.

    Attributes:
        signum: the signal's number.
    """

    def __init__(self, signum: int) -> None:
        self.signum = signum
        super().__init__(signal.Signals(signum).name)

    @property
    def exit_code(self) -> int:
        """The shell's code for a process ended by this signal (128 + its number)."""
        return 128 + self.signum


_received: list[int] = []  # the stop signals that arrived, latest last


def _raise_stopped(signum: int, _frame) -> None:
    _received.append(signum)
    raise Stopped(signum)


def as_stopped(interrupt: KeyboardInterrupt) -> Stopped:
    """The stop an interrupt stands for, also one a library re-raised as a plain one.

    Ray, for one, swallows the `Stopped` raised inside its wait and raises a bare
    KeyboardInterrupt instead; the signal that arrived last is the one meant (SIGINT
    when none did: Python's own Ctrl-C handler).
    """
    if isinstance(interrupt, Stopped):
        return interrupt
    return Stopped(_received[-1] if _received else signal.SIGINT)


def raise_on_stop_signals() -> None:
    """From now on, each stop signal raises `Stopped` in the main thread."""
    for signum in STOP_SIGNALS:
        signal.signal(signum, _raise_stopped)


@contextmanager
def on_stop_signals(handler: Callable[[int], None]) -> Iterator[None]:
    """Within the block, each stop signal calls `handler(signum)`; restored afterwards.

    The handler runs in the main thread between bytecodes: it should only set a flag or
    pass the signal on.
    """
    previous = {signum: signal.signal(signum, lambda number, _frame: handler(number))
                for signum in STOP_SIGNALS}
    try:
        yield
    finally:
        for signum, old in previous.items():
            # None: the old handler was not Python's (a C library's); the default then.
            signal.signal(signum, signal.SIG_DFL if old is None else old)
