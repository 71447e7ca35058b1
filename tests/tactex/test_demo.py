# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`make demo`'s job: the quick demo end to end through the launched nodes, and its thresholds."""

import json
import math
from pathlib import Path
import re
import subprocess
import sys

import pytest

from tactex.cli import main
from tactex.demo import figures as demo_report
from tactex.demo import pipeline as demo
from tactex_sim.scene import load_scene, resolve_scene

pytestmark = pytest.mark.integration

TACTEX = Path(sys.executable).parent / 'tactex'
SUMMARY_KEYS = {'contacts', 'normal_error_deg_mean', 'position_error_mm_mean',
                'contact_fraction', 'sliding_speed_error', 'cv_accuracy_grouped',
                'cv_accuracy_stratified', 'live_accuracy', 'time_to_decision_s',
                'madgwick_rejected', 'madgwick_bad_stamps', 'wall_s'}
PLOTS = ('pathway.png', 'sweep.png', 'confusion.png', 'accuracy_vs_contact_time.png',
         'identification.png')
# The demo scene's sliding contact: every live sweep is decided within it.
SWEEP_CONTACT_S = load_scene(resolve_scene(demo.SCENE)).sweep.contact_s


@pytest.mark.slow
@pytest.mark.ros
@pytest.mark.timeout(1800)
def test_quick_demo_runs_every_stage_through_the_nodes_and_meets_its_thresholds(tmp_path):
    from rosbags.highlevel import AnyReader

    from tactex_classify.data.sources import bag_parts
    from tactex_common.interfaces import typestore

    out = tmp_path / 'demo'
    result = subprocess.run([str(TACTEX), 'demo', '--quick', '--out', str(out)],
                            capture_output=True, text=True, timeout=1700,
                            stdin=subprocess.DEVNULL)
    logs = '\n'.join(p.read_text()[-3000:] for p in sorted((out / 'logs').glob('*.log'))) \
        if (out / 'logs').is_dir() else ''
    assert result.returncode == 0, result.stdout + result.stderr + logs
    assert all(f'stage {k}/{demo.STAGES}' in result.stdout for k in range(1, demo.STAGES + 1))
    summary = json.loads((out / 'summary.json').read_text())
    assert SUMMARY_KEYS <= set(summary)
    # Each figure against its constant, from summary.json and from the printed table.
    assert summary['contacts'] >= math.ceil(demo_report.MIN_CONTACT_SHARE
                                            * summary['probe_points'])
    assert summary['normal_error_deg_mean'] <= demo_report.MAX_NORMAL_ERROR_DEG
    assert summary['position_error_mm_mean'] <= demo_report.MAX_POSITION_ERROR_MM
    assert summary['contact_fraction'] >= demo_report.MIN_CONTACT_FRACTION
    assert summary['sliding_speed_error'] <= demo_report.MAX_SPEED_ERROR
    chance = 1 / len(demo.QUICK.textures)
    assert summary['cv_accuracy_grouped'] >= demo_report.TIMES_CHANCE * chance
    assert summary['live_accuracy'] >= demo_report.TIMES_CHANCE * chance
    assert summary['time_to_decision_s'] <= SWEEP_CONTACT_S
    assert summary['madgwick_rejected'] == 0
    assert all(item['passed'] for item in summary['thresholds'].values())
    assert len(re.findall(r'^  \S+ \S+.* \(threshold (<=|>=) \S+.*\): PASS$', result.stdout,
                          re.MULTILINE)) == len(summary['thresholds'])
    for plot in PLOTS:
        assert (out / plot).read_bytes()[:8] == b'\x89PNG\r\n\x1a\n', plot
    # The recordings sweep_node wrote are closed and readable, one per recorded sweep.
    recordings = sorted(p for p in (out / 'bags').iterdir() if p.is_dir())
    assert len(recordings) == summary['sweeps_recorded'] == (len(demo.QUICK.textures)
                                                              * demo.QUICK.sweeps)
    for recording in recordings:
        with AnyReader(bag_parts(recording), default_typestore=typestore()) as reader:
            assert reader.message_count > 0, recording
    assert (out / 'train' / 'model').is_dir()
    assert summary['live_sweeps'] == len(demo.QUICK.textures) * demo.QUICK.live_sweeps
    # Identification: its own recordings (every texture under each movement the pathway
    # holds), a bundle for the movement file written beside it, one goal per texture.
    from tactex_description.movements import load_movements
    movements = load_movements(out / 'movements.yaml')
    assert len(movements.movements) == demo.QUICK.identify_movements
    movement_recordings = [p for p in (out / 'movement_bags').iterdir() if p.is_dir()]
    assert len(movement_recordings) == (len(demo.QUICK.textures) * demo.QUICK.identify_sweeps
                                        * demo.QUICK.identify_movements)
    assert (out / 'identify' / 'bundle' / 'bundle.json').is_file()
    identification = summary['identification']
    assert [goal['truth'] for goal in identification['goals']] == \
        list(demo.QUICK.textures[:demo.QUICK.identify_textures])
    for goal in identification['goals']:
        assert 1 <= len(goal['movements']) <= demo.QUICK.identify_budget, goal
        assert set(goal['movements']) <= set(movements.names)
        assert goal['contact_s'] > 0 and goal['stop_reason'], goal
    assert identification['failed'] == 0
    assert 'beside the fixed sweep (classifier_node)' in result.stdout


PASSING = {'contacts': 3, 'probe_points': 3, 'normal_error_deg_mean': 1.0,
           'position_error_mm_mean': 0.5, 'contact_fraction': 0.95, 'sliding_speed_error': 0.02,
           'cv_accuracy_grouped': 0.8, 'cv_accuracy_stratified': 0.9, 'live_accuracy': 0.75,
           'time_to_decision_s': 2.0, 'madgwick_rejected': 0.0, 'madgwick_bad_stamps': 0.0,
           'wall_s': 100.0}


@pytest.mark.parametrize('value', [12.0, math.nan])
def test_a_missed_threshold_fails_the_demo_and_names_the_figure(monkeypatch, capsys, tmp_path,
                                                                 value):
    def fake_run(self):
        summary = dict(PASSING, normal_error_deg_mean=value)
        (self.folder / 'summary.json').write_text(json.dumps(summary))
        return summary, demo_report.checks(summary, summary['probe_points'], 4,
                                           SWEEP_CONTACT_S)
    monkeypatch.setattr(demo.Demo, 'run', fake_run)
    assert main(['demo', '--quick', '--out', str(tmp_path / 'demo')]) == 1
    captured = capsys.readouterr()
    assert 'contact_fraction 0.95 (threshold >= 0.75): PASS' in captured.out
    errors = [line for line in captured.err.splitlines() if line.startswith('error:')]
    assert len(errors) == 1
    assert re.fullmatch(r'error: 1 figure\(s\) missed the threshold: normal_error_deg_mean '
                        r'\S+ deg \(threshold <= 5 deg\): FAIL', errors[0])
    assert (tmp_path / 'demo' / 'summary.json').is_file()  # kept to look at


def test_the_default_demo_sweeps_all_twelve_textures_and_judges_against_their_chance():
    from tactex_sim.textures import TEXTURES
    assert demo.DEFAULT.texture_names == list(TEXTURES) and len(TEXTURES) == 12
    assert demo.QUICK.texture_names == list(demo.QUICK.textures)
    figures = {c.key: c for c in demo_report.checks(PASSING, PASSING['probe_points'],
                                                      len(demo.DEFAULT.texture_names),
                                                      SWEEP_CONTACT_S)}
    assert figures['cv_accuracy_grouped'].limit == pytest.approx(2 / 12)


def test_a_previous_demo_folder_is_replaced_and_any_other_folder_kept(monkeypatch, capsys,
                                                                      tmp_path):
    def fake_run(self):
        return dict(PASSING), demo_report.checks(PASSING, PASSING['probe_points'], 4,
                                                 SWEEP_CONTACT_S)
    monkeypatch.setattr(demo.Demo, 'run', fake_run)
    out = tmp_path / 'demo'
    assert main(['demo', '--quick', '--out', str(out)]) == 0
    (out / 'old.txt').write_text('from the first run')
    assert main(['demo', '--quick', '--out', str(out)]) == 0
    assert not (out / 'old.txt').exists() and (out / demo.MARKER).is_file()
    (tmp_path / 'mine').mkdir()
    (tmp_path / 'mine' / 'keep.txt').write_text('keep')
    assert main(['demo', '--out', str(tmp_path / 'mine')]) == 1
    assert 'already holds files' in capsys.readouterr().err
    assert (tmp_path / 'mine' / 'keep.txt').read_text() == 'keep'
