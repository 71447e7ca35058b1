# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex sim collect --movements`: every texture swept under every movement, each named.

The movement's speed, press depth, tilt, direction and contact length replace the scene's
nominal sweep (its variability drawn around them); trial ids stay unique across
movements; a bag is the same whatever the order of the movement file; convert keeps each
recording's movement; a movement the arm cannot sweep is refused before any bag, the
command naming the movement file.
"""

from dataclasses import replace
import json
import math
from pathlib import Path
import tomllib

import numpy as np
import pytest

from tactex.cli import main
from tactex_classify.data.bags import read_recording
from tactex_description.kinematics import forward_kinematics
from tactex_description.mjcf import EDGE_TIP_RADIUS_M
from tactex_description.movements import load_movements
from tactex_description.speed_ramp import RAMP_ACCELERATION_M_S2
from tactex_sim.collect import collect, collectable_scenes, movement_scene
from tactex_sim.errors import SceneError
from tactex_sim.scene import parse_scene
from tactex_sim.sweep import plan_sweep, SweepParameters
from tactex_trajectory.simulated_sweeps import rim_press_depth

ROOT = Path(__file__).resolve().parents[2]
SCENE = parse_scene(tomllib.loads((ROOT / 'config' / 'scenes' / 'uneven_texture.toml')
                                  .read_text()), 'uneven_texture')
FORWARD = ('{name: ahead, speed: 0.02, press_depth: 0.002, edge_tilt: 0.4, '
           'direction: forward, contact_length: 0.03}')
BACKWARD = ('{name: back, speed: 0.03, press_depth: 0.0025, edge_tilt: 0.5, '
            'direction: backward, contact_length: 0.045}')


def movement_file(tmp_path, *rows, name='movements.yaml'):
    path = tmp_path / name
    path.write_text('window: 64\nmovements:\n' + ''.join(f'  - {row}\n' for row in rows))
    return load_movements(path, sample_rate_hz=SCENE.sensor_rate_hz)


def metadata(path: Path) -> dict:
    return read_recording(path).metadata


def test_every_texture_is_swept_under_every_movement_with_unique_trials(tmp_path):
    movements = movement_file(tmp_path, FORWARD, BACKWARD)
    paths = collect(SCENE, 2, tmp_path / 'bags', textures=('wood', 'carpet wool'),
                    movements=movements, progress=lambda line: None)
    assert [p.name for p in paths] == [
        'wood_ahead_0000', 'wood_ahead_0001', 'carpet_wool_ahead_0002', 'carpet_wool_ahead_0003',
        'wood_back_0004', 'wood_back_0005', 'carpet_wool_back_0006', 'carpet_wool_back_0007']
    for path in paths:
        meta = metadata(path)
        movement = movements.by_name(meta['movement'])
        assert meta['trial'] == int(path.name[-4:])
        assert abs(meta['sweep']['speed_m_s'] / movement.speed_m_s - 1) <= 2 * 0.04 + 1e-9
        assert meta['sweep']['direction'] == (-1 if movement.direction == 'backward' else 1)
        assert meta['sweep']['ramp_acceleration_m_s2'] == RAMP_ACCELERATION_M_S2


def test_a_backward_movement_slides_towards_the_start_over_its_contact_length(tmp_path):
    movements = movement_file(tmp_path, FORWARD, BACKWARD)
    for movement, path in zip(movements.movements, collect(
            SCENE, 1, tmp_path / 'bags', textures=('wood',), movements=movements,
            progress=lambda line: None), strict=True):
        recording = read_recording(path)
        truth = recording.truth
        sliding = np.zeros(truth.edge_ns.size, dtype=bool)
        for start, end in recording.active_ns:
            sliding |= (truth.edge_ns >= start) & (truth.edge_ns <= end)
        x = truth.edge_m[sliding, 0]
        travel = (x[-1] - x[0]) * (1 if movement.direction == 'forward' else -1)
        # The edge trails its plan (servos, the compliant body under friction), more when
        # it pushes its tilted edge ahead (backward) than when it drags it.
        assert 0.6 * movement.contact_length_m < travel < 1.1 * movement.contact_length_m, \
            movement.name


def rim_depths(scene):
    """How deep the edge's rim is planned into the surface while the scripted sweep slides."""
    plan = plan_sweep(scene, SweepParameters.nominal(scene))
    sliding = (plan.times_s > plan.slide_start_s) & (plan.times_s < plan.slide_end_s)
    edges = np.array([forward_kinematics(joints[:4])[:3, 3] for joints in plan.joints[sliding]])
    return rim_press_depth(edges, scene.surface)


def test_a_movement_presses_its_rim_as_deep_as_the_sweep_action_would(tmp_path):
    """A movement file's press depth is the rim's, in sim collect as in a Sweep goal."""
    movement, = movement_file(tmp_path, '{name: m, speed: 0.015, press_depth: 0.0015, '
                              'edge_tilt: 0.5, direction: forward, '
                              'contact_length: 0.03}').movements
    swept = movement_scene(SCENE, movement)
    assert swept.sweep.press == 'rim' and SCENE.sweep.press == 'centre'
    assert np.mean(rim_depths(swept)) == pytest.approx(0.0015, abs=1e-4)
    # The scene's own sweep presses the edge's centre its depth in: the rim r deeper.
    centred = replace(swept, sweep=replace(swept.sweep, press='centre'))
    assert np.mean(rim_depths(centred)) == pytest.approx(0.0015 + EDGE_TIP_RADIUS_M, abs=1e-4)


def test_a_movement_ramps_its_speed_around_its_contact_as_the_sweep_action_slides(tmp_path):
    """Up from rest and back down at the action's ramp acceleration, outside the contact.

    The recording's active part is the contact at full speed; the scenes' own sweeps
    start and stop at full speed.
    """
    flat = parse_scene(tomllib.loads((ROOT / 'config' / 'scenes' / 'even_texture.toml')
                                     .read_text()), 'even_texture')
    movement, = movement_file(tmp_path, BACKWARD).movements
    for scene, ramped in ((movement_scene(flat, movement), True), (flat, False)):
        plan = plan_sweep(scene, SweepParameters.nominal(scene))
        # On the flat plate the edge's x is the script's travel.
        x = np.array([forward_kinematics(joints[:4])[0, 3] for joints in plan.joints])
        speed = np.abs(np.gradient(x, plan.times_s))
        active = (plan.times_s > plan.slide_start_s + 0.015) & (
            plan.times_s < plan.slide_end_s - 0.015)  # a step's central difference halves
        assert speed[active] == pytest.approx(scene.sweep.speed_m_s, rel=0.02)
        assert plan.slide_end_s - plan.slide_start_s == pytest.approx(scene.sweep.contact_s)
        before = plan.times_s < plan.slide_start_s - 0.02
        if ramped:
            ramp_s = math.pi * movement.speed_m_s / (2 * RAMP_ACCELERATION_M_S2)
            speed_at = dict(zip(np.round(plan.times_s, 2), speed, strict=True))
            ramp_begins = plan.slide_start_s - ramp_s
            assert speed_at[round(ramp_begins - 0.05, 2)] < 0.05 * movement.speed_m_s
            assert speed_at[round(ramp_begins + ramp_s / 2, 2)] == pytest.approx(
                movement.speed_m_s / 2, rel=0.1)  # the cosine ramp's middle
            assert np.max(np.abs(np.gradient(speed, plan.times_s))) < \
                1.1 * RAMP_ACCELERATION_M_S2
            assert np.all(speed[before] < movement.speed_m_s)
        else:
            assert np.max(speed[before]) < 1e-4  # at rest until it slides at full speed


def test_movements_take_their_parts_of_the_swept_path_as_of_a_probed_pathway(tmp_path):
    """Forward from the path's start, backward from its end, as on a pathway.

    The Sweep action puts them so on a probed pathway (identification's pathway_part), so
    the same movement meets the same stretch of the plate's wave in sim collect as through
    the action.
    """
    forward, backward = movement_file(tmp_path, FORWARD, BACKWARD).movements
    path_end = SCENE.sweep.start_x_m + SCENE.sweep.speed_m_s * SCENE.sweep.contact_s
    assert movement_scene(SCENE, forward).sweep.start_x_m == SCENE.sweep.start_x_m
    assert movement_scene(SCENE, backward).sweep.start_x_m == pytest.approx(path_end)


def test_a_movement_only_its_extreme_draws_cannot_sweep_is_refused_before_any_bag(tmp_path):
    """Its nominal sweep fits; one drawn 8 mm farther and 8 % faster would not.

    sim collect crashed at sweep 1690 of 1920 on such a draw of a shipped movement.
    """
    edge = movement_file(tmp_path, '{name: edge, speed: 0.035, press_depth: 0.002, '
                         'edge_tilt: 0.5, direction: forward, contact_length: 0.0875}')
    swept = movement_scene(SCENE, edge.movements[0])
    plan_sweep(swept, SweepParameters.nominal(swept))  # reachable as laid out
    with pytest.raises(SceneError, match='movement edge: sweep point .* unreachable'):
        collect(SCENE, 1, tmp_path / 'bags', textures=('wood',), movements=edge,
                progress=lambda line: None)
    assert not (tmp_path / 'bags').exists()


def test_every_shipped_movement_is_collectable_on_the_uneven_scene():
    """Contact and both speed ramps on the patch and within the arm's reach."""
    shipped = load_movements(ROOT / 'config' / 'movements.yaml')
    assert list(collectable_scenes(SCENE, shipped)) == list(shipped.names)


def test_a_bag_does_not_depend_on_the_order_of_the_movement_file(tmp_path):
    one = collect(SCENE, 1, tmp_path / 'one', textures=('wood',),
                  movements=movement_file(tmp_path, FORWARD, BACKWARD, name='a.yaml'),
                  progress=lambda line: None)
    two = collect(SCENE, 1, tmp_path / 'two', textures=('wood',),
                  movements=movement_file(tmp_path, BACKWARD, FORWARD, name='b.yaml'),
                  progress=lambda line: None)
    back_one, back_two = one[1], two[0]
    assert back_one.name == 'wood_back_0001' and back_two.name == 'wood_back_0000'
    first, second = read_recording(back_one), read_recording(back_two)
    assert np.array_equal(first.values, second.values)


def test_convert_keeps_each_recordings_movement(tmp_path):
    movements = movement_file(tmp_path, FORWARD, BACKWARD)
    collect(SCENE, 1, tmp_path / 'bags', textures=('wood',), movements=movements,
            progress=lambda line: None)
    assert main(['convert', str(tmp_path / 'bags'), '--out', str(tmp_path / 'data.npz'),
                 '--window', '64']) == 0
    sidecar = json.loads((tmp_path / 'data.json').read_text())
    assert sorted(r['movement'] for r in sidecar['recordings']) == ['ahead', 'back']
    for row in sidecar['recordings']:  # and what each sweep ran at, drawn around the file
        movement = movements.by_name(row['movement'])
        assert row['sweep']['speed_m_s'] == pytest.approx(movement.speed_m_s, rel=0.1)
        assert row['sweep']['edge_tilt_rad'] == pytest.approx(movement.edge_tilt_rad, abs=0.1)


def test_a_movement_the_arm_cannot_sweep_is_refused_before_any_bag(tmp_path):
    steep = movement_file(tmp_path, FORWARD, '{name: steep, speed: 0.03, press_depth: 0.003, '
                          'edge_tilt: 1.0, direction: forward, contact_length: 0.09}')
    with pytest.raises(SceneError, match='movement steep: sweep point .* unreachable.*lower '
                                         'its edge_tilt'):
        collect(SCENE, 1, tmp_path / 'bags', textures=('wood',), movements=steep,
                progress=lambda line: None)
    assert not (tmp_path / 'bags').exists()
    far = movement_file(tmp_path, '{name: far, speed: 0.02, press_depth: 0.002, edge_tilt: '
                        '0.5, direction: forward, contact_length: 0.25}')
    # 250 mm and 2 x 6 mm of ramps from x = 0.085 m (+ 8 mm drawn) off the patch at 0.33 m
    with pytest.raises(SceneError, match='far slides 250 mm and ramps its speed over 13 mm '
                                         'more; the texture patch holds 237 mm'):
        movement_scene(SCENE, far.movements[0])


def test_the_command_names_the_movement_file_of_a_movement_the_arm_cannot_sweep(tmp_path,
                                                                                capsys):
    movement_file(tmp_path, '{name: steep, speed: 0.03, press_depth: 0.003, edge_tilt: 1.0, '
                  'direction: forward, contact_length: 0.09}')
    path = tmp_path / 'movements.yaml'
    assert main(['sim', 'collect', '--movements', str(path), '--sweeps', '1', '--textures',
                 'wood', '--out', str(tmp_path / 'bags')]) == 1
    error = capsys.readouterr().err.strip()
    assert error.startswith(f'error: --movements {path}: movement steep: sweep point')
    assert error.endswith('lower its edge_tilt or press_depth, or shorten its contact_length')
    reasons = error.split('every solution breaks a joint limit: ')[1].split('; lower')[0]
    assert len(reasons.split('; ')) == len(set(reasons.split('; ')))  # each reason once
    assert not (tmp_path / 'bags').exists()
