# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex sweep`: send a Sweep goal, show its progress, print how well it slid.

Like `ros2 action send_goal --feedback sweep tactex_msgs/action/Sweep ...` without the
`ros2` CLI. Without `--pathway` the goal carries no contacts and sweep_node slides along
the pathway probe_node broadcast (`tactex probe` first); `--pathway FILE` sends a saved
one (probe_node's pathway_file). `--record` has the node record the sweep to a bag for a
labelled dataset. Ctrl-C cancels the goal; the node lifts the edge off before it ends.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from tactex.errors import CommandError
from tactex.options import add_goal_options, check_input_file, input_path, number, text, trial_id
from tactex_common.constants import SLIDING_SPEED_M_S
from tactex_trajectory.poses import PoseSettings


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    pose = PoseSettings()  # (the planner's SweepSettings imports scipy: 0.6 s at start-up)
    parser.add_argument('--pathway', type=input_path, metavar='FILE',
                        help='a pathway file to slide along (default: the one probe_node '
                             'broadcast on probe/pathway)')
    parser.add_argument('--speed', type=number(), default=SLIDING_SPEED_M_S,
                        metavar='M_S', help='sliding speed of the edge, m/s '
                                            f'(default {SLIDING_SPEED_M_S:g}, the original)')
    parser.add_argument('--edge-offset', type=number(above=None, at_least=0.0),
                        default=pose.edge_offset_rad, metavar='RAD',
                        help='tilt of the sensor from the normal so its edge touches, rad, '
                             f'below pi/2 (default {pose.edge_offset_rad:g})')
    parser.add_argument('--press-depth', type=number(above=None, at_least=0.0),
                        default=pose.press_depth_m, metavar='M',
                        help=f'indentation of the edge, m (default {pose.press_depth_m:g})')
    parser.add_argument('--label', type=text, default='unknown', metavar='TEXTURE',
                        help='texture label written to the recording (default unknown)')
    parser.add_argument('--trial', type=trial_id, default=0, metavar='N',
                        help='trial number written to the recording (groups its windows)')
    parser.add_argument('--movement', type=movement_name, metavar='NAME',
                        help='the movement (config/movements.yaml) this sweep makes, written '
                             'to the recording so that it can train identification; set '
                             '--speed, --press-depth and --edge-offset to its values')
    parser.add_argument('--record', action='store_true',
                        help="record the sweep to a bag under sweep_node's recording_root")
    add_goal_options(parser, 'sweep_node')


def movement_name(text: str) -> str:
    """A movement's name as movement files spell it (argparse type)."""
    from tactex_description.movements import NAME
    if not NAME.match(text):
        raise argparse.ArgumentTypeError(f'must start with a letter and hold only letters, '
                                         f'digits, _ and - (at most 64), got {text!r}')
    return text


WRITTEN = ('give a pathway file probe_node wrote (its parameter pathway_file, by default '
           '~/.ros/tactex/pathway.json)')


def pathway_of(path: Path):
    """The tactex_msgs/Pathway of a pathway file (CommandError when it is not one)."""
    from tactex_probe.errors import PathwayError
    from tactex_probe.messages import pathway_message
    from tactex_probe.pathway import Pathway
    try:
        return pathway_message(Pathway.load(check_input_file(path, '--pathway', hint=WRITTEN)))
    except PathwayError as err:  # its message begins with the file's name
        raise CommandError(f'--pathway {err}; {WRITTEN}') from None


def feedback_progress(feedback):
    """The bar's view of a Sweep feedback: percent of the path, contact, speed, tracking."""
    from tactex.goal_client import Progress
    touching = 'in contact' if feedback.in_contact else 'in the air'
    return Progress(done=round(100 * feedback.progress), total=100,
                    state=f'{touching}, {1e3 * feedback.sliding_speed:.1f} mm/s, tracking '
                          f'{1e3 * feedback.tracking_error:.1f} mm')


def result_lines(result, commanded_m_s: float) -> list[str]:
    """How the sweep went: contact, speed against the command, press depth, recording."""
    lines = [f'in contact {100 * result.contact_fraction:.0f} % of the sweep, '
             f'{len(result.contact_starts)} contact segment(s)',
             f'sliding speed {1e3 * result.speed_mean:.2f} +- {1e3 * result.speed_std:.2f} mm/s '
             f'(commanded {1e3 * commanded_m_s:.2f})',
             f'press depth error {1e3 * result.press_depth_error:.2f} mm rms']
    if result.recording_path:
        lines.append(f'recorded to {result.recording_path}')
    return lines


def run(args: argparse.Namespace) -> int:
    """Sweep; print the result; 1 when the goal did not succeed."""
    try:
        PoseSettings(edge_offset_rad=args.edge_offset, press_depth_m=args.press_depth)
    except ValueError as err:
        option = '--edge-offset' if 'edge_offset' in str(err) else '--press-depth'
        raise CommandError(f'{option}: {err}') from None
    from tactex.goal_client import send_goal
    from tactex.ros_client import client_node, namespaced
    from tactex_common import topics
    from tactex_msgs.action import Sweep
    goal = Sweep.Goal(sliding_speed=args.speed, edge_offset_angle=args.edge_offset,
                      press_depth=args.press_depth, label=args.label, trial=args.trial,
                      record=args.record, movement=args.movement or '')
    if args.pathway is not None:
        goal.pathway = pathway_of(args.pathway)
    action = namespaced(args.namespace, topics.SWEEP_ACTION)
    with client_node('tactex_sweep_client') as (node, executor):
        status, result = send_goal(node, executor, Sweep, action, goal, what='sweep',
                                   server_timeout_s=args.server_timeout,
                                   timeout_s=args.timeout, progress=feedback_progress, unit='%')
    print(f'sweep goal {status}' + (f': {result.message}' if result.message else ''))
    if status == 'succeeded' or result.contact_starts:
        for line in result_lines(result, args.speed):
            print(f'  {line}')
    return 0 if status == 'succeeded' else 1
