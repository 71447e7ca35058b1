# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""bench/bench_learning_curves.py --merge: calls joined, a later point kept, the earlier aside."""

import json
from pathlib import Path
import sys

import pytest
from support.scripts import load_script

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def bench(monkeypatch):
    monkeypatch.syspath_prepend(str(ROOT / 'bench'))  # its sibling modules
    return load_script('bench/bench_learning_curves.py')


def kept(folder: Path, command: str, points: dict, calls: list[str] | None = None) -> Path:
    folder.mkdir()
    summary = {'dataset': 'abc', 'test': 5, 'draws': 1, 'epochs': 100, 'seed': 0,
               'device': 'cpu', 'test_windows': 60, 'chance': 1 / 12, 'sizes': [5, 10],
               'models': ['bilstm_1'], 'points': points, 'skipped': [], 'command': command,
               **({'calls': calls} if calls else {})}
    (folder / 'learning_curves.json').write_text(json.dumps(summary), encoding='utf-8')
    return folder


def test_a_later_call_replaces_a_point_and_the_earlier_is_kept_aside(bench, tmp_path,
                                                                      monkeypatch):
    old = {'accuracy': [0.07], 'seconds': [100.0]}
    merged = kept(tmp_path / 'kept', 'python bench/bench_learning_curves.py --merge a b',
                  {'bilstm_1@5': old, 'bilstm_1@10': old}, calls=['call a', 'call b'])
    new = kept(tmp_path / 'new', 'call c', {'bilstm_1@5': {'accuracy': [0.4],
                                                           'seconds': [300.0]}})
    monkeypatch.setattr(sys, 'argv', ['bench_learning_curves.py', '--merge', 'kept', 'new'])
    assert bench.merge([merged, new], tmp_path / 'out', [5, 10], ['bilstm_1']) == 0
    summary = json.loads((tmp_path / 'out' / 'learning_curves.json').read_text())
    assert summary['points']['bilstm_1@5']['accuracy'] == [0.4]
    assert summary['points']['bilstm_1@10'] == {**old, 'device': 'cpu'}  # the call's device
    assert summary['replaced'] == {'bilstm_1@5': {**old, 'device': 'cpu', 'by': 'call c'}}
    assert summary['calls'] == ['call a', 'call b', 'call c']  # a merged folder's, one by one
    table = (tmp_path / 'out' / 'learning_curves.md').read_text()
    assert '- bilstm_1 at n = 5: 7.0 % (100 s), replaced by `call c`' in table


class Stopped(Exception):
    """A kill right after a kept epoch."""


def test_a_point_stopped_part_way_resumes_and_counts_the_training_before(bench, tmp_path,
                                                                         monkeypatch):
    import bench_architectures
    from support.toy_windows import toy
    import torch

    from tactex_classify.training.training_state import TrainingState
    data = toy(recordings_per_class=4, windows=4)
    config = bench_architectures.configuration('cnn_3', 3, 0, 1)
    state = tmp_path / 'training_state' / 'cnn_3@5#0.pt'
    save = TrainingState.save

    def save_then_stop(keeper, kept):
        save(keeper, kept)
        raise Stopped
    monkeypatch.setattr(TrainingState, 'due', lambda keeper: True)
    monkeypatch.setattr(TrainingState, 'save', save_then_stop)
    with pytest.raises(Stopped):
        bench_architectures.fit_timed(config, data, 'cpu', state)
    monkeypatch.undo()
    trained_before = torch.load(state, weights_only=True)['seconds']
    estimator, seconds = bench_architectures.fit_timed(config, data, 'cpu', state)
    assert [record['epoch'] for record in estimator.history_] == [1, 2, 3]
    assert seconds > estimator.resumed_seconds_ == trained_before > 0


def test_old_points_keep_the_device_of_their_call_when_a_gpu_call_resumes_them(bench, tmp_path,
                                                                                monkeypatch):
    import hashlib

    from support.toy_windows import toy
    data = toy(recordings_per_class=7, windows=2)
    data.save(tmp_path / 'toy.npz')
    out = kept(tmp_path / 'out', 'call cpu', {'extratrees@2': {'accuracy': [0.5],
                                                               'seconds': [1.0]}})
    summary = json.loads((out / 'learning_curves.json').read_text())
    summary.update(dataset=hashlib.sha256(data.X.tobytes()).hexdigest()[:16], sizes=[2])
    (out / 'learning_curves.json').write_text(json.dumps(summary))
    monkeypatch.setattr(sys, 'argv', [
        'bench_learning_curves.py', '--data', str(tmp_path / 'toy.npz'), '--sizes', '2',
        '--test', '5', '--models', 'extratrees', '--device', 'cuda', '--out', str(out)])
    assert bench.main() == 0
    points = json.loads((out / 'learning_curves.json').read_text())['points']
    assert points['extratrees@2'] == {'accuracy': [0.5], 'seconds': [1.0], 'device': 'cpu'}


def test_a_deep_points_training_state_goes_once_the_point_is_kept(bench, tmp_path,
                                                                  monkeypatch):
    from support.toy_windows import toy
    toy(recordings_per_class=7, windows=2).save(tmp_path / 'toy.npz')
    out = tmp_path / 'out'
    monkeypatch.setattr(sys, 'argv', [
        'bench_learning_curves.py', '--data', str(tmp_path / 'toy.npz'), '--sizes', '2',
        '--models', 'cnn_3', '--epochs', '2', '--out', str(out)])
    assert bench.main() == 0
    points = json.loads((out / 'learning_curves.json').read_text())['points']
    assert points['cnn_3@2']['device'] == 'cpu' and len(points['cnn_3@2']['accuracy']) == 1
    assert not [path for path in out.rglob('*.pt*')]  # its finished state was forgotten


def test_a_point_trained_on_a_gpu_joins_the_cpu_curves_and_says_where_it_ran(bench, tmp_path,
                                                                            monkeypatch):
    cpu = {'accuracy': [0.5], 'seconds': [1000.0]}
    kept_cpu = kept(tmp_path / 'cpu', 'call cpu', {'bilstm_1@5': cpu})
    gpu = kept(tmp_path / 'gpu', 'call gpu', {'bilstm_1@10': {
        'accuracy': [0.6], 'seconds': [40.0], 'device': 'cuda'}})
    summary = json.loads((gpu / 'learning_curves.json').read_text())
    (gpu / 'learning_curves.json').write_text(json.dumps({**summary, 'device': 'cuda'}))
    monkeypatch.setattr(sys, 'argv', ['bench_learning_curves.py', '--merge', 'cpu', 'gpu'])
    assert bench.merge([kept_cpu, gpu], tmp_path / 'out', [5, 10], ['bilstm_1']) == 0
    merged = json.loads((tmp_path / 'out' / 'learning_curves.json').read_text())
    assert merged['points']['bilstm_1@5']['device'] == 'cpu'  # the call's, kept per point
    assert merged['points']['bilstm_1@10']['device'] == 'cuda'
    table = (tmp_path / 'out' / 'learning_curves.md').read_text()
    assert '| bilstm_1 | 50.0 % (1000 s) | 60.0 % (40 s) (cuda) |' in table
    assert 'A device in brackets: the point trained there' in table


def test_calls_on_another_set_or_settings_are_not_merged(bench, tmp_path, capsys):
    first = kept(tmp_path / 'a', 'call a', {})
    other = kept(tmp_path / 'b', 'call b', {})
    summary = json.loads((other / 'learning_curves.json').read_text())
    (other / 'learning_curves.json').write_text(json.dumps({**summary, 'epochs': 50}))
    assert bench.merge([first, other], tmp_path / 'out', [5], ['bilstm_1']) == 1
    assert 'another set or settings' in capsys.readouterr().err
    assert not (tmp_path / 'out').exists()
