# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex record`: any label text arrives intact, and its recorder never outlives it."""

import json
import os
from pathlib import Path
import signal
import subprocess
import sys
import time

import pytest
from support.processes import alive, wait_for

from tactex.launching.environment import ros_environment

pytestmark = [pytest.mark.integration, pytest.mark.ros, pytest.mark.slow]
TACTEX = Path(sys.executable).parent / 'tactex'
AWKWARD_LABEL = 'wood: "oak" \'x\' -p output:=/etc --ros-args\ntrue 3 {a: b} 😀 é'


def start(out: Path, *extra: str) -> subprocess.Popen:
    log = open(out.with_name('record.log'), 'w')  # the process keeps it open
    return subprocess.Popen([str(TACTEX), 'record', '--out', str(out), *extra],
                            env=ros_environment(), stdout=log, stderr=subprocess.STDOUT)


def node_is_up(out: Path) -> bool:
    return 'recording to' in out.with_name('record.log').read_text()


def children(pid: int) -> list[int]:
    found = subprocess.run(['pgrep', '-P', str(pid)], capture_output=True, text=True)
    return [int(p) for p in found.stdout.split()]


def publish_until_a_part_exists(ros_context, out: Path) -> None:
    import rclpy
    from std_msgs.msg import Bool

    from tactex_common import topics
    from tactex_common.ros import COMMAND
    node = rclpy.create_node('record_test_publisher', context=ros_context)
    publisher = node.create_publisher(Bool, topics.SWEEP_ACTIVE, COMMAND)
    try:
        assert wait_for(lambda: publisher.publish(Bool(data=True)) or any(
            out.glob('part_*')), 30), 'the recorder wrote nothing'
        for _ in range(5):
            publisher.publish(Bool(data=False))
            time.sleep(0.05)
    finally:
        node.destroy_node()


def recorded_metadata(out: Path) -> dict:
    from rosbags.highlevel import AnyReader
    with AnyReader([sorted(out.glob('part_*'))[0]]) as reader:
        connection = next(c for c in reader.connections if c.topic == '/recording/metadata')
        _, _, raw = next(reader.messages(connections=[connection]))
        return json.loads(reader.deserialize(raw, connection.msgtype).data)


@pytest.mark.parametrize('options, expected', [
    ([], {}),
    (['--label', AWKWARD_LABEL, '--trial', '7', '--meta', 'operator=a: b', '--meta',
      'empty='], {'label': AWKWARD_LABEL, 'trial': 7, 'operator': 'a: b', 'empty': ''}),
], ids=['no-optional-arguments', 'awkward-text'])
def test_record_keeps_any_metadata_text_exactly(tmp_path, ros_context, options, expected):
    out = tmp_path / 'recording'
    process = start(out, *options)
    try:
        publish_until_a_part_exists(ros_context, out)
        process.send_signal(signal.SIGINT)
        # A hang guard, not a timing claim.
        assert process.wait(timeout=90) == 0, (tmp_path / 'record.log').read_text()
    finally:
        if process.poll() is None:
            process.kill()
    assert recorded_metadata(out) == expected


def test_record_with_sim_time_logs_sweep_segments_on_the_simulation_clock(tmp_path,
                                                                         ros_context):
    import rclpy
    from rosbags.highlevel import AnyReader
    from rosgraph_msgs.msg import Clock
    from std_msgs.msg import Bool

    from tactex_common import topics
    from tactex_common.ros import COMMAND
    out = tmp_path / 'recording'
    process = start(out, '--use-sim-time')
    node = rclpy.create_node('record_sim_time_test', context=ros_context)
    clock = node.create_publisher(Clock, '/clock', 10)
    active = node.create_publisher(Bool, topics.SWEEP_ACTIVE, COMMAND)
    simulated = Clock()
    simulated.clock.sec = 1000  # a simulation 1000 s in: far from any wall-clock time

    def tick() -> bool:
        clock.publish(simulated)
        active.publish(Bool(data=True))
        return any(out.glob('part_*'))
    try:
        assert wait_for(tick, 30), 'the recorder wrote nothing'
        for _ in range(5):
            tick()
            time.sleep(0.05)
        process.send_signal(signal.SIGINT)
        assert process.wait(timeout=90) == 0, (tmp_path / 'record.log').read_text()
    finally:
        node.destroy_node()
        if process.poll() is None:
            process.kill()
    with AnyReader(sorted(out.glob('part_*'))) as reader:
        segments = [c for c in reader.connections if c.topic == topics.SWEEP_ACTIVE]
        logged = [log_ns for _, log_ns, _ in reader.messages(connections=segments)]
    # Messages that came before the node's first /clock carry time 0; none the wall clock.
    assert logged and all(log_ns <= 1001 * 10**9 for log_ns in logged)
    assert any(log_ns >= 1000 * 10**9 for log_ns in logged)


@pytest.mark.parametrize('stop', [signal.SIGTERM, signal.SIGKILL], ids=['SIGTERM', 'SIGKILL'])
def test_killing_record_never_leaves_the_recorder_running(tmp_path, stop):
    process = start(tmp_path / 'recording')
    recorder = []
    try:
        assert wait_for(lambda: recorder.extend(children(process.pid)) or recorder, 20)
        assert wait_for(lambda: node_is_up(tmp_path / 'recording'), 30)
        os.kill(process.pid, stop)
        process.wait(timeout=20)
        assert wait_for(lambda: not alive(recorder[0]), 20), 'recorder_node outlived tactex'
    finally:
        for pid in [process.pid, *recorder]:
            if alive(pid):
                os.kill(pid, signal.SIGKILL)
    if stop == signal.SIGTERM:
        assert process.returncode == 0
