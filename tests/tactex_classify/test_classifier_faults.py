# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""classifier_node through a schedule of faults: it counts each, says so, and keeps deciding.

The real node (its own process) is fed a stream with every fault a live stream shows:
a value beyond float32, a future-stamped sample, a restarted clock, a burst of packed
stamps, stamp jitter, a frozen and a saturated IMU. Afterwards a known texture is decided
correctly and diagnostics are OK again. The worker's own faults (an exception, a stall, a
thread that ended) are driven in this process, with a model that fails on purpose.
"""

import pytest
from support.livestream import (
    PERIOD_NS,
    SensorStandIn,
    start_node,
    stop,
    write_checkpoints,
)

from tactex_common import chips

pytestmark = [pytest.mark.integration, pytest.mark.ros, pytest.mark.slow]
BURST = 200  # samples stamped 0.1 ms apart: more than half of the rate judge's span
GYRO_RAIL = chips.gyro_range(245).rails_si[1]


@pytest.fixture(scope='module')
def checkpoints(tmp_path_factory):
    return write_checkpoints(tmp_path_factory.mktemp('checkpoints'))


def levels(sensor):
    return [status.level for status in sensor.diagnostics]


def test_the_node_counts_every_stream_fault_recovers_and_decides_a_known_texture(
        checkpoints, ros_context):
    from diagnostic_msgs.msg import DiagnosticStatus
    process = start_node(checkpoints / 'minirocket', 'degraded_s:=1.0')
    try:
        sensor = SensorStandIn(ros_context)
        assert sensor.spin_until(lambda: sensor.diagnostics, 60.0), 'the node never came up'
        sensor.publish(2.0, ridged=1.0)
        sensor.publish_one(sensor.stamp_ns(), 1.0, ax=1e300)  # float32 overflow
        sensor.publish(1.0, ridged=1.0)
        sensor.publish_one(sensor.stamp_ns() + 3600 * 10**9, 1.0)  # an hour ahead
        sensor.publish(1.0, ridged=1.0)
        offset = -30 * 10**9  # the clock restarts 30 s back, and stays there
        sensor.publish(1.5, ridged=1.0, offset_ns=offset)
        start = sensor.stamp_ns() + offset
        for k in range(BURST):  # a buffered burst, stamped as it arrived
            sensor.publish_one(start + k * 100_000, 1.0)
        sensor.publish(2.5, ridged=1.0, offset_ns=offset)
        sensor.publish(1.5, ridged=1.0, offset_ns=offset, jitter_ns=10_000_000)
        frozen_from = sensor.stamp_ns() + offset
        sensor.publish(1.5, ridged=0.0, offset_ns=offset, gyro=(0.0, 0.0, 0.0), ax=0.5)
        frozen_to = sensor.stamp_ns() + offset
        sensor.publish(1.5, ridged=1.0, offset_ns=offset, gyro=(0.0, GYRO_RAIL, 0.0))
        sensor.publish(4.0, ridged=0.0, offset_ns=offset)  # a known texture after the faults
        sensor.spin_for(2.0)
        values = sensor.values()
    finally:
        output = stop(process)
    assert 'Traceback' not in output, output
    for fault in ('invalid', 'off_timeline', 'resyncs', 'refused', 'frozen', 'saturated'):
        assert int(values[f'faults_{fault}']) >= 1, (fault, values)
    assert int(values['faults_worker_errors']) == 0
    assert DiagnosticStatus.WARN in levels(sensor) and DiagnosticStatus.ERROR in levels(sensor)
    assert sensor.diagnostics[-1].level == DiagnosticStatus.OK, sensor.diagnostics[-1]
    last = sensor.estimates[-1]
    assert last.label == 'smooth' and last.decided
    stamps = [e.header.stamp.sec * 10**9 + e.header.stamp.nanosec for e in sensor.estimates]
    assert not [s for s in stamps if frozen_from + 32 * PERIOD_NS <= s <= frozen_to]
    assert sum(1 for s in stamps if s > frozen_to) >= 3


class FailingModel:
    """Wraps a predictor: raises on call `raise_at`, blocks on call `block_at` until freed."""

    def __init__(self, predictor, *, raise_at=None, block_at=None):
        import threading
        self.predictor, self.raise_at, self.block_at = predictor, raise_at, block_at
        self.calls, self.free = 0, threading.Event()
        self.inner = predictor.predict_proba
        predictor.predict_proba = self

    def __call__(self, X):
        self.calls += 1
        if self.calls == self.raise_at:
            raise MemoryError('out of memory in the model')
        if self.calls == self.block_at:
            self.free.wait(30.0)
        return self.inner(X)


def node_in_process(monkeypatch, checkpoint, context, **failures):
    """classifier_node in this process, its model wrapped in a FailingModel."""
    from rclpy.parameter import Parameter

    from tactex_classify.online import classifier_node
    wrapped = {}
    load = classifier_node.load_predictor

    def load_failing(*args, **kwargs):
        predictor = load(*args, **kwargs)
        wrapped['model'] = FailingModel(predictor, **failures)
        return predictor
    monkeypatch.setattr(classifier_node, 'load_predictor', load_failing)
    parameters = [Parameter('checkpoint', value=str(checkpoint)),
                  Parameter('contact', value='always'),
                  Parameter('diagnostics_period_s', value=0.2),
                  Parameter('stall_s', value=0.5), Parameter('degraded_s', value=1.0)]
    node = classifier_node.ClassifierNode(context=context, parameter_overrides=parameters)
    return node, wrapped['model']


def stream_ridged(node, context):
    """Three seconds of the ridged texture through `node`, in this process; the stand-in."""
    try:
        sensor = SensorStandIn(context, node)
        sensor.publish(3.0, ridged=1.0)
        sensor.spin_for(1.0)
    finally:
        node.destroy_node()
    return sensor


def test_a_window_whose_model_raises_is_counted_and_the_next_is_classified(
        checkpoints, ros_context, monkeypatch):
    node, model = node_in_process(monkeypatch, checkpoints / 'minirocket', ros_context,
                                  raise_at=2)
    sensor = stream_ridged(node, ros_context)
    values = sensor.values()
    assert values['faults_model_errors'] == '1'
    assert model.calls >= 4 and sensor.estimates[-1].label == 'ridged'


def test_a_stalled_worker_is_an_error_until_it_moves_again(checkpoints, ros_context,
                                                           monkeypatch):
    from diagnostic_msgs.msg import DiagnosticStatus
    node, model = node_in_process(monkeypatch, checkpoints / 'minirocket', ros_context,
                                  block_at=2)
    try:
        sensor = SensorStandIn(ros_context, node)
        sensor.publish(2.5, ridged=1.0)
        assert sensor.spin_until(lambda: sensor.diagnostics[-1].level == DiagnosticStatus.ERROR,
                                 5.0)
        assert 'stalled' in sensor.diagnostics[-1].message
        classified = len(sensor.estimates)
        model.free.set()
        sensor.publish(2.5, ridged=1.0)
        sensor.spin_for(1.5)
    finally:
        node.destroy_node()
    assert len(sensor.estimates) > classified
    assert sensor.diagnostics[-1].level != DiagnosticStatus.ERROR


@pytest.mark.filterwarnings('ignore::pytest.PytestUnhandledThreadExceptionWarning')
def test_a_worker_thread_that_ends_is_restarted_and_counted(checkpoints, ros_context,
                                                            monkeypatch):
    node, _ = node_in_process(monkeypatch, checkpoints / 'minirocket', ros_context)
    drain = node._drain
    calls = []

    def drain_then_die():
        calls.append(1)
        if len(calls) == 5:
            raise SystemExit  # not an Exception: ends the thread as a crash in C would
        drain()
    monkeypatch.setattr(node, '_drain', drain_then_die)
    sensor = stream_ridged(node, ros_context)
    assert sensor.values()['faults_worker_restarts'] == '1'
    assert sensor.estimates and sensor.estimates[-1].label == 'ridged'
