# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""A recording decoded in a second process replays as decoded in one, and fails the same.

`replay_recording` reads a long recording through a spawned decoder: the windows,
probabilities, decisions and faults are those of decoding it in the caller's process; an
unreadable message is the same UnreadablePart; a decoder that dies is a BagError naming
the recording, never a hang; stopping early (an exception, Ctrl-C) leaves no process.
"""

import multiprocessing
import os
import re
import signal

import numpy as np
import pytest
from support.bagfactory import write_bag

from tactex_classify.data import decoder_process
from tactex_classify.data.bags import sample_values
from tactex_classify.data.sources import decoded_messages, UnreadablePart
from tactex_classify.errors import BagError
from tactex_classify.models.baselines import MiniRocketRidge
from tactex_classify.online.live import LiveSettings
from tactex_classify.online.replay import replay_recording
from tactex_classify.online.runtime import load_predictor
from tactex_common.stamps import stamp_ns

RATE_HZ = 120.0
PERIOD_NS = int(1e9 / RATE_HZ)
COUNT = 3000  # samples a stream: 9,000 messages, several batches
TOPICS = {'/tactile/imu/data_raw': 'imu', '/tactile/imu/mag': 'mag',
          '/tactile/pressure': 'pressure', '/sweep/active': 'active',
          '/recording/metadata': 'metadata'}


def signal_values(count, seed):
    """Ten channels: a 9 Hz ripple in the first half, a 31 Hz one after; 101 kPa."""
    rng = np.random.default_rng(seed)
    t = np.arange(count) / RATE_HZ
    ripple = np.where(t < t[-1] / 2, np.sin(2 * np.pi * 9 * t), np.sin(2 * np.pi * 31 * t))
    values = 0.2 * rng.normal(size=(count, 10)) + ripple[:, None]
    values[:, 9] += 101_325.0
    return values


@pytest.fixture(scope='module')
def lab(tmp_path_factory):
    """A long live-order recording (sweeps, metadata) and a MiniRocket for its ripples."""
    root = tmp_path_factory.mktemp('decoder')
    stamps = 10**12 + np.arange(COUNT, dtype=np.int64) * PERIOD_NS
    values = signal_values(COUNT, 0)
    values[700, 2] = np.nan  # an invalid sample, counted
    write_bag(root / 'long', stamps, values, live_order=True,
              metadata={'label': 'ridged', 'sensor_rate_hz': RATE_HZ},
              active=[(stamps[20], stamps[1400]), (stamps[1500], stamps[-20])])
    training = signal_values(COUNT, 1)
    starts = [s for s in range(0, COUNT - 64, 32) if not s < COUNT // 2 < s + 64]
    X = np.stack([training[s:s + 64] for s in starts]).astype(np.float32)
    y = np.array([int(s >= COUNT // 2) for s in starts])
    MiniRocketRidge(dilations=3).fit(X, y, ['ridged', 'fine']).save(
        root / 'model', hop=16, sampling_rate_hz=RATE_HZ)
    return root


@pytest.fixture
def spawned(monkeypatch):
    """Every recording decoded in a second process, however short."""
    monkeypatch.setattr(decoder_process, 'SPAWN_FROM', 0)


def replayed(lab, **kwargs):
    result = replay_recording(load_predictor(lab / 'model'), lab / 'long',
                              live=LiveSettings(contact='auto'), **kwargs)
    return (result.label, result.start_ns, result.decisions, result.final.tolist(),
            result.faults, [(start, end, proba.tolist()) for start, end, proba in result.windows])


def test_a_spawned_decoder_replays_what_decoding_in_process_does(lab, monkeypatch):
    monkeypatch.setattr(decoder_process, 'SPAWN_FROM', 10**9)
    in_process = replayed(lab)
    monkeypatch.setattr(decoder_process, 'SPAWN_FROM', 0)
    assert replayed(lab) == in_process
    label, _, decisions, _, faults, windows = in_process
    assert label == 'ridged' and [d[1] for d in decisions] == ['ridged', 'fine']
    assert len(windows) > 100
    assert faults['invalid'] == 1 and faults['resets']


@pytest.mark.parametrize('spawn_from', [0, 10**9])
def test_the_samples_are_the_messages_in_logged_order(lab, monkeypatch, spawn_from):
    monkeypatch.setattr(decoder_process, 'SPAWN_FROM', spawn_from)
    (part,) = [lab / 'long']
    expected = []
    for topic, log_ns, message in decoded_messages(part, TOPICS):
        role = TOPICS[topic]
        if role in ('active', 'metadata'):
            expected.append((role, log_ns, log_ns, message.data))
        else:
            expected.append((role, stamp_ns(message.header.stamp), log_ns,
                             sample_values(role, message)))
    with decoder_process.decoded_samples(part, [part], TOPICS, 3 * COUNT) as samples:
        got = list(samples)
    assert len(got) == 3 * COUNT + 5
    assert [repr(item) for item in got] == [repr(item) for item in expected]  # NaN == NaN


@pytest.mark.parametrize('good', [0, 2500])
def test_an_unreadable_message_is_the_same_unreadable_part_either_way(lab, tmp_path,
                                                                     monkeypatch, good):
    stamps = 10**12 + np.arange(good + 10, dtype=np.int64) * PERIOD_NS
    path = write_bag(tmp_path / 'broken', stamps, signal_values(good + 10, 2), live_order=True,
                     unreadable_imu_from=good)
    with pytest.raises(UnreadablePart) as direct:
        for _ in decoded_messages(path, TOPICS):
            pass
    assert str(direct.value).startswith(f'{path}: cannot read: ')
    for spawn_from in (10**9, 0):
        monkeypatch.setattr(decoder_process, 'SPAWN_FROM', spawn_from)
        with pytest.raises(UnreadablePart) as raised:
            replay_recording(load_predictor(lab / 'model'), path,
                             live=LiveSettings(contact='always'))
        assert str(raised.value) == str(direct.value)
        assert raised.value.reason == direct.value.reason


def test_a_failure_of_another_kind_in_the_decoder_is_a_bag_error_naming_it(lab, spawned):
    part = lab / 'long'
    wrong = {'/tactile/imu/mag': 'imu'}  # a MagneticField read as an Imu
    with pytest.raises(BagError, match=re.escape(f'{part}: decoding failed: AttributeError')):
        with decoder_process.decoded_samples(part, [part], wrong, COUNT) as samples:
            list(samples)
    assert not multiprocessing.active_children()


def test_a_decoder_that_dies_is_a_bag_error_naming_the_recording(lab, spawned):
    part = lab / 'long'
    with decoder_process.decoded_samples(part, [part], TOPICS, 3 * COUNT) as samples:
        next(samples)  # the rest cannot all wait in the pipe: the decoder is still there
        (child,) = multiprocessing.active_children()
        os.kill(child.pid, signal.SIGKILL)
        with pytest.raises(BagError, match=re.escape(f'{part}: the process decoding it '
                                                     'stopped (exit code -9)')):
            for _ in samples:
                pass
    assert not multiprocessing.active_children()


@pytest.mark.parametrize('error', [KeyboardInterrupt, RuntimeError])
def test_stopping_early_leaves_no_decoder_behind(lab, spawned, error):
    seen = []

    def progress(samples):
        seen.extend(multiprocessing.active_children())
        raise error('stopped by the caller')
    with pytest.raises(error, match='stopped by the caller'):
        replayed(lab, progress=progress)
    assert [child.name for child in seen] == ['tactex decoder']
    assert not seen[0].is_alive() and seen[0].exitcode is not None
    assert not multiprocessing.active_children()
