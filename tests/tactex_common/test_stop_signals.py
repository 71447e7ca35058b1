# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Every command and node that runs until stopped stops cleanly on SIGINT, SIGTERM and SIGHUP.

Each is started as nohup, a background job of a script or a CI runner would start it:
SIGINT inherited as ignored, no terminal. It must still stop on each of the three
signals, with exit code 0 and no traceback; a batch job reports the signal and leaves no
half-written output.
"""

from contextlib import contextmanager
from pathlib import Path
import signal
import subprocess
import sys
import time

import pytest
from support.processes import wait_for

from tactex.launching.environment import ros_environment

pytestmark = [pytest.mark.integration, pytest.mark.ros, pytest.mark.slow]
BIN = Path(sys.executable).parent
STOP_SIGNALS = [signal.SIGINT, signal.SIGTERM, signal.SIGHUP]
SIGNAL_IDS = [s.name for s in STOP_SIGNALS]
# A hang guard, not a timing claim.
STOP_GUARD_S = 30
TRACES = ('Traceback', 'KeyboardInterrupt', 'RCLError')


@contextmanager
def started_like_a_background_job(command: list[str], log: Path,
                                  watched_node: str | None = None, ros_context=None):
    """Run `command` with SIGINT ignored, no terminal and its own session; killed after.

    Yields the process and, when `watched_node` is named, a function telling whether
    that node is in the ROS graph.
    """
    import rclpy
    with open(log, 'w') as out:
        process = subprocess.Popen(
            command, env=ros_environment(), stdin=subprocess.DEVNULL, stdout=out,
            stderr=subprocess.STDOUT, start_new_session=True,
            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_IGN))
    watcher = None if watched_node is None else rclpy.create_node(
        'stop_signal_test', context=ros_context)
    try:
        yield process, lambda: watched_node in watcher.get_node_names()
    finally:
        if watcher is not None:
            watcher.destroy_node()
        if process.poll() is None:
            process.kill()
            process.wait()


def stop_and_check(process: subprocess.Popen, stop_signal: int, log: Path,
                   expected_code: int = 0) -> str:
    """Send `stop_signal`; the process ends with `expected_code` and no traceback."""
    process.send_signal(stop_signal)
    try:
        code = process.wait(timeout=STOP_GUARD_S)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait()
        pytest.fail(f'did not stop within {STOP_GUARD_S} s of {stop_signal.name}:\n'
                    f'{log.read_text()}')
    output = log.read_text()
    assert code == expected_code, output
    assert not any(trace in output for trace in TRACES), output
    return output


@pytest.mark.parametrize('stop_signal', STOP_SIGNALS, ids=SIGNAL_IDS)
@pytest.mark.parametrize('node, parameters', [
    ('madgwick_node', []),
    ('mujoco_bridge', []),
    ('recorder_node', ['-p', 'output:={out}']),
])
def test_a_node_stops_on_each_signal(tmp_path, ros_context, stop_signal, node, parameters):
    log = tmp_path / 'node.log'
    command = [str(BIN / node), '--ros-args',
               *(p.format(out=tmp_path / 'rec') for p in parameters)]
    with started_like_a_background_job(command, log, node, ros_context) as (process, up):
        assert wait_for(up, 60), f'{node} did not come up:\n{log.read_text()}'
        stop_and_check(process, stop_signal, log)


@pytest.mark.parametrize('stop_signal', STOP_SIGNALS, ids=SIGNAL_IDS)
def test_tactex_record_stops_on_each_signal_and_closes_its_bag(tmp_path, ros_context,
                                                                stop_signal):
    log = tmp_path / 'record.log'
    out = tmp_path / 'recording'
    with started_like_a_background_job([str(BIN / 'tactex'), 'record', '--out', str(out)],
                                       log, 'recorder_node', ros_context) as (process, up):
        assert wait_for(up, 60), log.read_text()
        assert wait_for(lambda: 'recording to' in log.read_text(), 30), log.read_text()
        output = stop_and_check(process, stop_signal, log)
    assert 'recorded 0 messages' in output  # the node closed its recorder


@pytest.mark.parametrize('stop_signal', STOP_SIGNALS, ids=SIGNAL_IDS)
def test_tactex_launch_stops_every_node_on_each_signal(tmp_path, ros_context, stop_signal):
    log = tmp_path / 'launch.log'
    with started_like_a_background_job([str(BIN / 'tactex'), 'launch', 'sim'], log,
                                       'mujoco_bridge', ros_context) as (process, up):
        assert wait_for(up, 60), log.read_text()
        output = stop_and_check(process, stop_signal, log)
    started = output.count('[launch] started')
    assert started >= 1 and 'exited with code' not in output, output


@pytest.mark.parametrize('stop_signal', STOP_SIGNALS, ids=SIGNAL_IDS)
@pytest.mark.parametrize('device', ['teensy', 'dynamixel'])
def test_tactex_emulate_stops_on_each_signal_and_removes_its_link(tmp_path, stop_signal,
                                                                   device):
    log = tmp_path / 'emulate.log'
    link = tmp_path / 'link'
    with started_like_a_background_job(
            [str(BIN / 'tactex'), 'emulate', device, '--link', str(link)], log) as (process, _):
        assert wait_for(lambda: ' on ' in log.read_text(), 30), log.read_text()
        stop_and_check(process, stop_signal, log)
    assert not link.exists()


@pytest.mark.parametrize('stop_signal', STOP_SIGNALS, ids=SIGNAL_IDS)
def test_a_batch_job_reports_the_signal_and_leaves_nothing_half_written(tmp_path,
                                                                        stop_signal):
    log = tmp_path / 'collect.log'
    out = tmp_path / 'bags'
    with started_like_a_background_job(
            [str(BIN / 'tactex'), 'sim', 'collect', '--out', str(out), '--sweeps', '3',
             '--workers', '1'], log) as (process, _):
        assert wait_for(lambda: any(tmp_path.glob('.bags.partial-*')), 60), log.read_text()
        time.sleep(1.0)  # inside the job
        output = stop_and_check(process, stop_signal, log, expected_code=128 + stop_signal)
    assert f'error: stopped by {stop_signal.name}' in output
    assert list(tmp_path.iterdir()) == [log]
