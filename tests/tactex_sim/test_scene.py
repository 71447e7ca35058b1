# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Scene files: every shipped scene loads; every mistake is named."""

from pathlib import Path

import pytest

from tactex_sim.errors import SceneError, UnknownNameError
from tactex_sim.scene import load_scene, parse_scene
from tactex_sim.world import World

SCENES = sorted((Path(__file__).resolve().parents[2] / 'config' / 'scenes').glob('*.toml'))
MINIMAL = {'name': 't', 'seed': 1, 'effects': ['contact'], 'surface': {'kind': 'flat'}}


@pytest.mark.parametrize('path', SCENES, ids=lambda p: p.stem)
def test_shipped_scenes_load_and_build(path):
    scene = load_scene(path)
    assert World(scene).model.nq > 0


def test_unknown_top_level_key_is_named():
    with pytest.raises(SceneError, match="unknown key\\(s\\) 'gravity' in \\[top level\\]"):
        parse_scene({**MINIMAL, 'gravity': 9.8})


def test_unknown_section_key_lists_the_known_ones():
    with pytest.raises(SceneError, match="'amplitud' in \\[surface\\]; known: amplitude_m"):
        parse_scene({**MINIMAL, 'surface': {'kind': 'flat', 'amplitud': 1}})


@pytest.mark.parametrize('change, match', [
    ({'seed': -1}, 'seed'),
    ({'sensor_rate_hz': 0}, 'sensor_rate_hz'),
    ({'timestep_s': 0.05}, 'timestep_s'),
    ({'surface': {'kind': 'wavy'}}, 'kind'),
    ({'surface': {'size_m': [0.3]}}, 'size_m must be a list of 2'),
    ({'surface': {'amplitude_m': 'big'}}, 'amplitude_m must be a finite number'),
    ({'effects': ['contact', 'contact']}, 'repeat'),
    ({'effect': {'texture': {}}}, 'does not list'),
    ({'patches': [{'texture': 'wood', 'x_m': [0.2, 0.1], 'y_m': [0, 1]}]}, 'empty rectangle'),
])
def test_bad_values_fail_with_the_key(change, match):
    with pytest.raises(SceneError, match=match):
        parse_scene({**MINIMAL, **change})


def test_missing_file_and_bad_toml(tmp_path):
    with pytest.raises(SceneError, match='no scene file'):
        load_scene(tmp_path / 'none.toml')
    broken = tmp_path / 'broken.toml'
    broken.write_text('name = "x', encoding='utf-8')
    with pytest.raises(SceneError, match='not valid TOML'):
        load_scene(broken)


def test_unknown_effect_lists_the_registered_ones():
    scene = parse_scene({**MINIMAL, 'effects': ['contact', 'wind']})
    with pytest.raises(UnknownNameError, match='unknown effect .wind.; known effects: contact'):
        World(scene)


def test_unknown_effect_option_is_refused():
    scene = parse_scene({**MINIMAL, 'effects': ['barometer'],
                         'effect': {'barometer': {'altitude': 3}}})
    with pytest.raises(SceneError, match="effect 'barometer': unknown option"):
        World(scene)


def test_unknown_texture_is_named():
    scene = parse_scene({**MINIMAL, 'patches': [{'texture': 'velvet', 'x_m': [0, 1],
                                                  'y_m': [0, 1]}]})
    with pytest.raises(UnknownNameError, match="unknown texture 'velvet'; known: brocade"):
        World(scene)
