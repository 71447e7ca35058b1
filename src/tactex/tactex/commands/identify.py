# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex identify`: send an Identify goal, show each movement's belief, print the texture.

Like `ros2 action send_goal --feedback identify tactex_msgs/action/Identify ...` without
the `ros2` CLI. identify_node (`tactex launch system sim:=true bundle:=RUN/bundle`)
chooses the movements and drives the sweep action; without `--pathway` it slides along
the pathway probe_node broadcast (`tactex probe` first). Ctrl-C cancels the goal; the
running sweep lifts the edge off before it ends.
"""

from __future__ import annotations

import argparse
from functools import partial

from tactex.options import add_goal_options, input_path, integer, number, trial_id
from tactex_classify.identification.selection import LIVE_DEFAULT, POLICIES

SHOWN_TEXTURES = 3  # the leading textures printed after each movement
# What the no-server error suggests: identify_node needs a bundle and a sweep node.
LAUNCH = 'system sim:=true bundle:=RUN/bundle'


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('--pathway', type=input_path, metavar='FILE',
                        help='a pathway file to choose parts from (default: the one '
                             'probe_node broadcast on probe/pathway)')
    parser.add_argument('--policy', choices=POLICIES, default=LIVE_DEFAULT,
                        help=f'how the next movement is chosen (default {LIVE_DEFAULT}: the '
                             'largest expected information gain per contact second among '
                             'the movements run fewest times)')
    parser.add_argument('--threshold', type=number(at_most=1.0),
                        default=0.99, metavar='P',
                        help='decide when the leading posterior exceeds this (default 0.99, '
                             "the live classifier's)")
    parser.add_argument('--budget-movements', type=integer(1, 1000), default=0, metavar='N',
                        help='at most this many movements (default: no limit)')
    parser.add_argument('--budget-seconds', type=number(), default=0.0, metavar='S',
                        help='at most this many contact seconds (default: no limit)')
    parser.add_argument('--seed', type=trial_id, default=0, metavar='N',
                        help='seed of the random and active-sampled policies (default 0)')
    add_goal_options(parser, 'identify_node')


def belief_line(class_names, probabilities) -> str:
    """The leading textures and their probabilities, most probable first."""
    ranked = sorted(zip(probabilities, class_names, strict=True), reverse=True)
    return ', '.join(f'{name} {100 * p:.1f} %' for p, name in ranked[:SHOWN_TEXTURES])


def feedback_progress(feedback, budget_movements: int = 0):
    """The bar's view of an Identify feedback: movements run (of the budget), the leader."""
    from tactex.goal_client import Progress
    return Progress(done=feedback.movements_run,
                    total=budget_movements or feedback.movements_run,
                    state=f'{feedback.movement}: '
                          f'{belief_line(feedback.class_names, feedback.probabilities)}, '
                          f'{feedback.contact_seconds:.1f} s in contact')


def result_lines(result) -> list[str]:
    """What the identification did: each movement, the belief, the seconds it took."""
    run = [f'{name} ({windows} windows)' for name, windows in
           zip(result.movements, result.windows, strict=True)]
    lines = [f'movements: {", ".join(run) or "none"}',
             f'belief: {belief_line(result.class_names, result.probabilities)}'
             if result.probabilities else 'belief: none (no movement ran)',
             f'{result.contact_seconds:.1f} s in contact, {result.wall_seconds:.1f} s in all']
    if result.stop_reason:
        lines.append(f'stopped: {result.stop_reason}')
    return lines


def run(args: argparse.Namespace) -> int:
    """Identify; print the texture and how it was found; 1 when the goal did not succeed."""
    from tactex.commands.sweep import pathway_of
    from tactex.goal_client import send_goal
    from tactex.ros_client import client_node, namespaced
    from tactex_common import topics
    from tactex_msgs.action import Identify
    goal = Identify.Goal(policy=args.policy, threshold=args.threshold,
                         budget_movements=args.budget_movements,
                         budget_seconds=args.budget_seconds, seed=args.seed)
    if args.pathway is not None:
        goal.pathway = pathway_of(args.pathway)
    action = namespaced(args.namespace, topics.IDENTIFY_ACTION)
    with client_node('tactex_identify_client') as (node, executor):
        status, result = send_goal(node, executor, Identify, action, goal, what='identify',
                                   server_timeout_s=args.server_timeout,
                                   timeout_s=args.timeout, unit='movements', launch=LAUNCH,
                                   progress=partial(feedback_progress,
                                                    budget_movements=args.budget_movements))
    texture = result.texture or ('undecided' if status == 'succeeded' else '')
    print(f'identify goal {status}' + (f': {texture}' if texture else '')
          + (f' ({result.message})' if result.message else ''))
    for line in result_lines(result):
        print(f'  {line}')
    return 0 if status == 'succeeded' else 1
