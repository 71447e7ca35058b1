# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex record`: run the recorder node with its settings given on the command line.

The settings reach `recorder_node` in a parameter file (an unlinked temporary file the
child reads through /dev/fd), never as `-p name:=value` overrides, so a label may be
any text: overrides are parsed as YAML and `true`, `3`, `a: b` or `'` would change type
or break. The node dies with this command: it gets SIGTERM when this process ends
however it ends (Linux parent-death signal, SIGKILL included), and SIGINT, SIGTERM or
SIGHUP given to this command are passed on, then awaited so the last part bag closes.
"""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path
import shutil
import signal
import subprocess
import sys
import tempfile

from tactex.errors import CommandError
from tactex.options import check_output_folder, number, output_path, trial_id
from tactex_common.stopping import on_stop_signals

PR_SET_PDEATHSIG = 1  # linux/prctl.h
RESERVED_KEYS = ('label', 'trial', 'surface')


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('--out', type=output_path, required=True, help='recording directory (new)')
    parser.add_argument('--label', help='texture class (any text)')
    parser.add_argument('--trial', type=trial_id, help='recording / trajectory id')
    parser.add_argument('--surface', help='surface, e.g. uneven')
    parser.add_argument('--meta', action='append', default=[], metavar='KEY=VALUE',
                        help='more metadata (repeatable)')
    parser.add_argument('--split-s', type=number(at_most=3600.0), default=1.0,
                        help='seconds per part bag: the most a crash can lose (1.0)')
    parser.add_argument('--compress', action='store_true', help='zstd-compress messages')
    parser.add_argument('--use-sim-time', action='store_true',
                        help="stamp what has no header (sweep/active, the metadata) with the "
                             "simulation's /clock, as a simulated system's IMU stamps are; "
                             'without it, the wall clock')


def metadata_of(args: argparse.Namespace) -> dict:
    """The recording's metadata from the options.

    Raises:
        CommandError: a --meta item that is not KEY=VALUE, or that repeats a key or sets
            one that has its own option.
    """
    metadata: dict = {key: value for key, value in (
        ('label', args.label), ('trial', args.trial), ('surface', args.surface))
        if value is not None}
    for item in args.meta:
        key, sep, value = item.partition('=')
        key = key.strip()
        if not sep or not key:
            raise CommandError(f'--meta {item!r} is not KEY=VALUE')
        if key in RESERVED_KEYS:
            raise CommandError(f'--meta {item!r}: give {key} with --{key}')
        if key in metadata:
            raise CommandError(f'--meta gives {key!r} twice')
        metadata[key] = value
    return metadata


def yaml_quoted(text: str) -> str:
    """`text` as a YAML double-quoted scalar: every character survives, nothing is parsed.

    Raises:
        CommandError: the text holds characters that are not Unicode (undecodable bytes).
    """
    out = []
    for char in text:
        code = ord(char)
        if 0xD800 <= code <= 0xDFFF:
            raise CommandError(f'{text!r} holds bytes that are not valid text (UTF-8)')
        if char in '"\\':
            out.append('\\' + char)
        elif code < 0x20 or 0x7F <= code <= 0x9F or code in (0xFEFF, 0xFFFE, 0xFFFF):
            out.append(f'\\u{code:04x}')
        else:
            out.append(char)
    return '"' + ''.join(out) + '"'


def parameter_file(out: Path, metadata: dict, split_s: float, compress: bool,
                   use_sim_time: bool = False) -> str:
    """The recorder node's parameters as a ROS 2 parameter file."""
    return ('recorder_node:\n  ros__parameters:\n'
            f'    output: {yaml_quoted(str(out))}\n'
            f'    metadata: {yaml_quoted(json.dumps(metadata, ensure_ascii=False))}\n'
            f'    split_s: {split_s!r}\n'
            f'    compress: {"true" if compress else "false"}\n'
            f'    use_sim_time: {"true" if use_sim_time else "false"}\n')


def _die_with_parent():
    """A preexec function: the child gets SIGTERM when this process ends (Linux)."""
    if not sys.platform.startswith('linux'):
        return None
    import ctypes
    prctl = ctypes.CDLL(None, use_errno=True).prctl
    parent = os.getpid()

    def setup() -> None:
        prctl(PR_SET_PDEATHSIG, signal.SIGTERM)
        if os.getppid() != parent:  # the parent died before prctl took effect
            os.kill(os.getpid(), signal.SIGTERM)
    return setup


def run(args: argparse.Namespace) -> int:
    """Start recorder_node in the foreground until Ctrl-C or SIGTERM."""
    from tactex.launching.environment import ros_environment

    check_output_folder(args.out)
    metadata = metadata_of(args)
    parameters = parameter_file(args.out.absolute(), metadata, args.split_s, args.compress,
                                args.use_sim_time)
    executable = shutil.which('recorder_node') or str(Path(sys.executable).parent /
                                                      'recorder_node')
    with tempfile.TemporaryFile('w+', encoding='utf-8') as handle:
        handle.write(parameters)
        handle.flush()
        fd = handle.fileno()
        process = subprocess.Popen(
            [executable, '--ros-args', '--params-file', f'/dev/fd/{fd}'],
            env=ros_environment(), pass_fds=(fd,), preexec_fn=_die_with_parent())
        return _wait(process)


def _wait(process: subprocess.Popen) -> int:
    """Wait for the node, passing SIGINT, SIGTERM and SIGHUP on; never leave it running.

    The first stop signal is passed on as it came (the node closes its last part bag);
    a second one kills the node.
    """
    stops = []

    def forward(signum: int) -> None:
        stops.append(signum)
        if process.poll() is None:
            process.send_signal(signum if len(stops) == 1 else signal.SIGKILL)

    try:
        with on_stop_signals(forward):
            code = process.wait()
        return 0 if code in (0, -signal.SIGINT, -signal.SIGTERM, -signal.SIGHUP) else 1
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
