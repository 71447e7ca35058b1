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
    assert summary['points']['bilstm_1@10'] == old
    assert summary['replaced'] == {'bilstm_1@5': {**old, 'by': 'call c'}}
    assert summary['calls'] == ['call a', 'call b', 'call c']  # a merged folder's, one by one
    table = (tmp_path / 'out' / 'learning_curves.md').read_text()
    assert '- bilstm_1 at n = 5: 7.0 % (100 s), replaced by `call c`' in table
