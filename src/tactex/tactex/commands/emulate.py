# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex emulate teensy|dynamixel`: protocol-exact hardware on a pseudo-terminal, with faults."""

from __future__ import annotations

import argparse
import math
import os
from pathlib import Path
import signal
import sys
import tempfile


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('device', choices=['teensy', 'dynamixel'], help='what to emulate')
    parser.add_argument('--rate', type=float, default=120.0, help='teensy: frames per second')
    parser.add_argument('--link', type=Path,
                        help='stable path linked to the pty (default /tmp/tactex-teensy or '
                             '/tmp/tactex-dynamixel)')
    parser.add_argument('--motion', choices=['static', 'sway'], default='static',
                        help='signal source: motionless, or compliant sway + vibration')
    parser.add_argument('--replay', type=Path, metavar='CSV',
                        help='replay a recording instead: CSV with t,ax,ay,az,gx,gy,gz,mx,my,mz,'
                             'baro[,temp] in SI units (overrides --motion)')
    parser.add_argument('--roll', type=float, default=0.0, help='static roll (deg)')
    parser.add_argument('--pitch', type=float, default=0.0, help='static pitch (deg)')
    parser.add_argument('--fault', action='append', default=[], metavar='KIND@S[:ARG]',
                        help='teensy: garbage@S:BYTES, crc@S:FRAMES, drop@S:FRAMES, '
                             'stall@S:SECONDS, disconnect@S:SECONDS; dynamixel: silence@S:ID, '
                             'answer@S:ID, corrupt@S:ID, overload@S:ID (repeatable)')
    parser.add_argument('--duration', type=float, default=math.inf,
                        help='stop after this many seconds (default: run until Ctrl-C)')
    parser.add_argument('--seed', type=int, default=0, help='noise seed')
    parser.add_argument('--start-time-us', type=int, default=0,
                        help='device clock at start (e.g. 4294000000 to cross the wrap)')


def run(args: argparse.Namespace) -> int:
    """Open the pty, print its path, serve until done."""
    # SIGTERM (a launcher, a test harness) unwinds like Ctrl-C, so the link is removed.
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(0))
    if args.device == 'dynamixel':
        return _run_dynamixel(args)
    args.link = args.link or Path(tempfile.gettempdir()) / 'tactex-teensy'
    from tactex_sensor.emulator import Fault, Motion, ReplaySource, SignalSource, TeensyEmulator

    try:
        faults = tuple(Fault.parse(spec) for spec in args.fault)
        if args.replay:
            source = ReplaySource(args.replay)
        else:
            source = SignalSource(Motion(args.motion), roll_rad=math.radians(args.roll),
                                  pitch_rad=math.radians(args.pitch), seed=args.seed)
        emulator = TeensyEmulator(args.link, args.rate, source, faults=faults,
                                  start_time_us=args.start_time_us)
    except (ValueError, OSError) as err:
        print(f'error: {err}', file=sys.stderr)
        return 1
    with emulator:
        print(f'teensy emulator on {args.link} -> {os.path.realpath(args.link)} at '
              f'{args.rate:g} Hz; faults: {", ".join(args.fault) or "none"}', flush=True)
        emulator.run(args.duration)
    print(f'sent {emulator.frames_sent} writes, {emulator.frames_overflowed} lost to a '
          'full or closed pty')
    return 0


DYNAMIXEL_FAULTS = ('silence', 'answer', 'corrupt', 'overload')


def _run_dynamixel(args: argparse.Namespace) -> int:
    """Serve a chain of five XM430-W350 (IDs 11-15) and apply faults on schedule."""
    import time

    from tactex_driver.servo_emulator import ServoChainEmulator

    link = args.link or Path(tempfile.gettempdir()) / 'tactex-dynamixel'
    schedule = []
    for spec in args.fault:
        kind, _, rest = spec.partition('@')
        at, _, servo = rest.partition(':')
        try:
            if kind not in DYNAMIXEL_FAULTS:
                raise ValueError
            schedule.append((float(at), kind, int(servo)))
        except ValueError:
            print(f'error: bad fault {spec!r}: expected KIND@SECONDS:ID with KIND one of '
                  f'{", ".join(DYNAMIXEL_FAULTS)}', file=sys.stderr)
            return 1
    schedule.sort()
    with ServoChainEmulator(link) as emulator:
        if any(servo not in emulator.servos for _, _, servo in schedule):
            print(f'error: fault names a servo not on the chain {sorted(emulator.servos)}',
                  file=sys.stderr)
            return 1
        print(f'dynamixel chain (XM430-W350, IDs {sorted(emulator.servos)}) on {link} -> '
              f'{os.path.realpath(link)}; faults: {", ".join(args.fault) or "none"}',
              flush=True)
        start = time.monotonic()
        actions = {'silence': lambda s: emulator.silence(s, True),
                   'answer': lambda s: emulator.silence(s, False),
                   'corrupt': emulator.corrupt_next_status, 'overload': emulator.overload}
        while time.monotonic() - start < args.duration:
            while schedule and schedule[0][0] <= time.monotonic() - start:
                _, kind, servo = schedule.pop(0)
                actions[kind](servo)
                print(f'{time.monotonic() - start:.2f} s: {kind} servo {servo}', flush=True)
            time.sleep(0.01)
    return 0
