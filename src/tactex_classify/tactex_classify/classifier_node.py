# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""ROS 2 node classifying the texture under the sensor live, from a `tactex train` checkpoint.

Subscription callbacks only queue samples; a worker thread aligns them, cuts windows,
runs the model and publishes, so a slow model never delays the sensor callbacks: when
windows queue up, only the newest is classified and the others are counted as dropped.
"""

from __future__ import annotations

from collections import deque
import json
import math
import sys
import threading
import time

from builtin_interfaces.msg import Time
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
import numpy as np
from rcl_interfaces.msg import (
    FloatingPointRange,
    IntegerRange,
    ParameterDescriptor,
    SetParametersResult,
)
from rclpy.node import Node
from rclpy.qos import QoSProfile
from sensor_msgs.msg import FluidPressure, Imu, MagneticField
from std_msgs.msg import Bool, String
from visualization_msgs.msg import Marker, MarkerArray

from tactex_classify.bags import ROLE_CHANNELS
from tactex_classify.errors import ClassifyError
from tactex_classify.evidence import EvidenceSettings
from tactex_classify.live import CONTACT_SOURCES, LiveSettings, OnlineClassifier
from tactex_classify.runtime import load_predictor, RUNTIMES
from tactex_common import topics
from tactex_common.ros import COMMAND, SENSOR_DATA, spin
from tactex_common.stamps import stamp_ns
from tactex_msgs.msg import TextureEstimate

ROLE_TOPICS = {'imu': (Imu, topics.IMU_RAW), 'mag': (MagneticField, topics.MAG),
               'pressure': (FluidPressure, topics.PRESSURE)}
LATENCIES_KEPT = 2000  # the p50/p99 of diagnostics are over the newest this many windows
# The worker and the executor share the GIL: a woken worker would wait up to Python's
# default 5 ms switch interval while callbacks run; 0.5 ms bounds that wait.
GIL_SWITCH_INTERVAL_S = 0.0005
# Sensor-data QoS (best effort, volatile) with a deep queue: a busy executor catches up
# on up to 0.7 s of a 350 Hz stream instead of losing samples (each loss is a gap).
SENSOR_QUEUE = QoSProfile(depth=256, reliability=SENSOR_DATA.reliability,
                          durability=SENSOR_DATA.durability, history=SENSOR_DATA.history)


class StartError(Exception):
    """The node cannot start: a refused checkpoint or a stream it does not fit."""


def _values(role: str, message) -> tuple[float, ...]:
    if role == 'imu':
        a, w = message.linear_acceleration, message.angular_velocity
        return (a.x, a.y, a.z, w.x, w.y, w.z)
    if role == 'mag':
        m = message.magnetic_field
        return (m.x, m.y, m.z)
    return (message.fluid_pressure,)


def _time(ns: int) -> Time:
    sec, nanosec = divmod(int(ns), 1_000_000_000)
    return Time(sec=sec, nanosec=nanosec)


class ClassifierNode(Node):
    """Tactile topics -> texture/estimate, texture/markers, diagnostics."""

    def __init__(self, **kwargs) -> None:
        super().__init__('classifier_node', **kwargs)
        p = self._declare_parameters()
        try:
            self._predictor = load_predictor(p['checkpoint'], p['runtime'], threads=p['threads'])
        except (ClassifyError, ValueError, OSError) as err:
            self._refuse(f'checkpoint: {err}')
        info = self._predictor.info
        self._info = info
        mismatches = info.stream.mismatches(
            channels=[c for c in p['channels'] if c] or None, window=p['window'] or None,
            sampling_rate_hz=p['rate_hz'] or None, rate_tolerance=p['rate_tolerance'])
        if mismatches:
            self._refuse(f'{info.model_id} does not fit the stream: ' + '; '.join(mismatches))
        try:
            live = LiveSettings(hop=p['hop'], contact=p['contact'], contact_pa=p['contact_pa'],
                                reorder_s=p['reorder_s'], max_lag_s=p['max_lag_s'])
            self._classifier = OnlineClassifier(
                self._predictor.predict_proba, info.stream, len(info.classes), live=live,
                evidence=EvidenceSettings(p['threshold'], p['min_windows'], p['change_nats']))
        except ValueError as err:
            self._refuse(f'{info.model_id}: {err}')
        self._frame_id = p['frame_id']
        self._rate_tolerance = p['rate_tolerance']
        self._queue: deque = deque()  # (role, stamp_ns, values, arrival_ns) from callbacks
        self._wake = threading.Event()
        self._latencies: deque[float] = deque(maxlen=LATENCIES_KEPT)
        self._lock = threading.Lock()  # guards what diagnostics read from the worker
        self._arrivals: dict[str, int] = dict.fromkeys(self._classifier.windows.needed_roles, 0)
        self._started = time.monotonic()
        self._last_diagnostics = (time.monotonic(), 0)
        self._refusal = ''
        self._last_estimate = None
        self._classified = 0
        self._estimate_pub = self.create_publisher(TextureEstimate, topics.TEXTURE_ESTIMATE,
                                                   COMMAND)
        self._marker_pub = self.create_publisher(MarkerArray, topics.TEXTURE_MARKERS, COMMAND)
        self._diagnostics_pub = self.create_publisher(DiagnosticArray, topics.DIAGNOSTICS,
                                                      COMMAND)
        for role in self._classifier.windows.needed_roles:
            message_type, topic = ROLE_TOPICS[role]
            self.create_subscription(message_type, topic, self._callback(role), SENSOR_QUEUE)
        self.create_subscription(Bool, topics.SWEEP_ACTIVE, self._on_active, COMMAND)
        self.create_subscription(String, topics.RECORDING_METADATA, self._on_metadata,
                                 COMMAND)
        self.create_timer(p['diagnostics_period_s'], self._publish_diagnostics)
        self.create_timer(p['wait_warn_period_s'], self._warn_while_waiting)
        self.add_on_set_parameters_callback(self._on_set_parameters)
        self._running = True
        sys.setswitchinterval(GIL_SWITCH_INTERVAL_S)
        self._worker = threading.Thread(target=self._work, name='classifier', daemon=True)
        self._worker.start()
        self.get_logger().info(
            f'{info.model_id} ({self._predictor.runtime}): {len(info.classes)} classes, '
            f'{info.stream.window}-sample windows at {info.stream.sampling_rate_hz:g} Hz, hop '
            f'{self._classifier.windows.hop}, channels {", ".join(info.stream.channels)}; '
            f'contact by {p["contact"]}, decision above {p["threshold"]}')

    def _declare_parameters(self) -> dict:
        """Declare every parameter (mirrored in config/classify.yaml); return the values."""
        def declare(name, default, description, *, read_only=True, low=None, high=None):
            descriptor = ParameterDescriptor(description=description, read_only=read_only)
            if isinstance(default, float) and low is not None:
                descriptor.floating_point_range = [FloatingPointRange(from_value=low,
                                                                      to_value=high)]
            elif isinstance(default, int) and low is not None:
                descriptor.integer_range = [IntegerRange(from_value=low, to_value=high,
                                                         step=1)]
            return self.declare_parameter(name, default, descriptor).value

        return {
            'checkpoint': declare('checkpoint', '', 'checkpoint folder (RUN/model/ of tactex '
                                  'train)'),
            'runtime': declare('runtime', 'native', f'inference runtime: {", ".join(RUNTIMES)} '
                               '(onnxruntime needs `tactex export CHECKPOINT --onnx`)'),
            'threads': declare('threads', 1, 'inference threads', low=1, high=64),
            'threshold': declare('threshold', 0.99, 'decide when the largest posterior '
                                 'probability exceeds this (1: never)', read_only=False,
                                 low=0.0, high=1.0),
            'min_windows': declare('min_windows', 1, 'windows needed before a decision',
                                   low=1, high=10_000),
            'change_nats': declare('change_nats', 5.0, 'CUSUM threshold of a texture change '
                                   '(nats)', low=0.1, high=1000.0),
            'hop': declare('hop', 0, "samples between windows (0: the checkpoint's)", low=0,
                           high=100_000),
            'contact': declare('contact', 'auto', 'what keeps samples: '
                               f'{", ".join(CONTACT_SOURCES)}'),
            'contact_pa': declare('contact_pa', 40.0, 'pressure rise meaning contact (Pa)',
                                  low=0.1, high=1e6),
            'reorder_s': declare('reorder_s', 0.0, 'wait for late samples this long (s)',
                                 low=0.0, high=10.0),
            'max_lag_s': declare('max_lag_s', 0.25, 'stop waiting for a silent topic after '
                                 'this much IMU signal (s)', low=0.01, high=10.0),
            'rate_hz': declare('rate_hz', 0.0, "the stream's rate, checked against the "
                               "checkpoint's at start (0: measured only)", low=0.0, high=1e5),
            'rate_tolerance': declare('rate_tolerance', 0.05, 'relative rate difference '
                                      'accepted', low=0.0, high=1.0),
            'window': declare('window', 0, "the stream's window, checked at start (0: the "
                              "checkpoint's)", low=0, high=1_000_000),
            'channels': declare('channels', [''], "the stream's channels, checked at start "
                                "(['']: the checkpoint's)"),
            'frame_id': declare('frame_id', 'sensor_edge', 'frame of the estimates'),
            'diagnostics_period_s': declare('diagnostics_period_s', 1.0, 'diagnostics period '
                                            '(s)', low=0.01, high=3600.0),
            'wait_warn_period_s': declare('wait_warn_period_s', 5.0, 'warn this often while a '
                                          'topic is silent (s)', low=0.1, high=3600.0),
        }

    def _refuse(self, message: str):
        self.get_logger().fatal(message)
        raise StartError(message)

    def _callback(self, role: str):
        queue, wake = self._queue, self._wake

        def on_sample(message) -> None:
            queue.append((role, stamp_ns(message.header.stamp), _values(role, message),
                          time.monotonic_ns()))
            wake.set()
        return on_sample

    def _on_active(self, message: Bool) -> None:
        self._queue.append(('active', self.get_clock().now().nanoseconds, message.data, 0))
        self._wake.set()

    def _on_metadata(self, message: String) -> None:
        try:
            rate = json.loads(message.data).get('sensor_rate_hz')
        except (ValueError, AttributeError):
            return
        if isinstance(rate, (int, float)) and math.isfinite(rate):
            self._check_rate(float(rate), 'recording/metadata')

    def _check_rate(self, rate_hz: float, source: str) -> None:
        lines = self._info.stream.mismatches(sampling_rate_hz=rate_hz,
                                             rate_tolerance=self._rate_tolerance)
        if lines and not self._refusal:
            self._refusal = f'not classifying: {lines[0]} ({source})'
            self.get_logger().error(f'{self._info.model_id}: {self._refusal}')

    def _on_set_parameters(self, parameters) -> SetParametersResult:
        for parameter in parameters:
            if parameter.name == 'threshold':
                evidence = self._classifier.evidence
                evidence.settings = EvidenceSettings(float(parameter.value),
                                                     evidence.settings.min_windows,
                                                     evidence.settings.change_nats)
        return SetParametersResult(successful=True)

    def _work(self) -> None:
        """Drain the queue, classify, publish; never inside a subscription callback."""
        windows = self._classifier.windows
        while self._running:
            self._wake.wait(0.1)
            self._wake.clear()
            while self._queue:
                role, stamp, values, arrival = self._queue.popleft()
                if self._refusal:
                    continue
                if role == 'active':
                    windows.set_active(values, stamp)
                else:
                    windows.add(role, stamp, values, arrival)
                    self._arrivals[role] += 1
            if self._refusal:
                continue
            for result in self._classifier.step():
                self._publish(result)
                with self._lock:
                    self._latencies.append((time.monotonic_ns() - result.window.completed_ns)
                                           * 1e-6)
                    self._classified += 1
                    self._last_estimate = result.estimate

    def _publish(self, result) -> None:
        estimate, info = result.estimate, self._info
        message = TextureEstimate()
        message.header.stamp = _time(estimate.stamp_ns)
        message.header.frame_id = self._frame_id
        message.class_id = estimate.class_id
        message.label = info.classes[estimate.class_id]
        message.confidence = float(estimate.probabilities[estimate.class_id])
        message.class_names = list(info.classes)
        message.probabilities = [float(v) for v in estimate.probabilities]
        message.decided = estimate.decided
        message.contact_seconds = estimate.contact_seconds
        message.windows_used = len(estimate.spans_ns)
        message.window_starts = [_time(start) for start, _ in estimate.spans_ns]
        message.window_ends = [_time(end) for _, end in estimate.spans_ns]
        message.model_id = info.model_id
        self._estimate_pub.publish(message)
        marker = Marker(ns='texture', id=0, type=Marker.TEXT_VIEW_FACING, action=Marker.ADD)
        marker.header = message.header
        marker.pose.position.z = 0.03
        marker.pose.orientation.w = 1.0
        marker.scale.z = 0.012
        marker.color.a = 1.0
        marker.color.g = 1.0
        marker.color.r = 0.0 if estimate.decided else 1.0
        marker.text = (f'{message.label} {100 * message.confidence:.0f} %'
                       f'{" (decided)" if estimate.decided else ""}, '
                       f'{estimate.contact_seconds:.1f} s')
        self._marker_pub.publish(MarkerArray(markers=[marker]))

    def _silent_roles(self) -> list[str]:
        return [role for role, count in self._arrivals.items() if not count]

    def _warn_while_waiting(self) -> None:
        silent = self._silent_roles()
        if silent:
            waited = time.monotonic() - self._started
            needs = ', '.join(f'{ROLE_TOPICS[r][1]} ({", ".join(ROLE_CHANNELS[r])})'
                              for r in silent)
            self.get_logger().warn(f'no samples for {waited:.0f} s on {needs}: is the sensor '
                                   'node (or the simulator) running? Waiting.')

    def _publish_diagnostics(self) -> None:
        now = time.monotonic()
        counts = self._classifier.windows.counts
        samples = counts['samples']
        period, before = now - self._last_diagnostics[0], self._last_diagnostics[1]
        self._last_diagnostics = (now, samples)
        rate = (samples - before) / period if period > 0 else 0.0
        with self._lock:
            latencies = np.array(self._latencies)
            estimate, classified = self._last_estimate, self._classified
        p50, p99 = (np.percentile(latencies, [50, 99]) if latencies.size
                    else (math.nan, math.nan))
        stream_rate = self._classifier.windows.stream_rate_hz()
        if stream_rate is not None:
            self._check_rate(stream_rate, 'median step of the header stamps')
        silent = self._silent_roles()
        evidence = self._classifier.evidence
        if estimate is None or not evidence.windows:
            state = 'waiting for contact'
        else:
            label = self._info.classes[estimate.class_id]
            state = (f'{"decided" if estimate.decided else "leading"} {label} '
                     f'{100 * estimate.probabilities[estimate.class_id]:.1f} % after '
                     f'{estimate.contact_seconds:.2f} s ({evidence.windows} windows)')
        if self._refusal:
            level, summary = DiagnosticStatus.ERROR, self._refusal
        elif silent:
            level, summary = DiagnosticStatus.WARN, 'no samples on ' + ', '.join(
                ROLE_TOPICS[r][1] for r in silent)
        else:
            level, summary = DiagnosticStatus.OK, state
        values = {'model': self._info.model_id, 'runtime': self._predictor.runtime,
                  'input_rate_hz': f'{rate:.1f}', 'latency_p50_ms': f'{p50:.3f}',
                  'latency_p99_ms': f'{p99:.3f}', 'windows_cut': str(counts['windows']),
                  'windows_classified': str(classified),
                  'windows_dropped': str(self._classifier.skipped),
                  'samples_late': str(counts['late']),
                  'samples_dropped': str(counts['dropped']),
                  'samples_overflow': str(counts['overflow']), 'evidence': state,
                  'resets': json.dumps(self._classifier.resets, sort_keys=True),
                  'queued': str(len(self._queue))}
        status = DiagnosticStatus(level=level, name=f'tactex_classify: {self.get_name()}',
                                  message=summary, hardware_id=self._info.model_id,
                                  values=[KeyValue(key=k, value=v) for k, v in values.items()])
        array = DiagnosticArray(status=[status])
        array.header.stamp = self.get_clock().now().to_msg()
        self._diagnostics_pub.publish(array)

    def destroy_node(self) -> None:
        """Stop the worker."""
        self._running = False
        worker = getattr(self, '_worker', None)
        if worker is not None:
            self._wake.set()
            worker.join(timeout=2.0)
        super().destroy_node()


def main(args: list[str] | None = None) -> None:
    """Run the node until shutdown; a refused start exits with code 1."""
    try:
        spin(ClassifierNode, args)
    except StartError:
        sys.exit(1)
