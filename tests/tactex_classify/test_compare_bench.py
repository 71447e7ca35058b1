# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""bench/bench_compare.py: a kept grid's data, rebuilt by the commit that made them, checked."""

import json
import os
from pathlib import Path
import subprocess
import sys

import pytest
from support.badinputs import toy_dataset
from support.scripts import load_script

from tactex_classify.evaluation.model_grid import GridSettings, GridStore

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def bench():
    return load_script('bench/bench_compare.py')


def kept_grid(folder: Path, data: Path) -> None:
    """A grid started on `data` (window 32)."""
    toy_dataset(3).save(data)
    GridStore(folder).open(GridSettings(), {32: toy_dataset(3)}, {32: str(data)})


def test_the_data_a_grid_was_started_with_pass_and_other_data_are_refused(bench, tmp_path):
    kept_grid(tmp_path / 'grid', tmp_path / 'same.npz')
    bench.check_kept_data(tmp_path / 'grid', {32: tmp_path / 'same.npz'})
    toy_dataset(4).save(tmp_path / 'other.npz')
    with pytest.raises(SystemExit, match=r'^error: .*other data for window 32.*data_recipe'):
        bench.check_kept_data(tmp_path / 'grid', {32: tmp_path / 'other.npz'})


def test_any_data_start_a_grid_not_yet_kept(bench, tmp_path):
    toy_dataset(4).save(tmp_path / 'data.npz')
    bench.check_kept_data(tmp_path / 'new grid', {32: tmp_path / 'data.npz'})


def test_an_unknown_commit_is_one_error_line(bench):
    with pytest.raises(SystemExit, match=r'^error: --code no-such-commit: not a commit of'):
        bench.resolve_commit('no-such-commit')


def test_without_git_the_recipe_names_no_commit(bench, monkeypatch):
    def no_git(*arguments):
        raise FileNotFoundError('git')
    monkeypatch.setattr(bench, '_git', no_git)
    assert bench.resolve_commit(None) is None


@pytest.mark.skipif(not (ROOT / '.git').exists(), reason='needs a git checkout')
def test_a_commit_runs_from_its_own_worktree_removed_after(bench, tmp_path):
    head = bench.resolve_commit('HEAD')
    assert len(head) == 40
    tree = tmp_path / f'code-{head[:12]}'
    tree.mkdir()
    (tree / 'left by a killed run').write_text('')
    with bench.worktree_env(head, tmp_path) as env:
        assert not (tree / 'left by a killed run').exists()
        paths = env['PYTHONPATH'].split(os.pathsep)
        assert str(tree / 'src' / 'tactex_sim') in paths
        found = subprocess.run([sys.executable, '-c', 'import tactex_sim as m; print(m.__file__)'],
                               env=env, capture_output=True, text=True, check=True)
        assert Path(found.stdout.strip()).is_relative_to(tree)
    assert not tree.exists()
    listed = subprocess.run(['git', 'worktree', 'list'], cwd=ROOT, capture_output=True,
                            text=True, check=True).stdout
    assert str(tree) not in listed


def option(words: list[str], name: str) -> str:
    return words[words.index(name) + 1]


def test_the_device_script_resumes_the_kept_full_grid_on_its_data_and_settings():
    script = (ROOT / 'tools' / 'device_grid.sh').read_text(encoding='utf-8')
    call = script.split('python3 bench/bench_compare.py')[1].split('status=')[0]
    words = call.replace('\\\n', ' ').split()
    run = json.loads((ROOT / 'bench/results/compare_gpu_full/run.json').read_text())
    compare = [step['command'].split() for kept in run['calls'] for step in kept['steps']
               if step['command'].startswith('tactex compare')][-1]
    for name in ('--epochs', '--folds', '--seeds', '--cpus', '--cv', '--early-stopping',
                 '--profile', '--scaling', '--device', '--cells-per-gpu'):
        assert option(words, name) == option(compare, name), name
    assert '--mps' in words and '--mps' in compare
    assert option(words, '--grid') == 'compare_gpu_full'
    assert option(words, '--work') == '.device/data'  # where .device/run.sh unpacks the data
    recipe = run['data_recipe']
    assert option(words, '--recordings') == str(recipe['recordings_per_texture'])
    assert option(words, '--windows') == ','.join(map(str, recipe['windows']))
    assert f'--sweeps {recipe["sweeps"]} --code {recipe["code"][:12]} --data-only' in script
    assert '--exclude=training_state' in script  # a cell's state stays on the machine
