# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Every subcommand meets garbage: one `error:` line, exit 1, nothing touched outside --out.

Each case's single error line names the argument and the fix; no output holds a traceback.
"""

import hashlib
import json
import os
from pathlib import Path
import re
import subprocess
import sys

import pytest
from support.badinputs import BAD_INPUTS, make_workspace, toy_dataset

from tactex.cli import main

TACTEX = Path(sys.executable).parent / 'tactex'
CASES = [pytest.param(case, id=f'{command}: {case!r}'[:100])
         for command, cases in BAD_INPUTS.items() for case in cases]


@pytest.fixture(scope='module')
def workspace(tmp_path_factory):
    folder = make_workspace(tmp_path_factory.mktemp('bad_inputs'))
    yield folder
    (folder / 'readonly').chmod(0o755)


def snapshot(root: Path, out: Path | None) -> dict:
    """Every path under root (but `out` and what lies under it) with its content hash."""
    state = {}
    for path in sorted(root.rglob('*')):
        if out is not None and (path == out or out in path.parents):
            continue
        stat = path.lstat()
        digest = hashlib.sha1(path.read_bytes()).hexdigest() if path.is_file() else ''
        state[str(path.relative_to(root))] = (stat.st_mode, digest)
    return state


def check(case, workspace: Path, run) -> None:
    """Run a case with `run(argv) -> (code, stdout, stderr)` and assert the contract."""
    if case.needs_non_root and os.geteuid() == 0:
        pytest.skip('root may write anywhere')
    out = Path(case.out.replace('{w}', str(workspace))) if case.out else None
    before = snapshot(workspace, out)
    code, stdout, stderr = run(case.resolved(workspace))
    assert 'Traceback' not in stdout + stderr, stdout + stderr
    assert code == 1, stdout + stderr
    errors = [line for line in stderr.splitlines() if line.startswith('error:')]
    assert len(errors) == 1, stderr
    assert re.search(case.match, errors[0]), errors[0]
    assert snapshot(workspace, out) == before, 'something outside --out changed'
    if out is not None and out.exists() and not out.is_symlink():
        assert out.name in ('folder', 'full', 'grid', 'text.txt'), f'{out} was written'


def in_process(capsys):
    def run(argv):
        try:
            code = main(argv)
        except SystemExit as exit_:
            code = exit_.code
        captured = capsys.readouterr()
        return code, captured.out, captured.err
    return run


@pytest.mark.parametrize('case', CASES)
def test_bad_input_ends_in_one_error_line(case, workspace, capsys):
    check(case, workspace, in_process(capsys))


def test_every_subcommand_has_a_table_of_bad_inputs():
    from tactex.cli import COMMANDS
    assert set(COMMANDS) | {'tactex'} == set(BAD_INPUTS)
    assert all(len(cases) >= 2 for cases in BAD_INPUTS.values())


# Runs cases as the console script does (`sys.exit(main())`), in a fresh interpreter with
# real stdout/stderr, so output from any layer (C extensions, child processes, logging)
# is seen; each case's output follows a marker line.
HARNESS = """
import json, sys, traceback
from tactex.cli import main
for argv in json.loads(sys.argv[1]):
    for stream in (sys.stdout, sys.stderr):
        print('@@case', flush=True, file=stream)
    try:
        code = main(argv)
    except SystemExit as exit_:
        code = exit_.code
    except BaseException:
        traceback.print_exc()
        code = 'traceback'
    sys.stdout.flush()
    print(f'@@code {code}', file=sys.stderr, flush=True)
"""


def run_command_cases(cases, workspace):
    argvs = [case.resolved(workspace) for case in cases]
    result = subprocess.run([sys.executable, '-c', HARNESS, json.dumps(argvs)],
                            capture_output=True, text=True, timeout=300,
                            stdin=subprocess.DEVNULL)
    outs = result.stdout.split('@@case\n')[1:]
    errs = result.stderr.split('@@case\n')[1:]
    assert len(outs) == len(errs) == len(cases), result.stderr[-2000:]
    return [(case, out, err) for case, out, err in zip(cases, outs, errs, strict=True)]


@pytest.mark.slow
def test_scan_every_subcommand_table_for_tracebacks(workspace):
    """Each command's table in a fresh interpreter, and the installed script for one case."""
    results = []
    for cases in BAD_INPUTS.values():
        runnable = [c for c in cases if not (c.needs_non_root and os.geteuid() == 0)]
        results += run_command_cases(runnable, workspace)
        code, out, err = run_console_script(runnable[-1].resolved(workspace))
        results.append((runnable[-1], out, err + f'@@code {code}'))
    tracebacks = [repr(case) for case, out, err in results if 'Traceback' in out + err]
    wrong = [repr(case) for case, _, err in results if not err.rstrip().endswith('@@code 1')]
    assert not tracebacks and not wrong, (tracebacks, wrong)


def run_console_script(argv):
    result = subprocess.run([str(TACTEX), *argv], capture_output=True, text=True, timeout=120,
                            stdin=subprocess.DEVNULL)
    return result.returncode, result.stdout, result.stderr


def test_compare_with_an_address_nothing_answers_at_ends_in_one_error(tmp_path):
    # It used to wait more than 180 s inside Ray's client, deaf to SIGTERM; the timeout
    # only guards the test.
    data = toy_dataset(3).save(tmp_path / 'data.npz')
    result = subprocess.run([str(TACTEX), 'compare', str(data),
                             '--out', str(tmp_path / 'grid'), '--address', '127.0.0.1:1'],
                            capture_output=True, text=True, timeout=120,
                            stdin=subprocess.DEVNULL)
    assert result.returncode == 1, result.stderr
    assert result.stderr.strip() == ('error: cannot reach Ray at 127.0.0.1:1: Connection '
                                     'refused; start the head with `ray start --head` and give '
                                     'the address it prints')
    assert not (tmp_path / 'grid').exists()


def test_compare_with_mps_where_it_cannot_start_writes_no_grid(tmp_path, capsys, monkeypatch):
    from tactex_classify.evaluation import model_grid
    from tactex_common import gpu_sharing
    monkeypatch.setattr(model_grid, 'cuda_available', lambda: True)  # a GPU without MPS
    monkeypatch.setattr(gpu_sharing, 'DRIVER_BIN', tmp_path / 'nowhere')
    monkeypatch.setenv('PATH', str(tmp_path / 'nowhere'))
    data = toy_dataset(3).save(tmp_path / 'data.npz')
    code, _, stderr = in_process(capsys)(['compare', str(data), '--out', str(tmp_path / 'grid'),
                                          '--mps', '--models', 'bilstm_1'])
    assert code == 1
    assert stderr.strip().splitlines()[-1] == (
        'error: --mps: nvidia-cuda-mps-control not found (on PATH or in '
        f"{tmp_path / 'nowhere'}): install NVIDIA's driver utilities, or share the GPU "
        'without MPS')
    assert not (tmp_path / 'grid').exists()
