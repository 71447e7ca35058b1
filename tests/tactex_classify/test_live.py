# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The live core cuts the converter's windows from a recorded bag, and meets bad streams."""

import numpy as np
import pytest
from rosbags.highlevel import AnyReader
from support.bagfactory import write_bag

from tactex_classify.data.bags import TOPIC_ROLES
from tactex_classify.data.dataset import convert
from tactex_classify.models.checkpoint import StreamSpec
from tactex_classify.online.evidence import EvidenceSettings
from tactex_classify.online.live import (
    ContactLost,
    LiveSettings,
    LiveWindows,
    OnlineClassifier,
    Window,
)
from tactex_common.channels import CHANNELS
from tactex_common.interfaces import typestore

PERIOD_NS = 8_333_333  # 120 Hz
START_NS = 10**12
DELAY_NS = {'imu': 1_000_000, 'mag': 3_000_000, 'pressure': 2_000_000}  # transport


def irregular_recording(count=900, seed=0):
    """IMU stamps with jitter, a gap, a NaN sample, a repeated stamp; mag at half rate."""
    rng = np.random.default_rng(seed)
    stamps = START_NS + np.arange(count, dtype=np.int64) * PERIOD_NS \
        + rng.integers(-400_000, 400_000, count)
    stamps[500:] += 40 * PERIOD_NS  # a gap of 40 periods
    stamps[300] = stamps[299]  # a repeated stamp: the converter keeps the first
    values = rng.normal(size=(count, 10))
    values[:, 9] += 101_000.0
    values[420, 4] = np.nan  # a NaN sample, dropped
    mag_stamps = stamps[::2] + 2_000_000
    active = [(int(stamps[40]), int(stamps[610])), (int(stamps[700]), int(stamps[880]))]
    return stamps, values, mag_stamps, active


def bag_feed(path):
    """(arrival_ns, role, stamp_ns, values) of a bag's messages, as they would arrive live.

    Sensor messages arrive a transport delay after their header stamp; sweep/active at the
    time it was logged (the recorder's receive time).
    """
    feed = []
    roles = {f'/{topic}': role for role, (topic, _) in TOPIC_ROLES.items()}
    with AnyReader([path], default_typestore=typestore()) as reader:
        for connection, log_ns, raw in reader.messages():
            role = roles.get(connection.topic)
            message = reader.deserialize(raw, connection.msgtype)
            if role == 'active':
                feed.append((log_ns, role, log_ns, message.data))
                continue
            if role not in DELAY_NS:
                continue
            stamp = message.header.stamp.sec * 10**9 + message.header.stamp.nanosec
            if role == 'imu':
                a, w = message.linear_acceleration, message.angular_velocity
                values = (a.x, a.y, a.z, w.x, w.y, w.z)
            elif role == 'mag':
                m = message.magnetic_field
                values = (m.x, m.y, m.z)
            else:
                values = (message.fluid_pressure,)
            feed.append((stamp + DELAY_NS[role], role, stamp, values))
    return sorted(feed, key=lambda item: item[0])


def run_live(feed, stream, settings):
    """Feed every message, polling after each, as the node's worker does."""
    core = LiveWindows(stream, settings)
    events = []
    for arrival, role, stamp, values in feed:
        if role == 'active':
            core.set_active(values, stamp)
        else:
            core.add(role, stamp, values, arrival)
        events += core.poll()
    return core, events


@pytest.fixture(scope='module')
def recorded(tmp_path_factory):
    stamps, values, mag_stamps, active = irregular_recording()
    path = tmp_path_factory.mktemp('live') / 'wood_0000'
    write_bag(path, stamps, values, mag_stamps_ns=mag_stamps, active=active,
              metadata={'label': 'wood', 'trial': 0})
    return path


@pytest.mark.parametrize('window, hop', [(32, 16), (64, 64), (50, 7)])
def test_live_windows_equal_the_converters_window_by_window(recorded, window, hop):
    data = convert([recorded], window=window, hop=hop, progress=lambda line: None)
    stream = StreamSpec(tuple(data.channels), window, hop, 120.0)
    core, events = run_live(bag_feed(recorded), stream, LiveSettings(contact='sweep_active'))
    windows = [e for e in events if isinstance(e, Window)]
    assert len(windows) == len(data.X) > 4
    np.testing.assert_array_equal(np.array([w.values for w in windows], np.float32), data.X)
    np.testing.assert_array_equal(np.array([w.start_ns for w in windows]) * 1e-9, data.t0)
    # Each of the two segments ends in a contact loss.
    assert [e.reason for e in events if isinstance(e, ContactLost)] == ['sweep/active fell'] * 2
    assert core.counts['late'] == 0 and core.counts['overflow'] == 0
    assert core.counts['invalid'] == 1  # the NaN sample
    assert core.counts['dropped'] >= 1  # the repeated stamp


def test_samples_arriving_out_of_order_are_waited_for_or_counted_late(recorded):
    data = convert([recorded], window=32, hop=16, progress=lambda line: None)
    stream = StreamSpec(tuple(data.channels), 32, 16, 120.0)
    feed = bag_feed(recorded)
    imu = [i for i, item in enumerate(feed) if item[1] == 'imu']
    late = imu[200]
    feed.insert(imu[203], feed.pop(late))  # arrives after three newer IMU samples
    _, events = run_live(feed, stream, LiveSettings(contact='sweep_active', reorder_s=0.05))
    windows = [e for e in events if isinstance(e, Window)]
    np.testing.assert_array_equal(np.array([w.values for w in windows], np.float32), data.X)
    core, _ = run_live(feed, stream, LiveSettings(contact='sweep_active'))
    assert core.counts['late'] == 1


def test_a_burst_after_a_stall_gives_every_window_without_waiting_for_more(recorded):
    data = convert([recorded], window=32, hop=16, progress=lambda line: None)
    stream = StreamSpec(tuple(data.channels), 32, 16, 120.0)
    feed = bag_feed(recorded)
    core = LiveWindows(stream, LiveSettings(contact='sweep_active'))
    events = []
    for i, (arrival, role, stamp, values) in enumerate(feed):  # polled once per 400 messages
        if role == 'active':
            core.set_active(values, stamp)
        else:
            core.add(role, stamp, values, arrival)
        if i % 400 == 399 or i == len(feed) - 1:
            events += core.poll()
    windows = [e for e in events if isinstance(e, Window)]
    np.testing.assert_array_equal(np.array([w.values for w in windows], np.float32), data.X)


def chip_noise(i):
    """A gyro reading that changes every sample, as a live chip's does (never frozen)."""
    return 1e-3 * ((i * 7) % 5 - 2)


def stream_of(kind_of_sample, count, *, start=START_NS):
    """(role, stamp, values) of a synthetic 10-channel stream; ax carries the texture."""
    for i in range(count):
        stamp = start + i * PERIOD_NS
        ax = kind_of_sample(i)
        yield 'imu', stamp, (ax, 0.0, 9.8, chip_noise(i), 0.0, 0.0)
        yield 'mag', stamp, (1e-5, 0.0, 0.0)
        yield 'pressure', stamp, (103_000.0,)


def test_a_window_is_cut_as_its_last_frame_arrives_with_stamps_since_the_epoch():
    # Stamps since 1970 (~1.8e18 ns) are not exact as floats; the newest sample must still
    # be final at once, not wait for the next frame (it did: one frame of latency).
    core = LiveWindows(SPEC, LiveSettings(contact='always'))
    cut_at = []
    for frame in range(80):
        stamp = 1_795_360_000_123_456_789 + frame * 8_334_667
        for role, values in (('imu', (0.1, 0.0, 9.8, 0.0, 0.0, 0.0)), ('mag', (1e-5, 0.0, 0.0)),
                             ('pressure', (103_000.0,))):
            core.add(role, stamp, values, frame)
        cut_at += [(frame, event.end_ns == stamp) for event in core.poll()
                   if isinstance(event, Window)]
    assert cut_at and all(at_once for _, at_once in cut_at)
    assert [frame for frame, _ in cut_at][:2] == [SPEC.window - 1, SPEC.window - 1 + SPEC.hop]


def texture_model(windows):
    """A stand-in model: class 1 when ax averages above 0.5, confidently."""
    high = windows[:, :, 0].mean(axis=1) > 0.5
    proba = np.full((len(windows), 2), 0.005)
    proba[np.arange(len(windows)), high.astype(int)] = 0.995
    return proba


SPEC = StreamSpec(tuple(CHANNELS), 32, 16, 120.0)


def online(newest_only=False, **evidence):
    return OnlineClassifier(texture_model, SPEC, 2, live=LiveSettings(contact='always'),
                            evidence=EvidenceSettings(**evidence), newest_only=newest_only)


def test_a_texture_change_mid_stream_resets_the_evidence_within_one_window():
    change = 400
    classifier = online(threshold=0.999)
    results = []
    for role, stamp, values in stream_of(lambda i: float(i >= change), 800):
        classifier.windows.add(role, stamp, values, stamp)
        results += classifier.step()
    assert results[0].estimate.class_id == 0 and any(r.estimate.decided for r in results)
    restarts = [r for r in results if r.estimate.restarted == 'texture change']
    assert len(restarts) == 1
    change_ns = START_NS + change * PERIOD_NS
    # The first window lying wholly on the new texture restarts the evidence.
    first_new = next(r for r in results if r.window.start_ns >= change_ns)
    assert restarts[0].window.end_ns <= first_new.window.end_ns
    after = results[results.index(restarts[0]):]
    assert all(r.estimate.class_id == 1 for r in after)
    assert after[-1].estimate.decided


def test_evidence_is_reset_when_contact_is_lost_and_sums_while_in_contact():
    classifier = OnlineClassifier(texture_model, SPEC, 2,
                                  live=LiveSettings(contact='pressure'),
                                  evidence=EvidenceSettings(threshold=1.0), newest_only=False)
    results = []

    def pressure(i):  # in contact (2 kPa above the resting baseline) from 100 to 500
        return 101_000.0 + (2000.0 if 100 <= i < 500 else 0.0)

    for i in range(700):
        stamp = START_NS + i * PERIOD_NS
        for role, values in (('imu', (0.0, 0, 9.8, chip_noise(i), 0, 0)), ('mag', (0.0, 0, 0)),
                             ('pressure', (pressure(i),))):
            classifier.windows.add(role, stamp, values, stamp)
        results += classifier.step()
    used = [r.estimate.spans_ns for r in results]
    assert all(len(b) == len(a) + 1 for a, b in zip(used, used[1:], strict=False))
    assert classifier.resets == {'contact lost': 1}
    contact_s = results[-1].estimate.contact_seconds
    assert contact_s == pytest.approx((len(results) - 1) * 16 / 120 + 32 / 120, abs=1e-6)
    assert all(START_NS + 100 * PERIOD_NS <= r.window.start_ns for r in results)
    assert all(r.window.end_ns < START_NS + 500 * PERIOD_NS for r in results)


def test_nan_samples_and_a_missing_channel_topic_drop_samples_never_raise():
    core = LiveWindows(SPEC, LiveSettings(contact='always', max_lag_s=0.1))
    events = []
    for role, stamp, values in stream_of(lambda i: np.nan if i % 50 == 7 else 0.3, 300):
        if role != 'mag':  # the magnetometer topic never publishes
            core.add(role, stamp, values, stamp)
        events += core.poll()
    assert not events  # nothing aligns without the magnetometer the model needs
    assert core.counts['dropped'] > 250
    without_mag = StreamSpec(tuple(c for c in CHANNELS if c[0] != 'm'), 32, 16, 120.0)
    core = LiveWindows(without_mag, LiveSettings(contact='always'))
    for role, stamp, values in stream_of(lambda i: np.nan if i % 50 == 7 else 0.3, 300):
        core.add(role, stamp, values, stamp)
        events += core.poll()
    windows = [e for e in events if isinstance(e, Window)]
    assert windows and all(np.all(np.isfinite(w.values)) for w in windows)
    assert all(w.values.shape == (32, 7) for w in windows)
    assert core.counts['invalid'] == 6 and core.counts['dropped'] == 0  # the NaN samples


def test_duplicated_messages_and_a_stall_then_burst_are_harmless():
    core = LiveWindows(SPEC, LiveSettings(contact='always'))
    events = []
    for role, stamp, values in stream_of(lambda i: 0.3, 200):
        core.add(role, stamp, values, stamp)
        core.add(role, stamp, values, stamp)  # every message twice
    events += core.poll()  # one poll after a burst of 200 samples
    windows = [e for e in events if isinstance(e, Window)]
    assert len(windows) == (200 - 32) // 16 + 1
    assert core.counts['overflow'] == 0 and core.counts['dropped'] == 0


def test_when_windows_queue_up_only_the_newest_is_classified_and_the_rest_counted():
    classifier = online(newest_only=True, threshold=1.0)
    for role, stamp, values in stream_of(lambda i: 0.0, 200):
        classifier.windows.add(role, stamp, values, stamp)
    results = classifier.step()
    assert len(results) == 1 and classifier.skipped == (200 - 32) // 16
    assert results[0].window.end_ns == START_NS + 199 * PERIOD_NS - (199 - 31) % 16 * PERIOD_NS


def test_a_model_on_channels_the_topics_do_not_carry_is_refused():
    with pytest.raises(ValueError, match='trained on channels fx, fy.*fx, fy missing'):
        LiveWindows(StreamSpec(('fx', 'fy', 'ax'), 32, 16, 100.0))
