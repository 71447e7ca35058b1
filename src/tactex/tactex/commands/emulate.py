# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex emulate teensy|dynamixel`: protocol-exact hardware on a pseudo-terminal, with faults."""

from __future__ import annotations

import argparse
from contextlib import suppress
import math
import os
from pathlib import Path
import tempfile

from tactex.errors import CommandError
from tactex.options import check_input_file, input_path, integer, number, output_path, seed_value
from tactex_common.stopping import Stopped


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('device', choices=['teensy', 'dynamixel'], help='what to emulate')
    parser.add_argument('--rate', type=number(at_most=2000.0), default=120.0,
                        help='teensy: frames per second (0 < rate <= 2000)')
    parser.add_argument('--link', type=output_path,
                        help='stable path linked to the pty (default /tmp/tactex-teensy or '
                             '/tmp/tactex-dynamixel)')
    parser.add_argument('--motion', choices=['static', 'sway'], default='static',
                        help='signal source: motionless, or compliant sway + vibration')
    parser.add_argument('--replay', type=input_path, metavar='CSV',
                        help='replay a recording instead: CSV with t,ax,ay,az,gx,gy,gz,mx,my,mz,'
                             'baro[,temp] in SI units (overrides --motion)')
    parser.add_argument('--roll', type=number(above=None, at_least=-180.0, at_most=180.0),
                        default=0.0, help='static roll (deg)')
    parser.add_argument('--pitch', type=number(above=None, at_least=-90.0, at_most=90.0),
                        default=0.0, help='static pitch (deg)')
    parser.add_argument('--fault', action='append', default=[], metavar='KIND@S[:ARG]',
                        help='teensy: garbage@S:BYTES, crc@S:FRAMES, drop@S:FRAMES, '
                             'stall@S:SECONDS, disconnect@S:SECONDS; dynamixel: silence@S:ID, '
                             'answer@S:ID, corrupt@S:ID, overload@S:ID (repeatable)')
    parser.add_argument('--duration', type=number(), default=math.inf,
                        help='stop after this many seconds, stalls and disconnects included '
                             '(default: run until Ctrl-C)')
    parser.add_argument('--seed', type=seed_value, default=0, help='noise seed')
    parser.add_argument('--start-time-us', type=integer(0, 2**32 - 1), default=0,
                        help='device clock at start (e.g. 4294000000 to cross the wrap)')


def run(args: argparse.Namespace) -> int:
    """Open the pty, print its path, serve until done."""
    from tactex_common.errors import LinkError
    from tactex_common.pty_link import check_link_path

    default = 'tactex-dynamixel' if args.device == 'dynamixel' else 'tactex-teensy'
    args.link = args.link or Path(tempfile.gettempdir()) / default
    try:
        check_link_path(args.link)
    except LinkError as err:
        raise CommandError(f'--link {err}') from None
    if args.replay is not None:
        check_input_file(args.replay, '--replay')
    if args.device == 'dynamixel':
        return _run_dynamixel(args)
    from tactex_sensor.emulator import Fault, Motion, ReplaySource, SignalSource, TeensyEmulator

    try:
        faults = tuple(Fault.parse(spec) for spec in args.fault)
    except ValueError as err:
        raise CommandError(f'--fault: {err}') from None
    try:
        if args.replay:
            source = ReplaySource(args.replay)
        else:
            source = SignalSource(Motion(args.motion), roll_rad=math.radians(args.roll),
                                  pitch_rad=math.radians(args.pitch), seed=args.seed)
    except ValueError as err:
        raise CommandError(f'--replay: {err}') from None
    emulator = TeensyEmulator(args.link, args.rate, source, faults=faults,
                              start_time_us=args.start_time_us)
    with emulator:
        print(f'teensy emulator on {args.link} -> {os.path.realpath(args.link)} at '
              f'{args.rate:g} Hz; faults: {", ".join(args.fault) or "none"}', flush=True)
        with suppress(Stopped):  # a stop signal ends the run; the link is removed
            emulator.run(args.duration)
    print(f'sent {emulator.frames_sent} writes, {emulator.frames_overflowed} lost to a '
          'full or closed pty')
    return 0


DYNAMIXEL_FAULTS = ('silence', 'answer', 'corrupt', 'overload')


def _run_dynamixel(args: argparse.Namespace) -> int:
    """Serve a chain of five XM430-W350 (IDs 11-15) and apply faults on schedule."""
    import time

    from tactex_common.constants import SERVO_IDS
    from tactex_driver.servo_emulator import ServoChainEmulator

    schedule = []
    for spec in args.fault:
        kind, _, rest = spec.partition('@')
        at, _, servo = rest.partition(':')
        try:
            schedule.append((float(at), kind, int(servo)))
        except ValueError:
            schedule.append((math.nan, kind, -1))
        if kind not in DYNAMIXEL_FAULTS or not math.isfinite(schedule[-1][0]) \
                or schedule[-1][0] < 0:
            raise CommandError(f'--fault {spec!r}: expected KIND@SECONDS:ID with KIND one of '
                               f'{", ".join(DYNAMIXEL_FAULTS)} and SECONDS finite and >= 0')
    schedule.sort()
    unknown = sorted({servo for _, _, servo in schedule} - set(SERVO_IDS))
    if unknown:
        raise CommandError(f'--fault names servo(s) {unknown}, not on the chain '
                           f'{list(SERVO_IDS)}')
    with ServoChainEmulator(args.link) as emulator:
        print(f'dynamixel chain (XM430-W350, IDs {sorted(emulator.servos)}) on {args.link} -> '
              f'{os.path.realpath(args.link)}; faults: {", ".join(args.fault) or "none"}',
              flush=True)
        start = time.monotonic()
        actions = {'silence': lambda s: emulator.silence(s, True),
                   'answer': lambda s: emulator.silence(s, False),
                   'corrupt': emulator.corrupt_next_status, 'overload': emulator.overload}
        with suppress(Stopped):  # a stop signal ends the run; the link is removed
            while time.monotonic() - start < args.duration:
                while schedule and schedule[0][0] <= time.monotonic() - start:
                    _, kind, servo = schedule.pop(0)
                    actions[kind](servo)
                    print(f'{time.monotonic() - start:.2f} s: {kind} servo {servo}',
                          flush=True)
                time.sleep(0.01)
    return 0
