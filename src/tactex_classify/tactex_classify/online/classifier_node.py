# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""ROS 2 node classifying the texture under the sensor live, from a `tactex train` checkpoint.

Subscription callbacks only queue samples; a worker thread aligns them, cuts windows,
runs the model and publishes, so a slow model never delays the sensor callbacks: when
windows queue up, only the newest is classified and the others are counted as dropped.

Nothing stops it quietly. The queue is bounded (overflow counted); the worker survives
any exception (counted, its samples skipped), is restarted if its thread ends, and is
reported stalled when it stops draining the queue. Stream faults (live.py,
stream_health.py) are counted; diagnostics are WARN while any count grew in the last
`degraded_s`, ERROR while the stream's rate is off the model's or the worker is stalled.
"""

from __future__ import annotations

from collections import deque
import json
import math
import sys
import threading
import time

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
import numpy as np
from rcl_interfaces.msg import (
    FloatingPointRange,
    IntegerRange,
    ParameterDescriptor,
    SetParametersResult,
)
from std_msgs.msg import Bool, String
from visualization_msgs.msg import Marker, MarkerArray

from tactex_classify.data.bags import ROLE_CHANNELS, sample_values
from tactex_classify.errors import ClassifyError
from tactex_classify.online.evidence import EvidenceSettings
from tactex_classify.online.live import CONTACT_SOURCES, LiveSettings, OnlineClassifier
from tactex_classify.online.runtime import load_predictor, RUNTIMES
from tactex_classify.online.stream_health import stated_metadata
from tactex_classify.online.tactile_topics import ROLE_TOPICS, SENSOR_QUEUE
from tactex_common import frames, topics
from tactex_common.ros import COMMAND, spin, TactexNode, time_message
from tactex_common.stamps import stamp_ns
from tactex_msgs.msg import TextureEstimate

LATENCIES_KEPT = 2000  # the p50/p99 of diagnostics are over the newest this many windows
QUEUE_LIMIT = 32_768  # samples queued for the worker (30 s of three 350 Hz topics)
# What counts as a fault in diagnostics (each a count of its own): the worker's, the
# stream's (LiveWindows.counts) and the windows' (OnlineClassifier.faults).
NODE_FAULTS = ('queue_overflow', 'worker_errors', 'worker_restarts', 'metadata_invalid')
STREAM_FAULTS = ('invalid', 'off_timeline', 'resyncs', 'overflow')
# The worker and the executor share the GIL: a woken worker would wait up to Python's
# default 5 ms switch interval while callbacks run; 0.5 ms bounds that wait.
GIL_SWITCH_INTERVAL_S = 0.0005


class StartError(Exception):
    """The node cannot start: a refused checkpoint or a stream it does not fit."""


class ClassifierNode(TactexNode):
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
                                reorder_s=p['reorder_s'], max_lag_s=p['max_lag_s'],
                                jump_s=p['jump_s'])
            self._classifier = OnlineClassifier(
                self._predictor.predict_proba, info.stream, len(info.classes), live=live,
                evidence=EvidenceSettings(p['threshold'], p['min_windows'], p['change_nats']),
                rate_tolerance=p['rate_tolerance'])
        except ValueError as err:
            self._refuse(f'{info.model_id}: {err}')
        self._frame_id = p['frame_id']
        self._stall_s, self._degraded_s = p['stall_s'], p['degraded_s']
        # (role, stamp_ns, values, arrival_ns) from callbacks; full: the oldest are dropped.
        self._queue: deque = deque(maxlen=QUEUE_LIMIT)
        self._wake = threading.Event()
        self._latencies: deque[float] = deque(maxlen=LATENCIES_KEPT)
        self._lock = threading.Lock()  # guards what diagnostics read from the worker
        self._arrivals: dict[str, int] = dict.fromkeys(self._classifier.windows.needed_roles, 0)
        self._started = time.monotonic()
        self._last_diagnostics = (time.monotonic(), 0)
        self._node_faults = dict.fromkeys(NODE_FAULTS, 0)
        self._fault_history: deque[tuple[float, dict[str, int]]] = deque()
        self._last_error = ''
        self._beat = time.monotonic()  # the worker's last pass
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
        self._start_worker()
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
            'jump_s': declare('jump_s', 0.5, "a stamp further than this from the stream's "
                              'newest is off its timeline; three in a row restart it (s)',
                              low=0.05, high=3600.0),
            'stall_s': declare('stall_s', 5.0, 'the worker is stalled when it leaves queued '
                               'samples this long (s)', low=0.5, high=3600.0),
            'degraded_s': declare('degraded_s', 5.0, 'diagnostics stay WARN this long after a '
                                  'fault (s)', low=0.1, high=3600.0),
            'rate_hz': declare('rate_hz', 0.0, "the stream's rate, checked against the "
                               "checkpoint's at start (0: measured only)", low=0.0, high=1e5),
            'rate_tolerance': declare('rate_tolerance', 0.05, 'relative rate difference '
                                      'accepted', low=0.0, high=1.0),
            'window': declare('window', 0, "the stream's window, checked at start (0: the "
                              "checkpoint's)", low=0, high=1_000_000),
            'channels': declare('channels', [''], "the stream's channels, checked at start "
                                "(['']: the checkpoint's)"),
            'frame_id': declare('frame_id', frames.EDGE, 'frame of the estimates'),
            'diagnostics_period_s': declare('diagnostics_period_s', 1.0, 'diagnostics period '
                                            '(s)', low=0.01, high=3600.0),
            'wait_warn_period_s': declare('wait_warn_period_s', 5.0, 'warn this often while a '
                                          'topic is silent (s)', low=0.1, high=3600.0),
        }

    def _refuse(self, message: str):
        self.get_logger().fatal(message)
        raise StartError(message)

    def _enqueue(self, item: tuple) -> None:
        """Queue an item for the worker (a full queue drops its oldest, counted)."""
        if len(self._queue) == QUEUE_LIMIT:
            self._node_faults['queue_overflow'] += 1
        self._queue.append(item)
        self._wake.set()

    def _callback(self, role: str):
        def on_sample(message) -> None:
            self._enqueue((role, stamp_ns(message.header.stamp), sample_values(role, message),
                           time.monotonic_ns()))
        return on_sample

    def _on_active(self, message: Bool) -> None:
        self._enqueue(('active', self.get_clock().now().nanoseconds, message.data, 0))

    def _on_metadata(self, message: String) -> None:
        stated = stated_metadata(message.data)
        if 'sensor_rate_hz' not in stated:
            return
        self._enqueue(('rate', 0, stated['sensor_rate_hz'], 0))

    def _on_set_parameters(self, parameters) -> SetParametersResult:
        for parameter in parameters:
            if parameter.name == 'threshold':
                evidence = self._classifier.evidence
                evidence.settings = EvidenceSettings(float(parameter.value),
                                                     evidence.settings.min_windows,
                                                     evidence.settings.change_nats)
        return SetParametersResult(successful=True)

    def _start_worker(self) -> None:
        self._worker = threading.Thread(target=self._work, name='classifier', daemon=True)
        self._worker.start()

    def _work(self) -> None:
        """Drain the queue, classify, publish; never inside a subscription callback."""
        while self._running:
            self._beat = time.monotonic()
            self._wake.wait(0.1)
            self._wake.clear()
            try:
                self._drain()
            except Exception as err:  # noqa: BLE001 - the worker outlives any one failure
                self._node_faults['worker_errors'] += 1
                self._last_error = f'{type(err).__name__}: {err}'
                self.get_logger().error(f'skipped a pass of the classifier: {self._last_error}',
                                        throttle_duration_sec=5.0)

    def _drain(self) -> None:
        """One pass: the queued samples into the live core, its windows classified."""
        windows = self._classifier.windows
        while self._queue:
            self._beat = time.monotonic()
            role, stamp, values, arrival = self._queue.popleft()
            if role == 'active':
                windows.set_active(values, stamp)
            elif role == 'rate':
                error = self._classifier.rate.stated(values)
                if error:
                    self._node_faults['metadata_invalid'] += 1
                    self.get_logger().error(f'recording/metadata: {error}')
            else:
                windows.add(role, stamp, values, arrival)
                self._arrivals[role] += 1
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
        message.header.stamp = time_message(estimate.stamp_ns)
        message.header.frame_id = self._frame_id
        message.class_id = estimate.class_id
        message.label = info.classes[estimate.class_id]
        message.confidence = float(estimate.probabilities[estimate.class_id])
        message.class_names = list(info.classes)
        message.probabilities = [float(v) for v in estimate.probabilities]
        message.decided = estimate.decided
        message.contact_seconds = estimate.contact_seconds
        message.windows_used = len(estimate.spans_ns)
        message.window_starts = [time_message(start) for start, _ in estimate.spans_ns]
        message.window_ends = [time_message(end) for _, end in estimate.spans_ns]
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
            self.get_logger().warning(f'no samples for {waited:.0f} s on {needs}: is the sensor '
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
        faults = self._fault_totals()
        grown = self._grown_faults(now, faults)
        stalled = self._stalled(now)
        silent = self._silent_roles()
        evidence = self._classifier.evidence
        if estimate is None or not evidence.windows:
            state = 'waiting for contact'
        else:
            label = self._info.classes[estimate.class_id]
            state = (f'{"decided" if estimate.decided else "leading"} {label} '
                     f'{100 * estimate.probabilities[estimate.class_id]:.1f} % after '
                     f'{estimate.contact_seconds:.2f} s ({evidence.windows} windows)')
        refusal = self._classifier.rate.refusal
        if stalled or refusal:
            level, summary = DiagnosticStatus.ERROR, stalled or f'not classifying: {refusal}'
        elif silent:
            level, summary = DiagnosticStatus.WARN, 'no samples on ' + ', '.join(
                ROLE_TOPICS[r][1] for r in silent)
        elif grown:
            last = self._classifier.last_fault or self._last_error
            level, summary = DiagnosticStatus.WARN, (
                f'degraded in the last {self._degraded_s:g} s: '
                + ', '.join(f'{count} {name}' for name, count in grown.items())
                + (f' ({last})' if last else ''))
        else:
            level, summary = DiagnosticStatus.OK, state
        values = {'model': self._info.model_id, 'runtime': self._predictor.runtime,
                  'input_rate_hz': f'{rate:.1f}', 'latency_p50_ms': f'{p50:.3f}',
                  'latency_p99_ms': f'{p99:.3f}', 'windows_cut': str(counts['windows']),
                  'windows_classified': str(classified),
                  'windows_dropped': str(self._classifier.skipped),
                  'samples_late': str(counts['late']),
                  'samples_dropped': str(counts['dropped']),
                  'evidence': state,
                  'resets': json.dumps(self._classifier.resets, sort_keys=True),
                  'queued': str(len(self._queue)),
                  **{f'faults_{name}': str(count) for name, count in faults.items()}}
        self.publish_diagnostics(self._diagnostics_pub, level,
                                 'classifier', summary, values,
                                 hardware_id=self._info.model_id)

    def _fault_totals(self) -> dict[str, int]:
        """Every fault count: the worker's, the stream's and the windows'."""
        counts = self._classifier.windows.counts
        return {**self._node_faults, **{name: counts[name] for name in STREAM_FAULTS},
                **self._classifier.faults}

    def _grown_faults(self, now: float, totals: dict[str, int]) -> dict[str, int]:
        """The faults counted in the last `degraded_s`, by name (empty: none)."""
        history = self._fault_history
        history.append((now, totals))
        while len(history) > 1 and history[1][0] <= now - self._degraded_s:
            history.popleft()
        before = history[0][1]
        return {name: count - before[name] for name, count in totals.items()
                if count > before[name]}

    def _stalled(self, now: float) -> str:
        """Why the worker is not working ('' when it is); a thread that ended is restarted."""
        if not self._worker.is_alive() and self._running:
            self._node_faults['worker_restarts'] += 1
            self.get_logger().error('the classifier worker ended; restarted it')
            self._start_worker()
        waited = now - self._beat
        if self._queue and waited > self._stall_s:
            return (f'the classifier worker is stalled: {len(self._queue)} samples queued, '
                    f'no progress for {waited:.1f} s')
        return ''

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
