# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""A raw pseudo-terminal behind a stable symlink: where the hardware emulators plug in."""

from __future__ import annotations

import os
from pathlib import Path
import tty


class PtyLink:
    """The emulator's end of a pty (`master`), reachable by readers at `link`.

    The symlink is replaced atomically, so a reader that reopens `link` after a
    simulated unplug finds the new pty, as it would find a udev name again.
    """

    def __init__(self, link: Path) -> None:
        self.link = Path(link)
        self.master: int | None = None
        self._slave: int | None = None

    def open(self, *, blocking: bool = True) -> int:
        """Create the pty in raw mode, point the link at it, return the master fd."""
        master, slave = os.openpty()
        tty.setraw(slave)
        os.set_blocking(master, blocking)
        self.master, self._slave = master, slave
        temporary = self.link.with_name(self.link.name + '.tmp')
        temporary.unlink(missing_ok=True)
        temporary.symlink_to(os.ttyname(slave))
        temporary.replace(self.link)
        return master

    def close(self) -> None:
        """Close both ends and remove the link; safe to call twice."""
        for fd in (self.master, self._slave):
            if fd is not None:
                os.close(fd)
        self.master = self._slave = None
        self.link.unlink(missing_ok=True)
