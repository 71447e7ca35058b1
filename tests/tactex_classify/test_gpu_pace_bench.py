# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""bench/bench_gpu_pace.py refuses bad input before it starts a cell, and never keeps junk.

Bad input is one `error:` line on stderr and exit status 1; the kept calls in --out (a
copy of the kept results here) stay as they were, and no PNG is drawn. The runs are the
GPU's, so without one (CUDA hidden here) the bench measures nothing and says so.
"""

import json
import os
from pathlib import Path
import re
import shutil
import subprocess
import sys

import pytest
from support.badinputs import toy_dataset
from support.scripts import load_script, ROOT

SCRIPT = ROOT / 'bench' / 'bench_gpu_pace.py'
KEPT = ROOT / 'bench' / 'results' / 'gpu_pace.json'
NO_GPU = {**os.environ, 'CUDA_VISIBLE_DEVICES': ''}

pytestmark = pytest.mark.integration


@pytest.fixture
def pace(monkeypatch):
    monkeypatch.syspath_prepend(str(ROOT / 'bench'))  # its sibling modules
    return load_script('bench/bench_gpu_pace.py')


@pytest.fixture
def out(tmp_path) -> Path:
    """A copy of the kept calls, as --out."""
    return Path(shutil.copy(KEPT, tmp_path / 'gpu_pace.json'))


@pytest.fixture
def data(tmp_path) -> Path:
    return toy_dataset(3).save(tmp_path / 'toy.npz')


def bench(*argv) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, argv)], capture_output=True,
                          text=True, timeout=120, env=NO_GPU, stdin=subprocess.DEVNULL)


def assert_refused(code: int, stderr: str, *words: str) -> None:
    assert code == 1, stderr
    assert stderr.startswith('error: ') and stderr.count('\n') == 1, stderr
    assert all(word in stderr for word in words), stderr


def assert_kept(out: Path) -> None:
    assert out.read_bytes() == KEPT.read_bytes()
    assert not out.with_suffix('.png').exists()


def test_without_a_gpu_nothing_starts_and_nothing_is_written(out, data):
    result = bench('--runs', 'cnn_3:1', '--data', data, '--out', out)
    assert_refused(result.returncode, result.stderr, 'no CUDA device', 'GPU machine')
    assert_kept(out)


@pytest.mark.parametrize('argv, words', [
    (['--runs', ''], ['--runs', 'at least one MODEL:CELLS']),
    (['--runs', ','], ['--runs', 'at least one MODEL:CELLS']),
    (['--runs', 'nosuchmodel:1'], ['--runs', "unknown model 'nosuchmodel'"]),
    (['--runs', 'resnet:65'], ['--runs', 'CELLS must be a whole number in 1..64']),
    (['--runs', 'cnn_3:1:fast'], ['--runs', 'MODEL:CELLS[:mps][:autotune]']),
    (['--epochs', 'resnet:0'], ['--epochs', 'MODEL:EPOCHS', 'EPOCHS must be a whole number']),
    (['--epochs', 'cnn_3'], ['--epochs', 'is not MODEL:EPOCHS']),
    (['--epochs', 'cnn_3:x'], ['--epochs', 'is not MODEL:EPOCHS']),
    (['--epochs', 'cnn_3:1:2'], ['--epochs', 'is not MODEL:EPOCHS']),
    (['--start-timeout', '-1'], ['--start-timeout', 'finite number > 0']),
    (['--run-timeout', 'nan'], ['--run-timeout', 'finite number > 0']),
    (['--start-timeout', 'abc'], ['--start-timeout', 'finite number > 0']),
    (['--device', 'banana'], ['--device', 'cuda']),
])
def test_a_bad_option_is_one_error_line_and_nothing_starts(out, data, argv, words):
    result = bench('--data', data, '--out', out, *argv)
    assert_refused(result.returncode, result.stderr, *words)
    assert_kept(out)


@pytest.mark.parametrize('files, words', [
    ({'missing.npz': None}, 'does not exist'),
    ({'set.npz': 'folder'}, 'is a folder'),
    ({'notes.txt': b'some text'}, 'give a converted dataset (.npz)'),
    ({'junk.npz': b'junk', 'junk.json': b'{}'}, 'is not a tactex dataset'),
])
def test_data_that_is_not_a_tactex_dataset_is_refused_before_any_cell(out, tmp_path, files,
                                                                      words):
    for name, content in files.items():
        if content == 'folder':
            (tmp_path / name).mkdir()
        elif content:
            (tmp_path / name).write_bytes(content)
    result = bench('--runs', 'cnn_3:1', '--data', tmp_path / next(iter(files)), '--out', out)
    assert_refused(result.returncode, result.stderr, '--data', words)
    assert_kept(out)


@pytest.mark.parametrize('where, words', [
    (lambda folder: folder, ['is a folder']),
    (lambda folder: Path('/proc/nope/gpu_pace.json'), ['not writable']),
])
def test_an_unwritable_out_is_refused_before_any_cell(tmp_path, data, where, words):
    result = bench('--runs', 'cnn_3:1', '--data', data, '--out', where(tmp_path))
    assert_refused(result.returncode, result.stderr, '--out', *words)


def test_cells_that_all_fail_report_their_error_and_append_nothing(pace, out, data,
                                                                    monkeypatch, capsys):
    # Past the GPU check, each cell fails on the CUDA device hidden from it.
    monkeypatch.setattr(pace, 'cuda_available', lambda: True)
    monkeypatch.setattr(pace, 'raise_on_stop_signals', lambda: None)
    monkeypatch.setenv('CUDA_VISIBLE_DEVICES', '')
    code = pace.main(['--runs', 'cnn_3:1', '--data', str(data), '--out', str(out)])
    stderr = capsys.readouterr().err
    assert_refused(code, stderr, '--runs cnn_3 x1: no cell trained', 'nothing written')
    assert re.search('cuda|nvidia', stderr, re.IGNORECASE) and 'not ready' not in stderr
    assert_kept(out)


@pytest.mark.parametrize('kept', [
    {'calls': [1, 2]},
    {'calls': [{}]},
    {'calls': [{'machine': {'gpu': None}, 'runs': 'xyz'}]},
    {'calls': [{'machine': {'gpu': None},
                'runs': [{'cells': 1, 'mps': False, 'cell_epochs_per_s': 1.0}]}]},
    {'calls': [{'runs': [{'model': 'cnn_3', 'cells': 1, 'mps': False,
                          'cell_epochs_per_s': 1.0}]}]},
    {'calls': [{'machine': {'gpu': None},
                'runs': [{'model': 'cnn_3', 'cells': 1, 'mps': False,
                          'cell_epochs_per_s': 'fast'}]}]},
    [],
])
def test_plot_refuses_a_file_that_is_not_a_gpu_pace_result(tmp_path, kept):
    path = tmp_path / 'pace.json'
    path.write_text(json.dumps(kept))
    result = bench('--plot', '--out', path)
    assert_refused(result.returncode, result.stderr, f'--out {path}', 'not a gpu_pace result')
    assert not path.with_suffix('.png').exists()


def test_plot_draws_the_kept_calls_again(out):
    result = bench('--plot', '--out', out)
    assert result.returncode == 0, result.stderr
    assert out.with_suffix('.png').stat().st_size > 0
    assert out.read_bytes() == KEPT.read_bytes()
