# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex sim collect` refuses scenes whose sweeps cannot slide in contact over a texture."""

from pathlib import Path
import tomllib

import pytest

from tactex.cli import main
from tactex_sim.collect import check_collectable, collect
from tactex_sim.errors import SceneError
from tactex_sim.scene import parse_scene

SCENE = Path(__file__).resolve().parents[2] / 'config' / 'scenes' / 'uneven_texture.toml'


def scene_with(section: str, key: str, value):
    raw = tomllib.loads(SCENE.read_text())
    if section == 'top':
        raw[key] = value
        raw['effect'] = {k: v for k, v in raw['effect'].items() if k in value}
    elif section == 'patches':
        raw['patches'][0][key] = value
    else:
        raw[section][key] = value
    return parse_scene(raw, 'scene.toml'), raw


UNCOLLECTABLE = [
    ('sweep', 'speed_m_s', 0.0, 'speed_m_s and contact_s must be > 0'),
    ('sweep', 'contact_s', 0.0, 'speed_m_s and contact_s must be > 0'),
    ('variability', 'speed_fraction', 0.6, r'speed_fraction must be in \[0, 0.5\)'),
    ('variability', 'press_depth_m', [-0.001, 0.0004], 'never presses'),
    ('variability', 'press_depth_m', [0.0, 0.0], 'never presses'),
    ('patches', 'x_m', [0.30, 0.33], 'no patch lies on the swept path'),
    ('patches', 'y_m', [0.02, 0.08], 'no patch lies on the swept path'),
    ('top', 'effects', ['contact', 'compliance', 'imu_noise'], 'effects lack texture'),
    ('top', 'effects', ['texture', 'compliance'], 'effects lack contact'),
]


@pytest.mark.parametrize('section, key, value, match', UNCOLLECTABLE,
                         ids=[f'{c[1]}={c[2]}' for c in UNCOLLECTABLE])
def test_scenes_that_cannot_slide_over_a_texture_are_refused(tmp_path, section, key, value,
                                                             match):
    scene, _ = scene_with(section, key, value)
    with pytest.raises(SceneError, match=f'scene.toml: .*{match}'):
        check_collectable(scene)
    with pytest.raises(SceneError, match=match):
        collect(scene, 1, tmp_path / 'out', textures=('wood',), progress=lambda line: None)
    assert not (tmp_path / 'out').exists()


def test_the_shipped_texture_scenes_are_collectable():
    for name in ('uneven_texture', 'even_texture'):
        check_collectable(parse_scene(tomllib.loads(
            (SCENE.parent / f'{name}.toml').read_text()), name))


def test_cli_refuses_the_scene_before_creating_the_output(tmp_path, capsys):
    _, raw = scene_with('sweep', 'speed_m_s', 0.0)
    path = tmp_path / 'standing.toml'
    lines = [f'{k} = {v!r}'.replace("'", '"') for k, v in raw.items() if not isinstance(
        v, (dict, list)) or k == 'effects']
    for section in ('surface', 'sweep', 'variability'):
        lines.append(f'[{section}]')
        lines += [f'{k} = {v!r}'.replace("'", '"') for k, v in raw[section].items()]
    for patch in raw['patches']:
        lines.append('[[patches]]')
        lines += [f'{k} = {v!r}'.replace("'", '"') for k, v in patch.items()]
    path.write_text('\n'.join(lines).replace('True', 'true'))
    assert main(['sim', 'collect', '--scene', str(path), '--out', str(tmp_path / 'bags'),
                 '--sweeps', '1', '--textures', 'wood']) == 1
    error = capsys.readouterr().err
    assert error.startswith('error: ') and 'speed_m_s' in error
    assert not (tmp_path / 'bags').exists()


@pytest.mark.slow
def test_two_workers_record_the_same_bags_as_one(tmp_path):
    scene = parse_scene(tomllib.loads(SCENE.read_text()), 'uneven_texture')
    textures = ('wood', 'carpet wool')
    lines = []
    serial = collect(scene, 2, tmp_path / 'one', textures=textures, progress=lines.append)
    parallel = collect(scene, 2, tmp_path / 'two', textures=textures, progress=lines.append,
                       workers=2)
    assert [p.name for p in serial] == [p.name for p in parallel] == [
        'wood_0000', 'wood_0001', 'carpet_wool_0002', 'carpet_wool_0003']
    for one, two in zip(serial, parallel, strict=True):
        files = sorted(p.relative_to(one) for p in one.rglob('*') if p.is_file())
        assert files == sorted(p.relative_to(two) for p in two.rglob('*') if p.is_file())
        for name in files:
            assert (one / name).read_bytes() == (two / name).read_bytes(), f'{one.name}/{name}'
    assert sum('[4/4]' in line for line in lines) == 2


def test_collect_help_lists_every_texture_name(capsys):
    from tactex.cli import main
    from tactex_sim.textures import TEXTURES
    with pytest.raises(SystemExit):
        main(['sim', 'collect', '--help'])
    help_text = ' '.join(capsys.readouterr().out.split())
    assert all(name in help_text for name in TEXTURES)
