# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""A serial link that survives unplugging: reads bytes, reopens with backoff, never raises."""

from __future__ import annotations

from collections.abc import Callable
import enum
import time

import serial


class LinkState(enum.Enum):
    """Whether the port is open."""

    CONNECTED = 'connected'
    DISCONNECTED = 'disconnected'


class SerialLink:
    """Read from `port` at `baud`; on any error close, wait, reopen (backoff doubling to max).

    Args:
        port: device path (a udev symlink is best).
        baud: line rate.
        read_timeout_s: longest a read blocks, so the caller can stop promptly.
        backoff_s: first wait before reopening; doubles to `max_backoff_s`.
        opener: makes the port object (pyserial's `serial.Serial` by default).
        sleep: waits between attempts (injectable for tests).
    """

    def __init__(self, port: str, baud: int, *, read_timeout_s: float = 0.05,
                 backoff_s: float = 0.05, max_backoff_s: float = 2.0,
                 opener: Callable[..., serial.SerialBase] = serial.Serial,
                 sleep: Callable[[float], None] = time.sleep) -> None:
        self.port = port
        self.baud = baud
        self._timeout = read_timeout_s
        self._initial_backoff = backoff_s
        self._max_backoff = max_backoff_s
        self._backoff = backoff_s
        self._opener = opener
        self._sleep = sleep
        self._serial: serial.SerialBase | None = None
        self.state = LinkState.DISCONNECTED
        self.connects = 0
        self.disconnects = 0
        self.last_error = ''

    def read(self) -> bytes:
        """Return the bytes available now (b'' while disconnected or idle)."""
        if self._serial is None and not self._open():
            return b''
        try:
            waiting = self._serial.in_waiting
            data = self._serial.read(max(1, waiting))
        except (serial.SerialException, OSError, TypeError) as err:
            # pyserial reports an unplugged device as 'device reports readiness to read
            # but returned no data' or an OSError (EIO) from the fd.
            self._drop(f'read failed: {err}')
            return b''
        return data

    def close(self) -> None:
        """Close the port; safe to call twice."""
        if self._serial is not None:
            try:
                self._serial.close()
            except (serial.SerialException, OSError):
                pass
        self._serial = None
        self.state = LinkState.DISCONNECTED

    def _open(self) -> bool:
        try:
            self._serial = self._opener(self.port, self.baud, timeout=self._timeout)
        except (serial.SerialException, OSError, ValueError) as err:
            self.last_error = f'cannot open {self.port}: {err}'
            self._sleep(self._backoff)
            self._backoff = min(self._backoff * 2.0, self._max_backoff)
            return False
        self.state = LinkState.CONNECTED
        self.connects += 1
        self._backoff = self._initial_backoff
        return True

    def _drop(self, reason: str) -> None:
        self.last_error = reason
        self.disconnects += 1
        self.close()
