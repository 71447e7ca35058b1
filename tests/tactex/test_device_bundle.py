# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""tools/device_bundle.py replaces only a bundle it wrote, and only once the new one is whole.

pip is faked (no network here): a download writes stand-in wheels, or fails as pip does.
"""

import os
from pathlib import Path
import subprocess
import sys
import tarfile
import zipfile

import pytest
from support.badinputs import toy_dataset
from support.scripts import load_script

from tactex_classify.data.dataset import Dataset

ROOT = Path(__file__).resolve().parents[2]
PIP_FAILURE = ('ERROR: Could not find a version that satisfies the requirement rosbags==0.11.9\n'
               'ERROR: No matching distribution found for rosbags==0.11.9\n')


def _ray_wheel(path: Path, unused: tuple[str, ...]) -> None:
    with zipfile.ZipFile(path, 'w') as wheel:
        wheel.writestr('ray/__init__.py', '')
        wheel.writestr('ray/core/src/ray/raylet/raylet', b'\x7fELF binary')
        wheel.writestr('ray/_raylet.so', b'\x7fELF library')
        for part in unused:
            wheel.writestr(f'{part}/__init__.py', '')


@pytest.fixture
def tool(monkeypatch):
    """The tool as a module whose pip downloads stand-ins; `tool.pip_fails` makes them fail."""
    module = load_script('tools/device_bundle.py')
    module.pip_fails = False
    module.pip_calls = 0
    module.stripped_files = []
    real_run = subprocess.run

    def run(command, *args, **kwargs):
        if command[:2] == ['strip', '--strip-unneeded']:  # stands in for binutils' strip
            module.stripped_files += [Path(name).name for name in command[2:]]
            return subprocess.CompletedProcess(command, 0, None, '')
        if command[1:4] != ['-m', 'pip', 'download']:
            return real_run(command, *args, **kwargs)
        module.pip_calls += 1
        if module.pip_fails:
            if kwargs.get('check'):
                raise subprocess.CalledProcessError(1, command, None, PIP_FAILURE)
            return subprocess.CompletedProcess(command, 1, None, PIP_FAILURE)
        into = Path(command[command.index('-d') + 1])
        for spec in command[command.index('-d') + 2:]:
            name, version = spec.split('==')
            wheel = into / f'{name}-{version}-cp312-cp312-manylinux_2_28_x86_64.whl'
            if name == 'ray':
                _ray_wheel(wheel, module.RAY_UNUSED)
            else:
                wheel.write_bytes(b'wheel')
        return subprocess.CompletedProcess(command, 0, None, '')

    monkeypatch.setattr(subprocess, 'run', run)
    return module


def _main(tool, monkeypatch, *args: str) -> int:
    monkeypatch.setattr(sys, 'argv', ['device_bundle.py', *args])
    return tool.main()


def _snapshot(folder: Path) -> dict[str, bytes]:
    return {str(path.relative_to(folder)): path.read_bytes()
            for path in sorted(folder.rglob('*')) if path.is_file()}


def _one_error_line(capsys) -> str:
    err = capsys.readouterr().err
    assert err.startswith('error: ') and err.count('\n') == 1, err
    assert 'Traceback' not in err
    return err


@pytest.fixture
def dataset(tmp_path):
    data = tmp_path / 'input'
    data.mkdir()
    (data / 'sim.npz').write_bytes(b'npz')
    (data / 'sim.json').write_text('{}')
    return data / 'sim.npz'


def test_a_bundle_is_written_whole_with_its_mark(tool, monkeypatch, capsys, tmp_path, dataset):
    out = tmp_path / 'parent' / 'bundle'
    out.parent.mkdir()
    assert _main(tool, monkeypatch, '--out', str(out), '--data', str(dataset)) == 0
    assert f'{out}: ' in capsys.readouterr().out
    names = set(_snapshot(out))
    assert {'run.sh', 'ray.tar.xz', 'data.tar.xz', tool.MARK} <= names
    with tarfile.open(out / 'data.tar.xz') as archive:
        assert sorted(archive.getnames()) == ['sim.json', 'sim.npz']
    assert len([name for name in names if name.startswith('wheels/')]) == len(tool.PACKAGES)
    mark = (out / tool.MARK).read_text().splitlines()
    assert mark[0] == tool.MARK_LINE and set(mark[1:]) == names - {tool.MARK}
    assert [path.name for path in out.parent.iterdir()] == ['bundle']  # no temporary left


def test_an_earlier_bundle_is_replaced_by_the_new_one(tool, monkeypatch, capsys, tmp_path,
                                                      dataset):
    out = tmp_path / 'bundle'
    assert _main(tool, monkeypatch, '--out', str(out), '--data', str(dataset)) == 0
    assert _main(tool, monkeypatch, '--out', str(out)) == 0
    assert not (out / 'data' / 'sim.npz').exists() and (out / 'run.sh').is_file()
    assert sorted(path.name for path in tmp_path.iterdir()) == ['bundle', 'input']


def test_a_user_folder_with_a_run_sh_is_refused_and_kept(tool, monkeypatch, capsys, tmp_path):
    out = tmp_path / 'thesis'
    (out / 'src').mkdir(parents=True)
    (out / 'run.sh').write_text('#!/bin/sh\nmake\n')
    (out / 'src' / 'thesis.tex').write_text('\\documentclass{book}')
    before = _snapshot(out)
    assert _main(tool, monkeypatch, '--out', str(out)) == 1
    err = _one_error_line(capsys)
    assert f'--out {out} exists and is no bundle of this tool' in err and 'new folder' in err
    assert _snapshot(out) == before and tool.pip_calls == 0
    assert [path.name for path in tmp_path.iterdir()] == ['thesis']


def test_a_bundle_holding_a_users_file_is_refused_and_kept(tool, monkeypatch, capsys, tmp_path):
    out = tmp_path / 'bundle'
    assert _main(tool, monkeypatch, '--out', str(out)) == 0
    (out / 'notes.txt').write_text('mine')
    capsys.readouterr()
    before = _snapshot(out)
    assert _main(tool, monkeypatch, '--out', str(out)) == 1
    err = _one_error_line(capsys)
    assert 'files this tool did not write (notes.txt)' in err
    assert _snapshot(out) == before


def test_a_failed_download_leaves_no_folder_behind(tool, monkeypatch, capsys, tmp_path):
    tool.pip_fails = True
    out = tmp_path / 'bundle'
    assert _main(tool, monkeypatch, '--out', str(out)) == 1
    err = _one_error_line(capsys)
    assert err.startswith('error: downloading wheels for cp312 (11 packages) failed (pip exited '
                          '1): ERROR: No matching distribution found for rosbags==0.11.9; check '
                          'the package index is reachable')
    assert list(tmp_path.iterdir()) == []
    tool.pip_fails = False  # and a rerun is not blocked by anything left
    assert _main(tool, monkeypatch, '--out', str(out)) == 0


def test_a_failed_rebuild_leaves_the_earlier_bundle_as_it_was(tool, monkeypatch, capsys,
                                                              tmp_path, dataset):
    out = tmp_path / 'bundle'
    assert _main(tool, monkeypatch, '--out', str(out), '--data', str(dataset)) == 0
    before = _snapshot(out)
    capsys.readouterr()
    tool.pip_fails = True
    assert _main(tool, monkeypatch, '--out', str(out)) == 1
    assert 'downloading wheels for cp312' in _one_error_line(capsys)
    assert _snapshot(out) == before
    assert sorted(path.name for path in tmp_path.iterdir()) == ['bundle', 'input']


def test_a_symbolic_link_out_is_refused_and_its_folder_kept(tool, monkeypatch, capsys, tmp_path):
    real = tmp_path / 'real'
    assert _main(tool, monkeypatch, '--out', str(real)) == 0  # even a bundle of this tool
    capsys.readouterr()
    before = _snapshot(real)
    link = tmp_path / 'link'
    link.symlink_to(real, target_is_directory=True)
    assert _main(tool, monkeypatch, '--out', str(link)) == 1
    assert f'--out {link} is a symbolic link' in _one_error_line(capsys)
    assert link.is_symlink() and _snapshot(real) == before


def test_data_that_is_a_folder_is_named_as_one(tool, monkeypatch, capsys, tmp_path, dataset):
    out = tmp_path / 'bundle'
    assert _main(tool, monkeypatch, '--out', str(out), '--data', str(dataset.parent)) == 1
    err = _one_error_line(capsys)
    assert f'--data {dataset.parent} is a folder' in err and '.npz' in err
    assert 'no such file' not in err and not out.exists()


@pytest.mark.integration
def test_without_a_package_index_the_command_says_so_in_one_line(tmp_path):
    """The real pip, told to use no index, fails at once: one line, nothing written."""
    out = tmp_path / 'bundle'
    result = subprocess.run([sys.executable, str(ROOT / 'tools' / 'device_bundle.py'),
                             '--out', str(out)], capture_output=True, text=True, timeout=120,
                            env={**os.environ, 'PIP_NO_INDEX': '1'})
    assert result.returncode == 1, result.stderr
    assert result.stderr.startswith('error: downloading wheels for cp312')
    assert result.stderr.count('\n') == 1 and 'Traceback' not in result.stderr
    assert list(tmp_path.iterdir()) == []


def test_rays_programs_and_libraries_are_stripped_and_nothing_else(tool, monkeypatch, capsys,
                                                                   tmp_path):
    assert _main(tool, monkeypatch, '--out', str(tmp_path / 'bundle')) == 0
    assert sorted(tool.stripped_files) == ['_raylet.so', 'raylet']


def test_without_strip_the_bundle_is_refused_in_one_line(tool, monkeypatch, capsys, tmp_path):
    monkeypatch.setattr(tool.shutil, 'which', lambda name: None)
    assert _main(tool, monkeypatch, '--out', str(tmp_path / 'bundle')) == 1
    assert 'install binutils' in _one_error_line(capsys)
    assert not (tmp_path / 'bundle').exists()


@pytest.mark.skipif(not (ROOT / '.git').exists(), reason='the working tree is what git lists')
def test_a_bundle_that_does_not_fit_beside_the_working_tree_is_one_error_line(
        tool, monkeypatch, capsys, tmp_path):
    tree = tool.working_tree_bytes()
    monkeypatch.setattr(tool, 'CARRY_LIMIT', tree)  # the tree alone fills what a call carries
    assert _main(tool, monkeypatch, '--out', str(tmp_path / 'bundle')) == 1
    assert 'over the' in _one_error_line(capsys)


def test_a_dataset_travels_as_the_same_arrays_stored_for_xz(tool, monkeypatch, capsys, tmp_path):
    data = toy_dataset(3).save(tmp_path / 'input' / 'toy.npz')
    assert _main(tool, monkeypatch, '--out', str(tmp_path / 'bundle'), '--data', str(data)) == 0
    with tarfile.open(tmp_path / 'bundle' / 'data.tar.xz') as archive:
        archive.extractall(tmp_path / 'unpacked', filter='data')
    carried = tmp_path / 'unpacked' / 'toy.npz'
    with zipfile.ZipFile(carried) as npz:
        assert {member.compress_type for member in npz.infolist()} == {zipfile.ZIP_STORED}
    assert Dataset.load(carried).digest() == Dataset.load(data).digest()
    sidecar = data.with_suffix('.json').read_bytes()
    assert (tmp_path / 'unpacked' / 'toy.json').read_bytes() == sidecar


def test_two_data_files_of_one_name_are_refused_in_one_line(tool, monkeypatch, capsys, tmp_path,
                                                            dataset):
    other = tmp_path / 'elsewhere' / 'sim.npz'
    other.parent.mkdir()
    other.write_bytes(b'npz')
    assert _main(tool, monkeypatch, '--out', str(tmp_path / 'bundle'), '--data', str(dataset),
                 str(other)) == 1
    assert 'names sim.npz more than once' in _one_error_line(capsys)
    assert not (tmp_path / 'bundle').exists()
