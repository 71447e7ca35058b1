# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""A raw pseudo-terminal behind a stable symlink: where the hardware emulators plug in."""

from __future__ import annotations

import os
from pathlib import Path
import secrets
import tty

from tactex_common.errors import LinkError

# Where pseudo-terminal slaves live: a symlink pointing here was made by an emulator.
PTY_DIRECTORY = '/dev/pts'


def check_link_path(link: Path) -> None:
    """Refuse a link path that holds anything but an emulator's pty symlink.

    A symlink into /dev/pts (even a dangling one left by a killed emulator) may be
    replaced; a regular file, a folder or a symlink elsewhere is never touched.

    Raises:
        LinkError: the path holds something else, or its folder does not exist.
    """
    link = Path(link)
    if not link.parent.is_dir():
        raise LinkError(f'{link.parent} is not a folder; choose a link path in an existing '
                        'folder')
    if link.is_symlink():
        if not os.readlink(link).startswith(f'{PTY_DIRECTORY}/'):
            raise LinkError(f'{link} is a symlink to {os.readlink(link)}, not to a pty; '
                            'choose another link path')
    elif link.exists():
        kind = 'folder' if link.is_dir() else 'file'
        raise LinkError(f'{link} is an existing {kind}; choose a link path that does not '
                        'exist (it is never replaced)')


class PtyLink:
    """The emulator's end of a pty (`master`), reachable by readers at `link`.

    The symlink is replaced atomically, so a reader that reopens `link` after a
    simulated unplug finds the new pty, as it would find a udev name again. Only a
    symlink to a pty is ever replaced or removed (`check_link_path`).
    """

    def __init__(self, link: Path) -> None:
        self.link = Path(link)
        self.master: int | None = None
        self._slave: int | None = None
        self._target: str | None = None

    def open(self, *, blocking: bool = True) -> int:
        """Create the pty in raw mode, point the link at it, return the master fd.

        Raises:
            LinkError: the link path holds something the emulator did not create.
        """
        check_link_path(self.link)
        master, slave = os.openpty()
        tty.setraw(slave)
        os.set_blocking(master, blocking)
        self.master, self._slave = master, slave
        self._target = os.ttyname(slave)
        temporary = self.link.with_name(f'.{self.link.name}.{secrets.token_hex(6)}')
        temporary.symlink_to(self._target)
        temporary.replace(self.link)
        return master

    def close(self) -> None:
        """Close both ends and remove the link if it still points at our pty; idempotent."""
        for fd in (self.master, self._slave):
            if fd is not None:
                os.close(fd)
        self.master = self._slave = None
        if self._target is not None and self.link.is_symlink() \
                and os.readlink(self.link) == self._target:
            self.link.unlink()
        self._target = None
