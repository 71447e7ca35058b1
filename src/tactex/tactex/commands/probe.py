# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex probe`: send a Probe goal, show its progress, print the contacts it found.

Like `ros2 action send_goal --feedback probe tactex_msgs/action/Probe ...` on a machine
without the `ros2` CLI. The goal's defaults are probe_node's own (config/probe.yaml
`goal.*`: the demo plate in front of the arm). probe_node broadcasts the pathway (latched,
`probe/pathway`) and writes it to its `pathway_file` (~/.ros/tactex/pathway.json by
default), where `tactex sweep` and sweep_node find it. `--score` asks the running
simulator which scene it shows and measures the contacts against that surface.
Ctrl-C cancels the goal; the node lifts the sensor off before it ends.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from tactex.errors import CommandError
from tactex.options import add_goal_options, check_output_file, output_path, text
from tactex_probe.pathway import ContactStatus, DEFAULT_GOAL, PARAMETER_RANGES

PHASES = ('moving', 'descending', 'measuring', 'retracting')  # Probe feedback PHASE_* codes


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    for name in ('start', 'direction'):
        parser.add_argument(f'--{name}', type=float, nargs=3, default=DEFAULT_GOAL[name],
                            metavar=('X', 'Y', 'Z'),
                            help=f'{name} in base_link{", m" if name == "start" else ""} '
                                 f'(default {" ".join(f"{v:g}" for v in DEFAULT_GOAL[name])})')
    for name, allowed in PARAMETER_RANGES.items():
        parser.add_argument(f'--{name.replace("_", "-")}', type=float, default=DEFAULT_GOAL[name],
                            metavar=allowed.unit.upper().replace('/', '_'),
                            help=f'{allowed.description} ({allowed.unit}; default '
                                 f'{DEFAULT_GOAL[name]:g})')
    parser.add_argument('--score', action='store_true',
                        help="measure the contacts against the simulator's true surface and "
                             'plot them (needs the launch with sim:=true)')
    parser.add_argument('--out', type=output_path, default=Path('probe_score.png'), metavar='PNG',
                        help='with --score: the plot (default probe_score.png)')
    parser.add_argument('--simulator', type=text, default='mujoco_bridge', metavar='NODE',
                        help='with --score: the simulator node asked for its scene')
    add_goal_options(parser, 'probe_node')


def goal_parameters(args: argparse.Namespace):
    """The core's ProbeParameters of the options (CommandError naming a bad one)."""
    from tactex_probe.errors import ParameterError
    from tactex_probe.pathway import ProbeParameters
    values = {name: getattr(args, name) for name in DEFAULT_GOAL}
    try:
        return ProbeParameters(**values)
    except ParameterError as err:
        name = str(err).split()[0]
        raise CommandError(f'--{name.replace("_", "-")}: {err}') from None


def feedback_progress(feedback):
    """The bar's view of a Probe feedback: probes done of the goal's, phase, contacts."""
    from tactex.goal_client import Progress
    phase = PHASES[feedback.phase] if feedback.phase < len(PHASES) else str(feedback.phase)
    return Progress(done=feedback.probe_index, total=max(1, feedback.probe_count),
                    state=f'probe {feedback.probe_index + 1} {phase}, '
                          f'contacts {feedback.contacts_found}')


def contact_lines(result) -> list[str]:
    """One line per probe point: its outcome, and the contact's position and tilt."""
    lines = ['probe  outcome            x mm    y mm    z mm  normal tilt deg']
    contacts = iter(result.pathway.contacts)
    for index, code in enumerate(result.outcomes):
        name = ContactStatus(code).name.lower() if code in set(ContactStatus) else str(code)
        row = f'{index + 1:5d}  {name:17}'
        if code == ContactStatus.OK:
            contact = next(contacts)
            p, n = contact.position, contact.normal
            tilt = math.degrees(math.acos(max(-1.0, min(1.0, n.z))))
            row += f' {1e3 * p.x:7.1f} {1e3 * p.y:7.1f} {1e3 * p.z:7.1f} {tilt:16.1f}'
        lines.append(row)
    return lines


def score(result, scene_name: str, out: Path) -> str:
    """The contacts' errors against the scene's surface, as a line; the plot at `out`."""
    from tactex.demo.figures import pathway_errors, plot_pathway
    from tactex_probe.messages import contact_arrays
    from tactex_sim.errors import SimError
    from tactex_sim.scene import load_scene, resolve_scene
    try:
        surface = load_scene(resolve_scene(scene_name)).surface
    except SimError as err:
        raise CommandError(f'--score: the simulator runs scene {scene_name!r}, which is not '
                           f"readable here ({err}); run it on the simulator's machine") from None
    positions, normals = contact_arrays(result.pathway)
    staged = out.with_name(f'.{out.name}.partial.png')
    plot_pathway(staged, positions, normals, surface)
    staged.replace(out)
    if not len(positions):
        return f'score against scene {scene_name}: no contact to score; plot in {out}'
    normal_deg, position_mm = pathway_errors(positions, normals, surface)
    return (f'score against scene {scene_name}: normal error {normal_deg.mean():.2f} deg mean, '
            f'{normal_deg.max():.2f} max; position error {position_mm.mean():.2f} mm mean, '
            f'{position_mm.max():.2f} max (to the true surface); plot in {out}')


def run(args: argparse.Namespace) -> int:
    """Probe; print the outcome per point (and the score); 1 when the goal did not succeed."""
    from tactex.goal_client import send_goal
    from tactex.ros_client import client_node, namespaced, ParameterClient
    from tactex_common import topics
    from tactex_msgs.action import Probe
    from tactex_probe.messages import goal_message
    goal = goal_message(goal_parameters(args))
    out = check_output_file(args.out, suffix='.png') if args.score else None
    action = namespaced(args.namespace, topics.PROBE_ACTION)
    with client_node('tactex_probe_client') as (node, executor):
        scene_name = None
        if args.score:  # before the arm moves: a score without the simulator is refused
            simulator = ParameterClient(node, executor, namespaced(args.namespace,
                                                                   args.simulator), 5.0)
            scene_name = simulator.get('scene')
        status, result = send_goal(node, executor, Probe, action, goal, what='probe',
                                   server_timeout_s=args.server_timeout,
                                   timeout_s=args.timeout, progress=feedback_progress,
                                   unit='probes')
    elapsed = result.elapsed.sec + 1e-9 * result.elapsed.nanosec
    print(f'probe goal {status} in {elapsed:.1f} s: {len(result.pathway.contacts)} of '
          f'{len(result.outcomes)} probes gave a contact'
          + (f' ({result.message})' if result.message else ''))
    for line in contact_lines(result):
        print(line)
    if status != 'succeeded':
        return 1
    print(f'pathway broadcast on {namespaced(args.namespace, topics.PROBE_PATHWAY)} (latched) '
          "and written to probe_node's pathway_file (`tactex param get probe_node "
          "pathway_file`); `tactex sweep` slides along it")
    if scene_name is not None:
        print(score(result, scene_name, out))
    return 0
