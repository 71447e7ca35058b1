# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The accuracy-time report: its choices, its measures, and a quick run end to end."""

import json
import math

import numpy as np
import pytest

from tactex.accuracy_time import configurations, markdown, runner, section_text
from tactex.accuracy_time.classification import fits, mark_pareto
from tactex.accuracy_time.physical import spectral_distance_db
from tactex.accuracy_time.sizes import QUICK
from tactex.cli import main
from tactex_sim.errors import SimError


def point(model, contact_s, accuracy, threshold=0.99, window=128):
    return {'model': model, 'window': window, 'rule': f'posterior > {threshold}',
            'windows': None, 'threshold': threshold, 'contact_s': contact_s,
            'accuracy': accuracy, 'earliness': 0.5, 'harmonic_mean': 0.5}


def test_the_pareto_front_holds_only_points_nothing_beats():
    points = [point('a', 1.0, 0.6), point('b', 2.0, 0.9), point('c', 2.0, 0.8),
              point('d', 3.0, 0.9), point('e', 0.5, 0.5)]
    mark_pareto(points)
    assert [p['model'] for p in points if p['pareto']] == ['a', 'b', 'e']


def test_the_three_configurations_follow_their_rules():
    points = [point('fast', 0.5, 0.80), point('near', 1.5, 0.93, 0.9),
              point('best', 4.0, 0.97, 0.9999), point('budget', 1.9, 0.95, 0.999),
              {**point('fixed', 0.1, 1.0), 'threshold': None, 'rule': '1 window'},
              point('never', 5.0, 1.0, 1.0)]
    compute = [{'model': 'budget', 'latency': {'scikit-learn': {'single_s': 2e-3},
                                                'onnxruntime': {'single_s': 1e-4}}}]
    chosen = configurations.choose(points, compute)
    assert chosen['accurate']['model'] == 'best'  # fixed windows and threshold 1 never decide
    assert chosen['fastest']['model'] == 'near'  # within 5 points of 97 %
    assert chosen['budget']['model'] == 'budget'
    assert chosen['budget']['runtime'] == 'onnxruntime'
    assert chosen['accurate']['runtime'] == 'native'
    assert configurations.choose([point('slow', 3.0, 0.9)], [])['budget'] is None


def test_a_model_that_did_not_converge_is_marked_never_on_the_front_nor_chosen():
    from tactex.accuracy_time.section_text import contact_time
    stalled = {**point('cnn_3', 0.5, 0.95), 'not_converged': True}  # fast and lucky
    points = [stalled, point('extratrees', 1.0, 0.9), point('minirocket', 2.0, 0.92)]
    mark_pareto(points)
    assert [p['model'] for p in points if p['pareto']] == ['extratrees', 'minirocket']
    chosen = configurations.choose(points, [])
    assert {chosen[key]['model'] for key in ('fastest', 'accurate', 'budget')} == {
        'extratrees', 'minirocket'}
    text = contact_time({'size': {'textures': 4, 'sweeps': 3, 'folds': 3},
                         'data': {'recordings': 12, 'rate_hz': 120.0},
                         '1': {'points': points, 'skipped': []}})
    rendered = '\n'.join(text.tables[0])
    assert '| cnn_3 (not converged) |' in rendered and 'left off the Pareto front' in text.notes
    # Where every model failed to converge, one is still chosen (and marked above).
    assert configurations.choose([stalled], [])['accurate']['model'] == 'cnn_3'


def test_a_configuration_is_a_command_line_that_exports_onnx_only_when_it_runs_it():
    native = markdown.command({**point('extratrees', 1.0, 0.9), 'runtime': 'native'},
                            epochs=7, folds=4)
    onnx = markdown.command({**point('cnn_3', 1.0, 0.9, 0.999), 'runtime': 'onnxruntime'},
                          epochs=7, folds=4)
    assert 'tactex export' not in native and '--epochs' not in native
    assert 'tactex convert bags --window 128 --hop 64' in native
    assert 'tactex export run/model --onnx' in onnx and '--epochs 7 --cv grouped' in onnx
    launch = ('tactex launch classify checkpoint:=run/model threshold:=0.999 '
              'runtime:=onnxruntime')
    assert onnx.splitlines()[-2:] == [f'{launch} source:=sim   # in simulation',
                                      f'{launch}   # on the arm: the sensor on '
                                      'port:=/dev/ttyACM0']


def test_a_configuration_that_is_also_another_is_named_once():
    best = {**point('cnn_3', 1.0, 0.9, 0.999), 'runtime': 'native', 'earliness': 0.5}
    results = {'size': {'name': 'quick', 'epochs': 7, 'folds': 4, 'textures': 12,
                        'sweeps': 3}, 'seed': 0, 'total_s': 60,
               'data': {'recordings': 36, 'rate_hz': 120.0},
               'configurations': {'fastest': best, 'accurate': best, 'budget': None}}
    text = markdown.render({**results, **{section.key: {'failed': 'not run'}
                                          for section in markdown.SECTIONS}})
    opening = text.split('## 1.')[0]
    assert opening.count('tactex train') == 1
    assert '**Most accurate**: the same configuration as "Fastest decision" above.' in opening


def test_spectral_distance_is_zero_for_the_reference_and_grows_with_the_difference():
    reference = np.abs(np.random.default_rng(0).normal(size=(7, 129))) + 1e-3
    assert spectral_distance_db(reference, reference) == 0.0
    assert spectral_distance_db(10 * reference, reference) == pytest.approx(10.0)
    assert spectral_distance_db(100 * reference, reference) == pytest.approx(20.0)
    assert math.isfinite(spectral_distance_db(np.zeros_like(reference), reference))


def test_a_window_too_short_for_a_deep_model_is_found_before_training():
    assert fits('extratrees', 8, 10) and fits('cnn_3', 128, 10)
    assert not fits('cnn_3', 16, 10)


def test_a_failing_section_leaves_nothing_behind(tmp_path, monkeypatch, capsys):
    def fail(*args, **kwargs):
        raise SimError('the sweep never touched the patch')
    monkeypatch.setattr(runner, 'run_sections', fail)
    assert main(['report', 'accuracy-time', '--quick', '--out', str(tmp_path / 'out')]) == 1
    assert capsys.readouterr().err == 'error: the sweep never touched the patch\n'
    assert list(tmp_path.iterdir()) == []


def test_a_section_the_arm_cannot_do_is_reported_and_the_others_still_run(monkeypatch):
    from tactex.accuracy_time import (
        classification,
        identification,
        physical,
        sweep_speed,
        whole_job,
    )
    from tactex_probe.motion import PathUnreachable

    class Data:
        datasets = {64: type('D', (), {'trial': [0, 1], 'y': [0, 1], 'classes': ['a', 'b']})}
        rate_hz, collect_s = 120.0, 1.0

    def unreachable(*args, **kwargs):
        raise PathUnreachable('the probe line leaves the workspace at x = 0.4 m')
    live = point('extratrees', 1.0, 0.9)
    monkeypatch.setattr(classification, 'build_data', lambda *args: Data())
    monkeypatch.setattr(classification, 'contact_time', lambda *a, **k: {'points': [live]})
    monkeypatch.setattr(classification, 'compute_time', lambda *a, **k: {'rows': []})
    monkeypatch.setattr(physical, 'probing', unreachable)
    monkeypatch.setattr(sweep_speed, 'sweep_speed', lambda *a, **k: {'rows': ['measured']})
    monkeypatch.setattr(physical, 'simulation_cost', lambda *a, **k: {'rows': ['measured']})
    monkeypatch.setattr(physical, 'filter_rate', lambda *a, **k: {'rows': ['measured']})
    monkeypatch.setattr(whole_job, 'whole_job', lambda *a, **k: pytest.fail('ran without 3'))
    monkeypatch.setattr(identification, 'identification', lambda *a, **k: {'rows': ['measured']})
    results = runner.run_sections(QUICK, seed=0, threads=1, progress=lambda line: None)
    assert results['3'] == {'failed': 'PathUnreachable: the probe line leaves the workspace '
                                      'at x = 0.4 m'}
    assert results['7'] == {'failed': 'it starts from section 3, which was not measured'}
    assert all(results[n] == {'rows': ['measured']} for n in ('4', '5', '6', '8'))


@pytest.mark.slow
@pytest.mark.timeout(1200)  # about 6 minutes on two loaded cores
def test_the_quick_report_measures_every_section_and_opens_with_three_commands(tmp_path,
                                                                                capsys):
    out = tmp_path / 'report'
    assert main(['report', 'accuracy-time', '--quick', '--out', str(out)]) == 0
    printed = capsys.readouterr().out
    for number in range(1, 9):
        assert f'section {number}/8' in printed
    text = (out / 'report.md').read_text(encoding='utf-8')
    opening = text.split('## 1.')[0]
    assert opening.count('source:=sim   # in simulation') + opening.count(
        'no configuration decided') + opening.count('the same configuration as') == 3
    for number in range(1, 9):
        assert f'## {number}. ' in text
    pictures = sorted(p.name for p in out.glob('*.png'))
    assert len(pictures) == 8
    for name in pictures:
        assert f']({name})' in text
        assert (out / name).read_bytes()[:8] == b'\x89PNG\r\n\x1a\n'
    results = json.loads((out / 'results.json').read_text(encoding='utf-8'))
    assert {str(n) for n in range(1, 9)} <= set(results)
    assert all(0.0 <= p['accuracy'] <= 1.0 for p in results['1']['points'])
    assert [r['speed_mm_s'] for r in results['4']['rows']] == list(QUICK.speeds_mm_s)
    assert results['5']['rows'][0]['distance_db'] == 0.0
    assert all(s['wall_s'] > 0 for s in results['7']['stages'])
    policies = results['8']['policies']
    assert set(policies) == {'active', 'random', 'fixed', 'round-robin'}
    assert all(0.0 <= row['accuracy'] <= 1.0 and row['median_movements'] >= 1
               for row in policies.values())
    assert results['8']['episodes'] == QUICK.textures * 2 * QUICK.identify_seeds
    assert set(results['8']['tradeoff']) == set(policies)
    assert sorted(p.name for p in tmp_path.iterdir()) == ['report']  # nothing staged left


def test_a_speed_out_of_reach_is_a_row_that_says_so_not_a_lost_report(tmp_path):
    from tactex.accuracy_time import plots
    measured = {'speed_mm_s': 15.0, 'distance_mm': 30.0, 'contact_fraction': 0.98,
                'contact_fraction_min': 0.95, 'window_accuracy': 0.6, 'sweep_accuracy': 0.7,
                'windows': 40, 'collect_s': 9.0, 'failed': ''}
    failed = {'speed_mm_s': 60.0, 'failed': 'sweep point x=0.229 m unreachable'}
    results = {'seconds': {'4': 12.0}, '4': {
        'rows': [measured, failed], 'model': 'extratrees', 'contact_s': 2.0, 'window': 64,
        'sweeps': 3, 'textures': 4}}
    text = '\n'.join(section_text.sweep_speed(results).tables[0])
    assert '| 60 | not measured: sweep point x=0.229 m unreachable |' in text
    assert '| 15 | 30 | 98.0 % (95.0 %) | 40 | 60.0 % | 70.0 % | 9 |' in text
    plots.sweep_speed(tmp_path / 'speed.png', results['4']['rows'], 'test data')
    assert (tmp_path / 'speed.png').stat().st_size > 0


def test_the_identification_section_says_when_active_reaches_fixeds_accuracy(tmp_path):
    from tactex.accuracy_time import plots
    row = {'accuracy': 0.5, 'decided': 0.25, 'median_contact_s': 10.0, 'p90_contact_s': 20.0,
           'median_movements': 4.0, 'accuracy_after_k': [0.3, 0.4, 0.5]}
    eighth = {'policies': {'active': dict(row, accuracy=0.6), 'fixed': row},
              'grid_s': [0.0, 2.5, 5.0, 7.5], 'curves': {'active': [0.0, 0.4, 0.55, 0.6],
                                                         'fixed': [0.0, 0.3, 0.4, 0.5]},
              'threshold': 0.99, 'textures': 4, 'movements': ['slow_light', 'default'],
              'sweeps': 4, 'model': 'extratrees', 'folds': 2, 'seeds': 5, 'episodes': 40}
    text = section_text.identification({'8': eighth})
    assert "Active reaches fixed's final 50.0 % after 5.0 s of contact (fixed stops after " \
           'a median 10.0 s).' in text.notes
    assert '| fixed | 50.0 % | 25.0 % | 10.0 | 20.0 | 4 | 30.0 % | 40.0 % | 50.0 % |' in \
        '\n'.join(text.tables[0])
    assert len(text.tables) == 1  # a run kept before the trade-off
    cut = [{'threshold': 0.9, 'accuracy': 0.55, 'mean_contact_s': 4.0},
           {'threshold': 0.99, 'accuracy': 0.6, 'mean_contact_s': 6.5}]
    traded = section_text.identification({'8': dict(eighth, tradeoff={
        'active': cut, 'fixed': [{'threshold': 0.99, 'accuracy': 0.5, 'mean_contact_s': 9.0}]})})
    assert '| threshold | active | fixed |' in traded.tables[1]
    assert '| 0.9 | 55.0 % / 4.0 s | — |' in traded.tables[1]
    assert '| 0.99 | 60.0 % / 6.5 s | 50.0 % / 9.0 s |' in traded.tables[1]
    assert 'What a lower threshold buys' in traded.notes
    below = dict(eighth, curves={'active': [0.0, 0.1, 0.2, 0.3], 'fixed': [0.0] * 4})
    assert 'no contact time measured here' in section_text.identification({'8': below}).notes
    plots.identification(tmp_path / 'identification.png', eighth['grid_s'], eighth['curves'],
                         'test data')
    assert (tmp_path / 'identification.png').read_bytes()[:8] == b'\x89PNG\r\n\x1a\n'
