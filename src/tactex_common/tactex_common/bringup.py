# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Hardware bring-up checks: their result, and the checks of a serial port's device node.

`tactex doctor` and `tactex launch` (without sim:=true) run the checks of the tactile
module (tactex_sensor.bringup), the servos (tactex_driver.bringup) and the ROS settings;
each check says what it found and, when it failed, the fix.
"""

from __future__ import annotations

from dataclasses import dataclass
import grp
import os
from pathlib import Path
import re
import stat

from tactex_common.files import file_kind

OK, WARN, FAIL = 'ok', 'warn', 'fail'
# Kernel names that change with the plug order; a udev rule gives a stable one.
UNSTABLE_NAME = re.compile(r'^/dev/tty(ACM|USB)\d+$')


@dataclass(frozen=True)
class Check:
    """One bring-up check: what was checked, its status (ok/warn/fail), what was found, the fix."""

    name: str
    status: str
    detail: str
    fix: str = ''

    @property
    def failed(self) -> bool:
        """Whether the check failed (a warning does not)."""
        return self.status == FAIL


def udev_rules() -> str:
    """Where the workspace's udev rules file is (tactex's share directory)."""
    from tactex_common.share import share_directory
    return str(share_directory('tactex') / 'config' / '99-tactex.rules')


def port_checks(port: str, what: str) -> list[Check]:
    """Whether the device node `port` exists, is a serial device and may be opened here.

    `what` names the device for the messages (e.g. 'Teensy'). A missing port or one this
    user may not open fails with the fix (the udev rule, the dialout group); a kernel
    name such as /dev/ttyACM0 passes with a warning to give it a stable udev name.
    """
    name = f'{what} port'
    path = Path(port)
    if not path.exists():
        return [Check(name, FAIL, f'{port} does not exist',
                      f'plug the {what} in and find its port (`ls /dev/serial/by-id/`, '
                      f'`dmesg | tail`); install {udev_rules()} to /etc/udev/rules.d/ for a '
                      'stable name')]
    mode = path.stat().st_mode
    if not stat.S_ISCHR(mode):
        return [Check(name, FAIL, f'{port} is not a serial device (a {file_kind(mode)})',
                      f'give the {what} device node, e.g. /dev/ttyACM0 or a udev link')]
    if not os.access(path, os.R_OK | os.W_OK):
        group = _group_name(path.stat().st_gid)
        member = group in _own_groups()
        fix = (f'log out and in again: you are in group {group} but this session is not'
               if member else f'sudo usermod -aG {group} $USER, then log out and in again '
               f'(or install {udev_rules()}, which makes the port 0666)')
        return [Check(name, FAIL, f'{port} is not readable and writable by this user '
                      f'(owner group {group})', fix)]
    checks = [Check(name, OK, f'{port} is a serial device this user may open')]
    if UNSTABLE_NAME.match(str(port)):
        checks.append(Check(f'{what} port name', WARN,
                            f'{port} is a kernel name that can change with the plug order',
                            f'install {udev_rules()} to /etc/udev/rules.d/ (`sudo udevadm '
                            'control --reload-rules && sudo udevadm trigger`) and use its '
                            'stable name'))
    return checks


def _group_name(gid: int) -> str:
    try:
        return grp.getgrgid(gid).gr_name
    except KeyError:
        return str(gid)


def _own_groups() -> set[str]:
    return {_group_name(gid) for gid in os.getgroups()}
