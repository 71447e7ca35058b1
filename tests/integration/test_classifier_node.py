# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""classifier_node: waits for the sensor, classifies live, refuses what it does not fit."""

import os
from pathlib import Path
import subprocess
import sys
import time

import numpy as np
import pytest

from tactex.ros_env import ros_environment
from tactex_classify.baselines import MiniRocketRidge
from tactex_classify.classifier import DeepClassifier, TrainingConfig
from tactex_classify.runtime import export_onnx

pytestmark = [pytest.mark.ros, pytest.mark.slow]
BIN = Path(sys.executable).parent
RATE_HZ = 120.0
CLASSES = ['smooth', 'ridged']


def windows(count, window, rng):
    """Class 1 has a 20 Hz vibration on ax, class 0 none; gravity on az, 101 kPa."""
    X = rng.normal(0, 0.05, (count, window, 10))
    t = np.arange(window) / RATE_HZ
    y = np.arange(count) % 2
    X[y == 1, :, 0] += np.sin(2 * np.pi * 20 * t)
    X[:, :, 2] += 9.8
    X[:, :, 9] += 101_000
    return X.astype(np.float32), y


@pytest.fixture(scope='module')
def checkpoints(tmp_path_factory):
    folder = tmp_path_factory.mktemp('checkpoints')
    rng = np.random.default_rng(0)
    X, y = windows(40, 32, rng)
    MiniRocketRidge(dilations=3).fit(X, y, CLASSES).save(folder / 'minirocket', hop=16,
                                                         sampling_rate_hz=RATE_HZ)
    X, y = windows(40, 96, rng)
    deep = DeepClassifier(TrainingConfig(model='cnn_3', epochs=2)).fit(X, y, CLASSES)
    export_onnx(deep.save(folder / 'cnn', hop=48, sampling_rate_hz=RATE_HZ))
    return folder


def start_node(checkpoint, *params):
    args = [BIN / 'classifier_node', '--ros-args', '-p', f'checkpoint:={checkpoint}',
            '-p', 'contact:=always', '-p', 'diagnostics_period_s:=0.3',
            '-p', 'wait_warn_period_s:=0.5']
    for param in params:
        args += ['-p', param]
    return subprocess.Popen(args, env=ros_environment(), stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)


class SensorStandIn:
    """Publishes the raw tactile topics as teensy_node does (ax carries the texture)."""

    def __init__(self, context):
        from diagnostic_msgs.msg import DiagnosticArray
        import rclpy
        from rclpy.qos import qos_profile_sensor_data
        from sensor_msgs.msg import FluidPressure, Imu, MagneticField

        from tactex_msgs.msg import TextureEstimate
        self.node = rclpy.create_node('classifier_test', context=context)
        self.imu = self.node.create_publisher(Imu, 'tactile/imu/data_raw', qos_profile_sensor_data)
        self.mag = self.node.create_publisher(MagneticField, 'tactile/imu/mag',
                                              qos_profile_sensor_data)
        self.pressure = self.node.create_publisher(FluidPressure, 'tactile/pressure',
                                                   qos_profile_sensor_data)
        self.estimates, self.diagnostics = [], []
        self.node.create_subscription(TextureEstimate, 'texture/estimate', self.estimates.append,
                                      10)
        self.node.create_subscription(DiagnosticArray, 'diagnostics',
                                      lambda m: self.diagnostics.extend(m.status), 10)
        self.executor = rclpy.executors.SingleThreadedExecutor(context=context)
        self.executor.add_node(self.node)
        self.sample = 0
        self.classes = (Imu, MagneticField, FluidPressure)

    def publish(self, seconds, ridged):
        """Stream `seconds` of signal at RATE_HZ, paced in real time."""
        Imu, MagneticField, FluidPressure = self.classes
        start = time.monotonic()
        for k in range(int(seconds * RATE_HZ)):
            i, self.sample = self.sample, self.sample + 1
            stamp = self.node.get_clock().now().to_msg()
            imu = Imu()
            imu.header.stamp, imu.header.frame_id = stamp, 'sensor_link'
            imu.linear_acceleration.x = float(np.sin(2 * np.pi * 20 * i / RATE_HZ)) * ridged
            imu.linear_acceleration.z = 9.8
            mag = MagneticField()
            mag.header = imu.header
            pressure = FluidPressure(fluid_pressure=101_000.0)
            pressure.header = imu.header
            for publisher, message in ((self.imu, imu), (self.mag, mag),
                                       (self.pressure, pressure)):
                publisher.publish(message)
            self.executor.spin_once(timeout_sec=0)
            delay = start + (k + 1) / RATE_HZ - time.monotonic()
            if delay > 0:
                time.sleep(delay)

    def spin_until(self, condition, timeout_s):
        deadline = time.monotonic() + timeout_s
        while not condition() and time.monotonic() < deadline:
            self.executor.spin_once(timeout_sec=0.05)
        return condition()

    def values(self):
        return {kv.key: kv.value for kv in self.diagnostics[-1].values}


def stop(process):
    process.terminate()
    try:
        return process.communicate(timeout=10)[0]
    except subprocess.TimeoutExpired:
        process.kill()
        return process.communicate()[0]


def run_stream(context, process, *, smooth_s=2.0, ridged_s=4.0):
    sensor = SensorStandIn(context)
    assert sensor.spin_until(lambda: sensor.diagnostics, 60.0), 'the node never came up'
    time.sleep(1.2)  # long enough for a warning about the silent sensor
    sensor.publish(smooth_s, ridged=0.0)
    # The change to the ridged texture restarts the evidence. The worker may lag the stream
    # and skip windows on a loaded machine, so the ridged part lasts long enough for several
    # classified windows whatever it skips.
    sensor.publish(ridged_s, ridged=1.0)
    sensor.spin_until(lambda: sensor.estimates and sensor.estimates[-1].label == 'ridged', 20.0)
    return sensor


def test_the_node_waits_for_the_sensor_then_classifies_and_reports(checkpoints, ros_context):
    process = start_node(checkpoints / 'minirocket')
    try:
        sensor = run_stream(ros_context, process)
        assert sensor.estimates, 'no texture/estimate'
        last = sensor.estimates[-1]
        assert list(last.class_names) == CLASSES and last.model_id.startswith('minirocket@')
        assert last.label == 'ridged' and last.header.frame_id == 'sensor_edge'
        assert abs(sum(last.probabilities) - 1.0) < 1e-5
        assert len(last.window_starts) == len(last.window_ends) == last.windows_used >= 1
        assert any(e.label == 'smooth' for e in sensor.estimates)
        values = sensor.values()
        assert float(values['latency_p99_ms']) > 0 and values['runtime'] == 'numpy'
        assert 80.0 < float(values['input_rate_hz']) < 160.0
    finally:
        output = stop(process)
    assert 'no samples for' in output and 'tactile/imu/data_raw' in output, output


def test_the_onnxruntime_runtime_runs_without_torch(checkpoints, ros_context):
    process = start_node(checkpoints / 'cnn', 'runtime:=onnxruntime')
    try:
        sensor = run_stream(ros_context, process)
        assert sensor.estimates and sensor.values()['runtime'] == 'onnxruntime'
        maps = Path(f'/proc/{process.pid}/maps').read_text()
        assert 'libtorch' not in maps and 'onnxruntime' in maps
    finally:
        stop(process)


@pytest.mark.parametrize('params, message', [
    (('rate_hz:=350.0',), 'rate: the model was trained at 120 Hz, the stream runs at 350 Hz'),
    (('window:=64',), 'window: the model was trained on 32-sample windows, the stream is cut '
                      'into 64'),
    (("channels:=['ax','ay','az']",), 'channels: the model was trained on ax, ay, az, gx'),
])
def test_a_stream_the_checkpoint_does_not_fit_is_refused_at_start(checkpoints, params,
                                                                  message):
    process = start_node(checkpoints / 'minirocket', *params)
    output = process.communicate(timeout=60)[0]
    assert process.returncode == 1, output
    assert message in output and 'Traceback' not in output, output


def test_a_malicious_checkpoint_is_refused_and_nothing_in_it_runs(checkpoints, tmp_path):
    import json
    import shutil

    import torch

    from tactex_classify.checkpoint import CHECKSUM_FIELD, metadata_sha256, sha256
    folder = shutil.copytree(checkpoints / 'cnn', tmp_path / 'cnn')
    marker = tmp_path / 'pwned'

    class Payload:
        def __reduce__(self):
            return (os.system, (f'touch {marker}',))
    torch.save({'weights': Payload()}, folder / 'weights.pt')
    meta = json.loads((folder / 'checkpoint.json').read_text())
    meta['files'] = {'weights.pt': sha256(folder / 'weights.pt')}
    meta[CHECKSUM_FIELD] = metadata_sha256(meta)
    (folder / 'checkpoint.json').write_text(json.dumps(meta))
    process = start_node(folder)
    output = process.communicate(timeout=60)[0]
    assert process.returncode == 1 and 'refused weights.pt' in output, output
    assert not marker.exists()
