# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Helpers of the tests that run nodes as processes: waiting, checking and stopping them."""

from contextlib import contextmanager
from pathlib import Path
import signal
import subprocess
import sys
import time

STOP_TIMEOUT_S = 10.0


def alive(pid: int) -> bool:
    """Whether process `pid` exists and is not a zombie (from /proc/PID/stat)."""
    try:
        state = Path(f'/proc/{pid}/stat').read_text().split(')')[-1].split()[0]
    except FileNotFoundError:
        return False
    return state != 'Z'


def wait_for(condition, timeout_s: float) -> bool:
    """Poll `condition` every 50 ms for up to `timeout_s`; its last value."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(0.05)
    return bool(condition())


def stop(processes, stop_signal: int = signal.SIGTERM) -> list[str]:
    """Signal each process, wait 10 s, SIGKILL what remains; the names of those killed.

    Never raises, so that a test's own failure is the one reported.
    """
    for process in processes:
        if process.poll() is None:
            process.send_signal(stop_signal)
    stubborn = []
    for process in processes:
        try:
            process.wait(timeout=STOP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()
            stubborn.append(Path(str(process.args[0])).name)
    return stubborn


@contextmanager
def running_nodes(commands: dict[str, list], folder: Path):
    """Start each named command line with its log folder/NAME.log; SIGINT them all after."""
    from tactex.launching.environment import ros_environment
    logs = {name: open(folder / f'{name}.log', 'w') for name in commands}
    nodes = [subprocess.Popen(argv, env=ros_environment(), stdout=logs[name],
                              stderr=subprocess.STDOUT) for name, argv in commands.items()]
    try:
        yield nodes
    finally:
        stop(nodes, signal.SIGINT)
        for log in logs.values():
            log.close()


def tactex(*argv: str, timeout_s: float = 600) -> subprocess.CompletedProcess:
    """Run the installed `tactex ARGV` in the ROS environment; its output captured."""
    from tactex.launching.environment import ros_environment
    return subprocess.run([Path(sys.executable).parent / 'tactex', *argv], capture_output=True,
                          text=True, env=ros_environment(), timeout=timeout_s)
