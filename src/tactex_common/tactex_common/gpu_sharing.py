# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""NVIDIA's Multi-Process Service (MPS) for a block: processes that share one GPU at once.

Without MPS, processes that share a GPU take turns on it, each with its own context, so
many small trainings (one per grid cell) leave most of it idle while they wait. Under MPS
their kernels run side by side: on one H200, 12 cnn_3 cells trained 2.3 times as fast
together with it as without (`bench/bench_gpu_pace.py`, kept in
bench/results/gpu_pace.json). `multi_process_service` starts a private control daemon
(its pipe and log folders in a temporary folder, so it never meets a daemon another
program started), checks that a CUDA client can attach within `CLIENT_TIMEOUT_S`, sets
the variables its clients need in this process's environment (child processes, Ray's
local workers among them, inherit them), and quits the daemon and restores the
environment on exit.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
import os
from pathlib import Path
import shutil
import subprocess
import sys
import tempfile

from tactex_common.environment import environment_set
from tactex_common.errors import GpuSharingError

CONTROL = 'nvidia-cuda-mps-control'
# Where NVIDIA's container runtime mounts the driver's programs when they are not on PATH.
DRIVER_BIN = Path('/usr/local/nvidia/bin')
CLIENT_TIMEOUT_S = 60.0
DAEMON_TIMEOUT_S = 30.0
# A CUDA client's smallest complete round trip: a context, a kernel, a copy back.
CLIENT_PROBE = "import torch; torch.ones(1, device='cuda').sum().item()"


def control_program() -> str | None:
    """The MPS control program: on PATH, or where the driver's programs are mounted."""
    found = shutil.which(CONTROL)
    if found:
        return found
    mounted = DRIVER_BIN / CONTROL
    return str(mounted) if os.access(mounted, os.X_OK) else None


@contextmanager
def multi_process_service(python: str = sys.executable) -> Iterator[dict[str, str]]:
    """MPS for the block; yields the environment variables its clients need (already set).

    Args:
        python: the interpreter that tries a CUDA client under the daemon (torch's).

    Raises:
        GpuSharingError: no control program, the daemon would not start, or a CUDA
            client could not attach to it (the daemon is asked to quit first).
    """
    control = control_program()
    if control is None:
        raise GpuSharingError(f'{CONTROL} not found (on PATH or in {DRIVER_BIN}): install '
                              "NVIDIA's driver utilities, or share the GPU without MPS")
    folder = Path(tempfile.mkdtemp(prefix='tactex-mps-'))
    variables = {'CUDA_MPS_PIPE_DIRECTORY': str(folder / 'pipe'),
                 'CUDA_MPS_LOG_DIRECTORY': str(folder / 'log')}
    for path in variables.values():
        Path(path).mkdir()
    environment = {**os.environ, **variables}
    started = False
    try:
        _start(control, environment)
        started = True
        _check_client(python, environment)
        with environment_set(variables):
            yield variables
    finally:
        # A launcher that failed may have forked its daemon: ask it to quit all the same,
        # but a quit nobody answers then means none ran (no warning, no folder kept).
        if _quit(control, environment, warn=started) or not started:
            shutil.rmtree(folder, ignore_errors=True)


def _start(control: str, environment: dict[str, str]) -> None:
    """Start the control daemon; raise GpuSharingError (with its reason) if it would not."""
    try:
        started = _run([control, '-d'], environment, DAEMON_TIMEOUT_S)
    except (OSError, subprocess.TimeoutExpired) as err:
        raise GpuSharingError(f'{control} -d could not run ({err}); share the GPU without '
                              'MPS') from None
    if started.returncode:
        raise GpuSharingError(f'{CONTROL} -d exited {started.returncode}: '
                              f'{_last_line(started.stderr)}; share the GPU without MPS')


def _quit(control: str, environment: dict[str, str], *, warn: bool = True) -> bool:
    """Ask the daemon to quit (also one that may not have started); whether it answered.

    With `warn`, one that did not answer is named on stderr with the way to stop it.
    """
    try:
        done = _run([control], environment, DAEMON_TIMEOUT_S, stdin='quit\n')
        failed = f'{CONTROL} exited {done.returncode}' if done.returncode else None
    except (OSError, subprocess.TimeoutExpired) as err:
        failed = str(err)
    if failed and warn:
        pipe = environment['CUDA_MPS_PIPE_DIRECTORY']
        print(f'warning: the MPS daemon did not confirm it quit ({failed}); if it still runs, '
              f'stop it with: echo quit | CUDA_MPS_PIPE_DIRECTORY={pipe} {control}',
              file=sys.stderr)
    return not failed


def _check_client(python: str, environment: dict[str, str]) -> None:
    """Raise GpuSharingError unless a CUDA client attaches to the daemon in time."""
    try:
        probe = _run([python, '-c', CLIENT_PROBE], environment, CLIENT_TIMEOUT_S)
    except OSError as err:
        raise GpuSharingError(f'{python} could not run ({err}); share the GPU without MPS'
                              ) from None
    except subprocess.TimeoutExpired:
        raise GpuSharingError(f'a CUDA client did not attach to MPS within '
                              f'{CLIENT_TIMEOUT_S:g} s; share the GPU without MPS') from None
    if probe.returncode:
        raise GpuSharingError(f'a CUDA client failed under MPS: {_last_line(probe.stderr)}; '
                              'share the GPU without MPS')


def _run(command: list[str], environment: dict[str, str], timeout: float,
         stdin: str | None = None) -> subprocess.CompletedProcess:
    """A short program's run, its output captured."""
    return subprocess.run(command, env=environment, input=stdin, capture_output=True,
                          text=True, timeout=timeout, check=False)


def _last_line(text: str) -> str:
    """The last non-empty line of a program's error output (where it says why)."""
    lines = [line for line in text.strip().splitlines() if line.strip()]
    return lines[-1].strip() if lines else 'no message'
