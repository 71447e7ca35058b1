# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The `tactex` command line: one subcommand per job, each returning an exit code.

Bad input is normal: argument errors, the project's errors and the usual OS errors
end in one `error: ...` line on stderr and exit code 1, never a traceback.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from tactex.errors import CommandError
from tactex_classify.errors import ClassifyError
from tactex_common.errors import CommonError
from tactex_common.stopping import as_stopped, raise_on_stop_signals
from tactex_driver.errors import DriverError
from tactex_sim.errors import SimError

# Subcommand name -> module under tactex.commands with add_arguments(parser) and run(args).
COMMANDS = {
    'description': 'Show the robot description, write its URDF or MJCF, check the URDF.',
    'demo': 'Run the whole pipeline in simulation through the launched nodes (make demo).',
    'doctor': 'Hardware bring-up checks (ports, Teensy stream, servos, ROS settings) with fixes.',
    'emulate': 'Emulate hardware on a pseudo-terminal (teensy, dynamixel).',
    'sim': 'Simulation jobs: collect a synthetic texture dataset.',
    'record': 'Record the tactile topics, joint states and sweep segments (rosbag2, mcap).',
    'bag': 'What recordings hold (rosbag2, ROS 1, MCAP): bag info.',
    'convert': 'Turn recordings (rosbag2, ROS 1, MCAP) into a windowed dataset (.npz + JSON).',
    'import': 'Import datasets recorded elsewhere (MUN pickles, CSV folders).',
    'train': 'Cross-validate a texture model (honest and leaky CV side by side), report.',
    'compare': 'Compare models x windows x seeds x folds on Ray (resumable), with the table.',
    'export': "Write a checkpoint's model as ONNX (for classifier_node without torch).",
    'predict': 'Apply a checkpoint to recordings or datasets: what classifier_node decides, when.',
    'plot': "Draw a recording's channels, or a run's plots again from its kept numbers.",
    'launch': "Run a launch file's nodes as supervised processes (no ROS 2 launch needed).",
    'probe': 'Send a Probe goal: progress, the contacts found, --score against the simulator.',
    'sweep': 'Send a Sweep goal along the probed pathway: progress, contact and speed.',
    'identify': 'Send an Identify goal: movements chosen one sweep at a time until decided.',
    'param': "List, get or set a running node's parameters (no ros2 CLI needed).",
    'status': "One table of every running node's diagnostics (rates, latency, drops, state).",
    'watch': 'Show the live texture estimates, their evidence and decisions.',
    'view': 'The live system in Foxglove (tactile channels, arm, pathway, estimates).',
    'report': 'Reports across the system: accuracy-time (what accuracy costs in time), '
              'identification (active movement choice replayed on held-out recordings).',
}


# Subcommands whose module name differs (`import` is a Python keyword).
MODULES = {'import': 'import_data'}
# What a user can cause: reported in one line, never as a traceback.
USER_ERRORS = (CommandError, ClassifyError, CommonError, DriverError, SimError, OSError)


class CommandParser(argparse.ArgumentParser):
    """An argument parser whose errors are one `error:` line and exit code 1."""

    def error(self, message: str):
        """Print `error: MESSAGE; see ... --help` and exit with 1."""
        self.exit(1, f'error: {message}; see `{self.prog} --help`\n')


def build_parser() -> argparse.ArgumentParser:
    """Return the parser with every subcommand registered."""
    parser = CommandParser(
        prog='tactex', description='Texture recognition by touch on a ROS 2 arm.')
    subparsers = parser.add_subparsers(dest='command', required=True, metavar='COMMAND')
    for name, help_text in COMMANDS.items():
        module = importlib.import_module(f'tactex.commands.{MODULES.get(name, name)}')
        sub = subparsers.add_parser(name, help=help_text, description=help_text)
        module.add_arguments(sub)
        sub.set_defaults(run=module.run, parser=sub)
    return parser


def parsed(parser: argparse.ArgumentParser, argv: list[str] | None) -> argparse.Namespace:
    """The arguments; ones the subcommand does not know are its error, with its --help."""
    args, unknown = parser.parse_known_args(argv)
    if unknown:
        args.parser.error(f'unrecognized arguments: {" ".join(unknown)}')
    return args


def describe(error: BaseException) -> str:
    """One line for an error (OS errors as `PATH: reason`)."""
    if isinstance(error, OSError) and not isinstance(error, CommonError) and error.strerror:
        where = f'{error.filename}: ' if error.filename else ''
        return f'{where}{error.strerror}'
    return ' '.join(str(error).split()) or type(error).__name__


def main(argv: list[str] | None = None) -> int:
    """Parse `argv`, run the subcommand and return its exit code.

    SIGINT, SIGTERM and SIGHUP stop every subcommand (also when SIGINT was inherited as
    ignored); one that runs until stopped returns 0, any other reports the signal.
    """
    raise_on_stop_signals()
    args = parsed(build_parser(), argv)
    return guarded(lambda: args.run(args))


def guarded(run) -> int:
    """`run()`'s exit code; a stop signal or a user error as one `error:` line and its code.

    The caller has installed `raise_on_stop_signals()`.
    """
    try:
        return int(run())
    except KeyboardInterrupt as interrupt:
        stopped = as_stopped(interrupt)
        print(f'error: stopped by {stopped}', file=sys.stderr)
        return stopped.exit_code
    except USER_ERRORS as error:
        print(f'error: {describe(error)}', file=sys.stderr)
        return 1


if __name__ == '__main__':
    sys.exit(main())
