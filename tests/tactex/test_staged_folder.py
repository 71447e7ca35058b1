# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""An output folder appears whole or not at all; what a killed run left is cleared, not reused."""

import os
import subprocess
import sys

import pytest

from tactex.options import staged_folder


def test_the_folder_appears_only_when_the_work_succeeds(tmp_path):
    out = tmp_path / 'out'
    with staged_folder(out) as folder:
        (folder / 'result.txt').write_text('done')
        assert not out.exists()
    assert (out / 'result.txt').read_text() == 'done'
    assert sorted(p.name for p in tmp_path.iterdir()) == ['out']


def test_a_failure_leaves_nothing(tmp_path):
    out = tmp_path / 'out'
    with pytest.raises(RuntimeError), staged_folder(out) as folder:
        (folder / 'half.txt').write_text('half')
        raise RuntimeError('failed')
    assert list(tmp_path.iterdir()) == []


def test_a_staging_left_by_a_killed_run_is_removed_and_said(tmp_path, capsys):
    out = tmp_path / 'out'
    code = ('import os, sys\n'
            'from tactex.options import staged_folder\n'
            f'with staged_folder({str(out)!r}) as folder:\n'
            "    (folder / 'half.txt').write_text('half')\n"
            '    os.kill(os.getpid(), 9)\n')
    assert subprocess.run([sys.executable, '-c', code]).returncode == -9
    [left] = tmp_path.iterdir()
    assert left.name.startswith('.out.partial-')
    with staged_folder(out) as folder:
        assert not left.exists()
        assert list(folder.iterdir()) == []  # a new folder, not the killed run's
    assert f'removed {left}' in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ['out']


def test_a_staging_of_a_run_still_going_is_left_alone(tmp_path):
    out = tmp_path / 'out'
    running = tmp_path / f'.out.partial-{os.getppid()}-0123abcd'
    running.mkdir()
    with staged_folder(out):
        pass
    assert running.is_dir()


def test_a_failed_run_removes_the_folders_it_made_for_out_and_no_others(tmp_path):
    (tmp_path / 'kept').mkdir()
    out = tmp_path / 'kept' / 'made' / 'deeper' / 'report'
    with pytest.raises(RuntimeError), staged_folder(out) as folder:
        (folder / 'half.txt').write_text('half')
        raise RuntimeError('interrupted')
    assert not (tmp_path / 'kept' / 'made').exists() and (tmp_path / 'kept').is_dir()
