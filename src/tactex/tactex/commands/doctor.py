# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex doctor`: hardware bring-up checks, each with its fix.

The Teensy's port (exists, a serial device this user may open, a stable udev name), its
stream (frames at the firmware's rate, CRC and protocol version, every chip answering),
the servos (IDs, baud rate, models, supply, temperature, latched errors, position limits
against the URDF) and the ROS settings (domain, discovery, middleware). Nothing is
written to the hardware. Exit 1 when a check fails; warnings pass. The ports and rates
default to config/sensor.yaml and config/driver.yaml.
"""

from __future__ import annotations

import argparse

from tactex.options import integer, number, text

PARTS = ('sensor', 'arm', 'ros')


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('--sensor-port', type=text, metavar='DEV',
                        help="the Teensy's serial device (default: config/sensor.yaml port)")
    parser.add_argument('--sensor-baud', type=integer(1), metavar='BAUD',
                        help='its line rate (default: config/sensor.yaml baud)')
    parser.add_argument('--sensor-rate', type=number(at_most=2000.0), default=120.0,
                        metavar='HZ', help='frames per second the firmware sends (120 after '
                                           'power-on; TACTEX_RATE_HZ when built otherwise)')
    parser.add_argument('--listen', type=number(at_most=60.0), default=2.0, metavar='S',
                        help='seconds to listen to the Teensy (2)')
    parser.add_argument('--arm-port', type=text, metavar='DEV',
                        help="the servo adapter's serial device (default: config/driver.yaml "
                             'port)')
    parser.add_argument('--arm-baud', type=integer(1), metavar='BAUD',
                        help="the servos' line rate (default: config/driver.yaml baud)")
    parser.add_argument('--only', choices=PARTS, action='append', metavar='PART',
                        help=f'check only this part ({", ".join(PARTS)}; repeatable)')


def run(args: argparse.Namespace) -> int:
    """Run the checks; print them; 1 when one failed."""
    from tactex.bringup import arm_checks, configured_hardware, lines, ros_checks, sensor_checks
    hardware = configured_hardware()
    parts = args.only or PARTS
    checks = []
    if 'sensor' in parts:
        checks += sensor_checks(args.sensor_port or hardware.sensor_port,
                                args.sensor_baud or hardware.sensor_baud, args.sensor_rate,
                                args.listen)
    if 'arm' in parts:
        checks += arm_checks(args.arm_port or hardware.arm_port,
                             args.arm_baud or hardware.arm_baud, hardware.servo_ids)
    if 'ros' in parts:
        checks += ros_checks()
    for line in lines(checks):
        print(line)
    failed = sum(check.failed for check in checks)
    print(f'{len(checks)} checks: {failed} failed' if failed else
          f'{len(checks)} checks passed' + (' (see the warnings)' if any(
              check.status == 'warn' for check in checks) else ''))
    return 1 if failed else 0
