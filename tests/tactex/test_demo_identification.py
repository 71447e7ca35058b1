# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The demo's identification helpers: which movements a probed pathway holds, the figures.

The stages themselves run in test_demo's quick demo (through the launched nodes); here the
parts that decide what it sweeps and what it reports, without a simulator.
"""

import inspect
import math
from pathlib import Path

import pytest

from tactex.cli import build_parser
from tactex.demo.identification import (
    fitting_movements,
    identification_figures,
    identify_each,
    plot_identification,
    ramp_acceleration,
)
from tactex.errors import CommandError
from tactex_classify.identification.selection import LIVE_DEFAULT
from tactex_description.movements import load_movements
from tactex_msgs.action import Identify
from tactex_msgs.msg import Contact, Pathway

SHIPPED = load_movements(Path(__file__).resolve().parents[2] / 'config' / 'movements.yaml')


def pathway_along_x(length_m: float, step_m: float = 0.01) -> Pathway:
    """A flat probed pathway from x = 0.1 m, contacts every `step_m`."""
    pathway = Pathway()
    for k in range(int(round(length_m / step_m)) + 1):
        contact = Contact(status=Contact.STATUS_OK, confidence=1.0)
        contact.position.x, contact.position.z = 0.1 + k * step_m, 0.01
        contact.normal.z = 1.0
        pathway.contacts.append(contact)
    return pathway


def test_active_rounds_is_the_default_policy_of_the_goal_the_command_and_the_demo():
    # Declared in bench/bench_identification_seeds.py (ROUNDS_CONFIRMATORY): a pass of both
    # goals' tests on scene seeds 2071-2093 makes active-rounds the default; it passed.
    assert LIVE_DEFAULT == 'active-rounds'
    assert Identify.Goal().policy == LIVE_DEFAULT  # the action's own literal agrees
    assert build_parser().parse_args(['identify']).policy == LIVE_DEFAULT
    assert inspect.signature(identify_each).parameters['policy'].default == LIVE_DEFAULT


def test_the_ramp_acceleration_is_the_launched_sweep_nodes():
    assert ramp_acceleration() == pytest.approx(0.05)


def test_a_pathway_holds_the_movements_whose_contact_and_ramps_fit_in_file_order():
    ramps = ramp_acceleration()
    held = fitting_movements(pathway_along_x(0.07), SHIPPED)
    assert held.names == tuple(m.name for m in SHIPPED.movements
                               if m.part_length_m(ramps) <= 0.07 + 1e-3)
    assert held.names[:3] == ('slow_light', 'slow_deep', 'default') and held.window == 128
    assert fitting_movements(pathway_along_x(0.07), SHIPPED, 2).names == ('slow_light',
                                                                         'slow_deep')


def test_a_pathway_too_short_for_every_movement_is_one_error_naming_its_length():
    with pytest.raises(CommandError, match=r'pathway \(20 mm\) holds none of the movements'):
        fitting_movements(pathway_along_x(0.02), SHIPPED)


def goal(truth: str, answer: str, leader: str, movements: int, contact_s: float,
         status: int = 4) -> dict:
    return {'truth': truth, 'answer': answer, 'leader': leader, 'status': status,
            'movements': ['slow_light'] * movements, 'contact_s': contact_s, 'wall_s': 10.0,
            'belief': [(2.5 * (k + 1), 0.5) for k in range(movements)]}


def test_identification_figures_count_undecided_goals_as_wrong_and_failed_goals_apart():
    rows = [goal('wood', 'wood', 'wood', 2, 5.0), goal('felt', '', 'felt', 4, 10.0),
            goal('cork', 'wood', 'wood', 1, 2.5, status=6)]
    figures = identification_figures(rows)
    assert figures['accuracy'] == pytest.approx(1 / 3)
    assert figures['leader_accuracy'] == pytest.approx(2 / 3)
    assert figures['decided'] == pytest.approx(2 / 3)
    assert figures['median_movements'] == 2 and figures['median_contact_s'] == 5.0
    assert figures['failed'] == 1 and figures['episodes'] == 3
    assert identification_figures([]) == {'episodes': 0}


@pytest.mark.parametrize('fixed', [3.2, math.nan])
def test_the_identification_plot_is_a_png_with_or_without_a_fixed_decision(tmp_path, fixed):
    path = tmp_path / 'identification.png'
    plot_identification(path, [goal('wood', 'wood', 'wood', 2, 5.0),
                               goal('felt', '', 'felt', 0, 0.0)], fixed)
    assert path.read_bytes()[:8] == b'\x89PNG\r\n\x1a\n'
