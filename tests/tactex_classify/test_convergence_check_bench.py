# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""bench/bench_convergence_check.py checks the grid, the data and --out before it trains.

A grid that is not one `tactex compare` wrote (of one window), data other than the grid's,
or a bad number is one `error:` line and exit status 1; a grid with no unconverged cell
has nothing to check and writes nothing. Every case writes into a --out of its own.
"""

from dataclasses import asdict
import json
from pathlib import Path
import subprocess
import sys

import pytest
from support.scripts import ROOT
from support.toy_windows import toy

from tactex_classify.evaluation.model_grid import Cell, GridSettings, GridStore

SCRIPT = ROOT / 'bench' / 'bench_convergence_check.py'
CELL = Cell(seed=0, fold=1, scheme='grouped', window=128, model='cnn_1')
# A training whose loss still fell at its last epoch: the check trains it again.
UNCONVERGED = {'cell': asdict(CELL), 'accuracy': 0.5, 'epochs_run': 3,
               'train_losses': [1.2, 1.1, 1.0], 'config': {'epochs': 3}}

pytestmark = pytest.mark.integration


def check(*argv) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, argv)], capture_output=True,
                          text=True, timeout=300, stdin=subprocess.DEVNULL)


def assert_refused(result: subprocess.CompletedProcess, *words: str) -> None:
    assert result.returncode == 1, result.stderr
    assert result.stderr.startswith('error: ') and result.stderr.count('\n') == 1, \
        result.stderr
    assert all(word in result.stderr for word in words), result.stderr


def grid(folder: Path, cells: list[dict] = ()) -> Path:
    """A grid of one window (128) on a toy dataset, written as `tactex compare` does."""
    dataset = toy(recordings_per_class=5, windows=4, window=128)
    source = dataset.save(folder.parent / f'{folder.name}-data.npz')
    store = GridStore(folder)
    store.open(GridSettings(epochs=2, profile='modern', scaling='window'), {128: dataset},
               {128: str(source)})
    for result in cells:
        store.save(Cell(**result['cell']), result)
    return folder


def manifest(tmp_path: Path, change) -> Path:
    """A grid whose grid.json `change(manifest)` made."""
    folder = grid(tmp_path / 'grid')
    path = folder / 'grid.json'
    path.write_text(json.dumps(change(json.loads(path.read_text()))))
    return folder


@pytest.mark.parametrize('make, words', [
    (lambda tmp: tmp / 'missing', ['does not exist']),
    (lambda tmp: tmp, ['has no grid.json']),
    (lambda tmp: (tmp / 'grid.txt').write_text('x') and tmp / 'grid.txt', ['is a file']),
    (lambda tmp: (tmp / 'grid.json').write_text('{garbage') and tmp,
     ['not a tactex comparison manifest']),
    (lambda tmp: manifest(tmp, lambda kept: []), ['not a tactex comparison manifest']),
    (lambda tmp: manifest(tmp, lambda kept: {'data': kept['data']}),
     ['not a tactex comparison manifest']),
    (lambda tmp: manifest(tmp, lambda kept: {**kept, 'settings': {'bogus': 1}}),
     ['not a tactex comparison manifest']),
    (lambda tmp: manifest(tmp, lambda kept: {**kept, 'data': {'128': kept['data']['128'],
                                                               '256': kept['data']['128']}}),
     ['holds 2 windows (128, 256)', 'one window']),
])
def test_a_grid_that_is_not_a_comparison_of_one_window_is_one_error_line(tmp_path, make, words):
    result = check('--grid', make(tmp_path), '--out', tmp_path / 'check.json')
    assert_refused(result, '--grid', *words)
    assert not (tmp_path / 'check.json').exists()


@pytest.mark.parametrize('option', ['--cpus', '--epochs'])
def test_counts_below_one_are_refused(tmp_path, option):
    result = check('--grid', grid(tmp_path / 'grid', [UNCONVERGED]), option, '0', '--out',
                   tmp_path / 'check.json')
    assert_refused(result, f'argument {option}', 'whole number')


def test_a_grid_without_unconverged_cells_has_nothing_to_check_and_writes_nothing(tmp_path):
    result = check('--grid', grid(tmp_path / 'grid'), '--out', tmp_path / 'check.json')
    assert result.returncode == 0, result.stderr
    assert 'nothing to check, nothing written' in result.stdout
    assert not (tmp_path / 'check.json').exists()


@pytest.mark.parametrize('files, words', [
    ({'junk.npz': b'junk', 'junk.json': b'{}'}, ['is not a tactex dataset']),
    ({'folder.npz': None}, ['is a folder']),
])
def test_data_that_is_not_a_dataset_is_refused_before_any_worker(tmp_path, files, words):
    for name, content in files.items():
        if content is None:
            (tmp_path / name).mkdir()
        else:
            (tmp_path / name).write_bytes(content)
    result = check('--grid', grid(tmp_path / 'grid', [UNCONVERGED]), '--data',
                   tmp_path / next(iter(files)), '--out', tmp_path / 'check.json')
    assert_refused(result, '--data', *words)
    assert not (tmp_path / 'check.json').exists()


def test_data_other_than_the_grids_is_refused(tmp_path):
    other = toy(recordings_per_class=5, windows=4, window=128, seed=1).save(tmp_path / 'o.npz')
    result = check('--grid', grid(tmp_path / 'grid', [UNCONVERGED]), '--data', other, '--out',
                   tmp_path / 'check.json')
    assert_refused(result, f'--data {other} is not the dataset the grid was run on')
    assert not (tmp_path / 'check.json').exists()


def test_an_unconverged_cell_is_trained_again_into_out(tmp_path):
    out = tmp_path / 'new' / 'check.json'
    result = check('--grid', grid(tmp_path / 'grid', [UNCONVERGED]), '--cpus', '1', '--out', out)
    assert result.returncode == 0, result.stderr
    kept = json.loads(out.read_text())
    assert (kept['grid_epochs'], kept['epochs']) == (2, 4)
    assert [row['cell'] for row in kept['cells']] == [asdict(CELL)]
    assert kept['cells'][0]['before'] == {'accuracy': 0.5, 'epochs': 3}
