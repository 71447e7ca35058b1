# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""A stand-in for the sensor node and a classifier_node under test, for the live-path tests.

`SensorStandIn` publishes the raw tactile topics as teensy_node does (ax carries the
texture: a 20 Hz vibration on the ridged one) with chip noise, and can play faults:
stamps off by any amount, a burst of packed stamps, jitter, frozen or saturated IMU
samples, a value beyond float32.
"""

from pathlib import Path
import subprocess
import sys
import time

import numpy as np

from tactex.launching.environment import ros_environment
from tactex_classify.models.baselines import MiniRocketRidge
from tactex_classify.online.runtime import export_onnx
from tactex_classify.training.deep_classifier import DeepClassifier, TrainingConfig

BIN = Path(sys.executable).parent
RATE_HZ = 120.0
PERIOD_NS = int(1e9 / RATE_HZ)
CLASSES = ['smooth', 'ridged']
GYRO_NOISE = 0.003  # rad/s, about the LSM9DS0's at 245 dps


def training_windows(count, window, rng):
    """Class 1 has a 20 Hz vibration on ax, class 0 none; gravity on az, 101 kPa."""
    X = rng.normal(0, 0.05, (count, window, 10))
    t = np.arange(window) / RATE_HZ
    y = np.arange(count) % 2
    X[y == 1, :, 0] += np.sin(2 * np.pi * 20 * t)
    X[:, :, 2] += 9.8
    X[:, :, 9] += 101_000
    return X.astype(np.float32), y


def write_checkpoints(folder: Path) -> Path:
    """A MiniRocket (window 32) and a cnn_3 with its ONNX export (window 96) in `folder`."""
    rng = np.random.default_rng(0)
    X, y = training_windows(40, 32, rng)
    MiniRocketRidge(dilations=3).fit(X, y, CLASSES).save(folder / 'minirocket', hop=16,
                                                         sampling_rate_hz=RATE_HZ)
    X, y = training_windows(40, 96, rng)
    deep = DeepClassifier(TrainingConfig(model='cnn_3', epochs=2)).fit(X, y, CLASSES)
    export_onnx(deep.save(folder / 'cnn', hop=48, sampling_rate_hz=RATE_HZ))
    return folder


def start_node(checkpoint, *params):
    """classifier_node as a process of its own, contact 'always', quick diagnostics."""
    args = [BIN / 'classifier_node', '--ros-args', '-p', f'checkpoint:={checkpoint}',
            '-p', 'contact:=always', '-p', 'diagnostics_period_s:=0.3',
            '-p', 'wait_warn_period_s:=0.5']
    for param in params:
        args += ['-p', param]
    return subprocess.Popen(args, env=ros_environment(), stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)


def stop(process):
    """SIGTERM, then the output (SIGKILL after 10 s)."""
    process.terminate()
    try:
        return process.communicate(timeout=10)[0]
    except subprocess.TimeoutExpired:
        process.kill()
        return process.communicate()[0]


class SensorStandIn:
    """Publishes the raw tactile topics; collects texture/estimate and diagnostics."""

    def __init__(self, context, *extra_nodes):
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
        for node in (self.node, *extra_nodes):
            self.executor.add_node(node)
        self.sample = 0
        self.rng = np.random.default_rng(0)
        self.classes = (Imu, MagneticField, FluidPressure)

    def stamp_ns(self) -> int:
        return self.node.get_clock().now().nanoseconds

    def publish_one(self, stamp_ns, ridged, *, gyro=None, ax=None):
        """One sample on each topic stamped `stamp_ns` (gyro: fixed values, else noise)."""
        from builtin_interfaces.msg import Time
        Imu, MagneticField, FluidPressure = self.classes
        i, self.sample = self.sample, self.sample + 1
        sec, nanosec = divmod(int(stamp_ns), 10**9)
        imu = Imu()
        imu.header.stamp, imu.header.frame_id = Time(sec=sec, nanosec=nanosec), 'sensor_link'
        vibration = float(np.sin(2 * np.pi * 20 * i / RATE_HZ)) * ridged
        imu.linear_acceleration.x = vibration if ax is None else ax
        imu.linear_acceleration.z = 9.8
        w = gyro if gyro is not None else self.rng.normal(0, GYRO_NOISE, 3)
        imu.angular_velocity.x, imu.angular_velocity.y, imu.angular_velocity.z = map(float, w)
        mag = MagneticField()
        mag.header = imu.header
        pressure = FluidPressure(fluid_pressure=101_000.0)
        pressure.header = imu.header
        for publisher, message in ((self.imu, imu), (self.mag, mag),
                                   (self.pressure, pressure)):
            publisher.publish(message)
        self.executor.spin_once(timeout_sec=0)

    def publish(self, seconds, ridged, *, offset_ns=0, jitter_ns=0, gyro=None, ax=None):
        """Stream `seconds` of signal at RATE_HZ, paced in real time.

        Each sample is stamped now + `offset_ns`, +- `jitter_ns` (uniform).
        """
        start = time.monotonic()
        for k in range(int(seconds * RATE_HZ)):
            jitter = int(self.rng.uniform(-jitter_ns, jitter_ns)) if jitter_ns else 0
            self.publish_one(self.stamp_ns() + offset_ns + jitter, ridged, gyro=gyro, ax=ax)
            delay = start + (k + 1) / RATE_HZ - time.monotonic()
            if delay > 0:
                time.sleep(delay)

    def spin_until(self, condition, timeout_s):
        deadline = time.monotonic() + timeout_s
        while not condition() and time.monotonic() < deadline:
            self.executor.spin_once(timeout_sec=0.05)
        return condition()

    def spin_for(self, seconds):
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            self.executor.spin_once(timeout_sec=0.05)

    def values(self):
        """The newest diagnostics' key-values."""
        return {kv.key: kv.value for kv in self.diagnostics[-1].values}
