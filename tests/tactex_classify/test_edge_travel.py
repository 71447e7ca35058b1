# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""A recording's samples placed along the edge's path: from ground truth, else the joints."""

from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
import numpy as np
import pytest
from support.bagfactory import ramp, write_bag

from tactex.cli import main
from tactex_classify.data.bags import read_recording
from tactex_classify.data.edge_travel import edge_travel_m, STEP_M, travelled
from tactex_description.kinematics import forward_kinematics

SPEED_M_S = 0.015
PERIOD_S = 8_333_333 / 1e9  # ramp's sample period


def sliding_truth(count: int) -> dict:
    """The edge sliding along x at the sweep speed, in contact throughout."""
    x = 0.2 + SPEED_M_S * PERIOD_S * np.arange(count)
    return {'contact': [True] * count, 'texture': ['wood'] * count,
            'edge_m': np.column_stack([x, np.zeros(count), np.full(count, 0.05)])}


def test_ground_truth_gives_the_distance_slid_at_each_sample(tmp_path):
    stamps, values = ramp(240)
    recording = read_recording(write_bag(tmp_path / 'rec', stamps, values,
                                         truth=sliding_truth(240)))
    travel, source = edge_travel_m(recording)
    assert source == "the simulator's edge positions"
    expected = SPEED_M_S * PERIOD_S * np.arange(240)
    # Counted in steps of STEP_M: never ahead of the truth, never behind by a step.
    assert np.all(travel <= expected + 1e-12) and np.all(travel > expected - STEP_M)
    assert travel[-1] == pytest.approx(expected[-1], abs=STEP_M)


def test_without_ground_truth_the_arm_joints_give_it_through_forward_kinematics(tmp_path):
    stamps, values = ramp(120)
    joints = np.column_stack([np.linspace(-0.2, 0.2, 120), np.full(120, 0.3),
                              np.full(120, 0.2), np.full(120, 0.9)])
    recording = read_recording(write_bag(tmp_path / 'rec', stamps, values,
                                         joint_positions=joints))
    travel, source = edge_travel_m(recording)
    assert source == 'forward kinematics of the joint states'
    edge = np.array([forward_kinematics(q)[:3, 3] for q in joints])
    arc = np.sum(np.linalg.norm(np.diff(edge, axis=0), axis=1))  # a circle about joint1
    assert travel[0] == 0.0 and np.all(np.diff(travel) >= 0)
    assert travel[-1] == pytest.approx(arc, abs=STEP_M)


def test_a_standing_arm_whose_encoders_jitter_travels_nowhere():
    rng = np.random.default_rng(3)
    still = np.array([0.25, 0.0, 0.05]) + rng.uniform(-1, 1, (500, 3)) * 0.4 * STEP_M / 2
    assert travelled(still)[-1] == 0.0


def test_a_recording_with_neither_truth_nor_arm_joints_has_no_travel(tmp_path):
    stamps, values = ramp(50)
    bare = read_recording(write_bag(tmp_path / 'bare', stamps, values))
    joint1_only = read_recording(write_bag(tmp_path / 'speed', stamps, values,
                                           joint_speed=np.zeros(50)))
    assert edge_travel_m(bare) is None and edge_travel_m(joint1_only) is None


def test_tactex_plot_draws_a_recording_against_travel_when_it_can_and_says_so(tmp_path,
                                                                              capsys):
    stamps, values = ramp(240)
    write_bag(tmp_path / 'sim', stamps, values, truth=sliding_truth(240),
              metadata={'label': 'wood', 'trial': 1})
    write_bag(tmp_path / 'bare', stamps, values, metadata={'label': 'wood', 'trial': 2})
    assert main(['plot', str(tmp_path / 'sim'), '--out', str(tmp_path / 'sim.png')]) == 0
    assert main(['plot', str(tmp_path / 'bare'), '--out', str(tmp_path / 'bare.png')]) == 0
    out = capsys.readouterr().out
    assert "sim.png: channels against edge travel along its path (mm, from the simulator's" \
        in out
    assert 'bare.png: channels against time since the first sample (s; no edge positions' in out


@pytest.mark.hard_case
@settings(max_examples=60)
@given(points=arrays(np.float64, st.tuples(st.integers(0, 40), st.just(3)),
                     elements=st.floats(-1e308, 1e308)))
def test_any_finite_positions_give_a_finite_travel_that_never_decreases(points):
    distance = travelled(points)
    assert distance.shape == (len(points),)
    assert np.all(np.isfinite(distance)) and np.all(np.diff(distance) >= 0)
