# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""MPS for a block: started privately, refused with the reason, always quit, env restored."""

import os
from pathlib import Path
import subprocess
import sys
import tempfile

import pytest

from tactex_common import gpu_sharing
from tactex_common.errors import GpuSharingError
from tactex_common.gpu_sharing import multi_process_service

PIPE = 'CUDA_MPS_PIPE_DIRECTORY'


@pytest.fixture
def control(tmp_path, monkeypatch):
    """A stand-in control program on PATH that logs its calls; FAKE_MPS_EXIT sets -d's exit.

    The service's temporary folders go under tmp_path: one it keeps on purpose (a daemon
    that did not confirm quitting) must not be left in the machine's /tmp by the suite.
    """
    monkeypatch.setattr(tempfile, 'tempdir', str(tmp_path))
    calls = tmp_path / 'calls.log'
    program = tmp_path / 'bin' / gpu_sharing.CONTROL
    program.parent.mkdir()
    program.write_text('#!/bin/sh\n'
                       'if [ "$1" = "-d" ]; then\n'
                       f'  echo "start $CUDA_MPS_PIPE_DIRECTORY" >> {calls}\n'
                       '  echo "daemon refused" >&2; exit "${FAKE_MPS_EXIT:-0}"\n'
                       'fi\n'
                       f'echo "$(cat) $CUDA_MPS_PIPE_DIRECTORY" >> {calls}\n'
                       'exit "${FAKE_MPS_QUIT_EXIT:-0}"\n')
    program.chmod(0o755)
    monkeypatch.setenv('PATH', f'{program.parent}{os.pathsep}{os.environ["PATH"]}')
    monkeypatch.delenv(PIPE, raising=False)
    return calls


def client(tmp_path, body: str) -> str:
    """A stand-in for torch's interpreter: runs `body` as its CUDA client."""
    program = tmp_path / 'python'
    program.write_text(f'#!/bin/sh\n{body}\n')
    program.chmod(0o755)
    return str(program)


def test_the_service_sets_its_clients_variables_for_the_block_then_quits(tmp_path, control):
    with multi_process_service(python=client(tmp_path, 'exit 0')) as variables:
        pipe = variables[PIPE]
        assert os.environ[PIPE] == pipe and Path(pipe).is_dir()
        seen = subprocess.run([sys.executable, '-c', f'import os; print(os.environ["{PIPE}"])'],
                              capture_output=True, text=True, check=True).stdout.strip()
        assert seen == pipe  # a child process (a Ray worker) inherits them
    assert PIPE not in os.environ
    assert control.read_text().splitlines() == [f'start {pipe}', f'quit {pipe}']
    assert not Path(pipe).exists()  # the private folders go with the daemon


def test_a_variable_set_before_the_block_is_restored(tmp_path, control, monkeypatch):
    monkeypatch.setenv(PIPE, '/elsewhere')
    with multi_process_service(python=client(tmp_path, 'exit 0')):
        assert os.environ[PIPE] != '/elsewhere'
    assert os.environ[PIPE] == '/elsewhere'


def test_without_the_control_program_the_reason_and_the_way_out_are_named(monkeypatch,
                                                                          tmp_path):
    monkeypatch.setenv('PATH', str(tmp_path))
    monkeypatch.setattr(gpu_sharing, 'DRIVER_BIN', tmp_path)
    with pytest.raises(GpuSharingError, match='nvidia-cuda-mps-control not found .*share the '
                                              'GPU without MPS'):
        with multi_process_service():
            pass


def test_a_daemon_that_will_not_start_is_reported_with_its_message(tmp_path, control,
                                                                   monkeypatch):
    monkeypatch.setenv('FAKE_MPS_EXIT', '3')
    with pytest.raises(GpuSharingError, match='-d exited 3: daemon refused; share the GPU '
                                              'without MPS'):
        with multi_process_service(python=client(tmp_path, 'exit 0')):
            pass
    assert PIPE not in os.environ
    # a daemon that forked before its launcher failed is asked to quit all the same
    assert [line.split()[0] for line in control.read_text().splitlines()] == ['start', 'quit']


def test_a_daemon_that_never_started_leaves_no_warning_and_no_folder(tmp_path, control,
                                                                    monkeypatch, capsys):
    monkeypatch.setenv('FAKE_MPS_EXIT', '1')
    monkeypatch.setenv('FAKE_MPS_QUIT_EXIT', '1')  # nobody answers the quit: none ran
    with pytest.raises(GpuSharingError, match='-d exited 1'):
        with multi_process_service(python=client(tmp_path, 'exit 0')):
            pass
    assert 'warning' not in capsys.readouterr().err
    pipe = control.read_text().split()[1]
    assert not Path(pipe).parent.exists()


def test_a_daemon_that_does_not_confirm_quitting_keeps_its_folders_and_says_how_to_stop_it(
        tmp_path, control, monkeypatch, capsys):
    monkeypatch.setenv('FAKE_MPS_QUIT_EXIT', '1')
    with multi_process_service(python=client(tmp_path, 'exit 0')) as variables:
        pipe = variables[PIPE]
    warning = capsys.readouterr().err
    assert f'echo quit | CUDA_MPS_PIPE_DIRECTORY={pipe}' in warning
    assert 'nvidia-cuda-mps-control exited 1' in warning
    assert Path(pipe).is_dir()  # the pipe a running daemon listens on is not pulled away
    assert Path(pipe).parent.parent == tmp_path


def test_a_client_that_fails_stops_the_daemon_and_leaves_the_environment(tmp_path, control):
    python = client(tmp_path, 'echo "RuntimeError: MPS client failed" >&2; exit 1')
    with pytest.raises(GpuSharingError, match='a CUDA client failed under MPS: RuntimeError: '
                                              'MPS client failed; share the GPU without MPS'):
        with multi_process_service(python=python):
            pass
    assert PIPE not in os.environ
    assert [line.split()[0] for line in control.read_text().splitlines()] == ['start', 'quit']


def test_a_client_that_never_attaches_is_given_up_on(tmp_path, control, monkeypatch):
    monkeypatch.setattr(gpu_sharing, 'CLIENT_TIMEOUT_S', 0.5)
    with pytest.raises(GpuSharingError, match='did not attach to MPS within 0.5 s; share the '
                                              'GPU without MPS'):
        with multi_process_service(python=client(tmp_path, 'exec sleep 30')):
            pass
    assert control.read_text().splitlines()[-1].startswith('quit')
