# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The recorder: a real stream to part bags; a kill loses at most the last second."""

import os
from pathlib import Path
import signal
import subprocess
import sys
import threading
import time

import pytest

from tactex.launching.environment import ros_environment
from tactex_classify.data.bags import read_recording
from tactex_classify.data.dataset import convert
from tactex_sensor.emulator import Motion, SignalSource, TeensyEmulator

pytestmark = [pytest.mark.integration, pytest.mark.ros, pytest.mark.slow]
BIN = Path(sys.executable).parent
RATE_HZ = 200.0


def record(tmp_path, stop_signal, seconds=3.5):
    link = tmp_path / 'teensy'
    out = tmp_path / 'recording'
    env = ros_environment()
    with TeensyEmulator(link, RATE_HZ, SignalSource(Motion.SWAY)) as emulator:
        streamer = threading.Thread(target=emulator.run, args=(seconds + 6.0,), daemon=True)
        streamer.start()
        sensor = subprocess.Popen([BIN / 'teensy_node', '--ros-args', '-p', f'port:={link}'],
                                  env=env)
        recorder = subprocess.Popen(
            [BIN / 'tactex', 'record', '--out', str(out), '--label', 'wood', '--trial', '4',
             '--surface', 'flat', '--meta', 'operator=ci'], env=env)
        try:
            deadline = time.monotonic() + 20
            while not list(out.glob('part_*')) and time.monotonic() < deadline:
                time.sleep(0.05)
            started = time.monotonic()
            time.sleep(seconds)
            recorded_s = time.monotonic() - started
            # Signal the node itself (the tactex command's child).
            child = subprocess.run(['pgrep', '-P', str(recorder.pid)], capture_output=True,
                                   text=True).stdout.split()
            for pid in child:
                os.kill(int(pid), stop_signal)
            recorder.wait(timeout=10)
        finally:
            sensor.terminate()
            sensor.wait(timeout=10)
            if recorder.poll() is None:
                recorder.kill()
    return out, recorded_s


def test_killed_recorder_loses_at_most_the_last_second(tmp_path):
    out, recorded_s = record(tmp_path, signal.SIGKILL)
    parts = sorted(out.glob('part_*'))
    assert len(parts) >= 3
    recording = read_recording(out)
    assert recording.dropped['unreadable_parts'] <= 1
    assert recording.metadata['label'] == 'wood' and recording.metadata['trial'] == 4
    assert recording.metadata['operator'] == 'ci'
    samples = len(recording.stamps_ns)
    assert samples >= (recorded_s - 1.5) * RATE_HZ * 0.9
    data = convert([out], window=50, hop=25, all_samples=True, progress=lambda line: None)
    assert data.classes == ['wood'] and len(data.X) > 5


def test_stopped_recorder_closes_every_part(tmp_path):
    out, _ = record(tmp_path, signal.SIGINT, seconds=2.0)
    parts = sorted(out.glob('part_*'))
    assert parts and all((p / 'metadata.yaml').is_file() for p in parts)
    assert read_recording(out).dropped['unreadable_parts'] == 0
