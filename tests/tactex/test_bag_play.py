# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex bag play`: recordings published at their recorded timing, like `ros2 bag play`.

What is published (topics chosen, renamed, namespaced; offset, duration, rate factor;
ROS 1 messages as their ROS 2 types) is checked without ROS; the played recording into a
launched classifier_node decides what `tactex predict` decides on it, when it does.
"""

from pathlib import Path
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
from support.bagfactory import TS, write_bag
from support.foreign_bags import converted
from support.livestream import PERIOD_NS, RATE_HZ, start_node, stop, write_checkpoints

from tactex.bag_playback import Lateness, messages, parse_remap, PlayOptions, topics_of
from tactex.bag_player import NoSubscriberError, wait_for_subscribers
from tactex_classify.errors import BagError
from tactex_classify.online.live import LiveSettings
from tactex_classify.online.replay import replay_recording
from tactex_classify.online.runtime import load_predictor
from tactex_common import topics

TACTEX = Path(sys.executable).parent / 'tactex'
# What classifier_node subscribes to and the test recording holds.
NODE_READS = (topics.IMU_RAW, topics.MAG, topics.PRESSURE, topics.SWEEP_ACTIVE,
              topics.RECORDING_METADATA)


def texture_values(count: int, ridged: bool, seed: int = 0) -> np.ndarray:
    """What livestream's checkpoints learnt: a 20 Hz vibration on ax when ridged."""
    rng = np.random.default_rng(seed)
    values = rng.normal(0, 0.05, (count, 10))
    values[:, 0] += np.sin(2 * np.pi * 20 * np.arange(count) / RATE_HZ) * ridged
    values[:, 2] += 9.8
    values[:, 9] += 101_000
    return values


@pytest.fixture(scope='module')
def recording(tmp_path_factory):
    """Eight seconds of the ridged texture at 120 Hz, sliding from 1 s to 7 s."""
    stamps = 10**12 + np.arange(960, dtype=np.int64) * PERIOD_NS
    return write_bag(tmp_path_factory.mktemp('play') / 'ridged', stamps,
                     texture_values(960, True), metadata={'label': 'ridged', 'trial': 1},
                     active=[(stamps[120], stamps[840])], live_order=True)


def test_messages_come_in_logged_order_with_their_instants(recording):
    played = list(messages(recording, PlayOptions()))
    assert len(played) == 3 * 960 + 2 + 1  # three streams, two segment messages, metadata
    due = [m.due_s for m in played]
    assert due == sorted(due) and due[0] == 0.0
    assert due[-1] == pytest.approx(959 / RATE_HZ)


def test_offset_duration_and_rate_factor_shape_the_timeline(recording):
    played = list(messages(recording, PlayOptions(rate_factor=2.0, start_offset_s=1.0,
                                                  duration_s=2.0)))
    logged = [m.log_ns for m in played]
    assert min(logged) >= 10**12 + 10**9 and max(logged) <= 10**12 + 3 * 10**9
    assert max(m.due_s for m in played) == pytest.approx(1.0, abs=0.01)  # 2 s at twice speed


def test_topics_are_chosen_renamed_and_namespaced(recording):
    options = PlayOptions(topics=('tactile/imu/data_raw', '/sweep/active'),
                          remaps=(parse_remap('/tactile/imu/data_raw:=/imu/data'),),
                          namespace='left_arm')
    assert {m.topic for m in messages(recording, options)} == {'/left_arm/imu/data',
                                                                '/left_arm/sweep/active'}
    with pytest.raises(ValueError, match='is not OLD:=NEW'):
        parse_remap('/imu/data')


def test_a_topic_that_would_carry_two_types_is_refused_before_anything_plays(recording):
    options = PlayOptions(remaps=(parse_remap('/sweep/active:=/tactile/pressure'),))
    with pytest.raises(BagError, match='/tactile/pressure would carry two types, '
                                       '.*leave one out with --topics, or give it another '
                                       'name with --remap'):
        topics_of([recording], options)


def test_ros1_messages_play_as_their_ros2_types_header_seq_dropped(recording, tmp_path):
    old = converted(recording, tmp_path / 'ridged.bag')
    ros2 = sorted((m.log_ns, m.topic, m.msgtype, m.data)
                  for m in messages(recording, PlayOptions()))
    ros1 = sorted((m.log_ns, m.topic, m.msgtype, m.data) for m in messages(old, PlayOptions()))
    assert [r[:3] for r in ros1] == [r[:3] for r in ros2]  # (equal log times in any order)
    ros1, ros2 = ([r[1:] for r in rows] for rows in (ros1, ros2))
    assert ros1 == ros2  # the same CDR bytes as the ROS 2 recording's
    imu = next(r for r in ros1 if r[1] == 'sensor_msgs/msg/Imu')
    assert not hasattr(TS.deserialize_cdr(imu[2], imu[1]).header, 'seq')


def test_lateness_is_summarised_with_what_was_late():
    lateness = Lateness()
    for seconds in (0.0001, 0.0002, -0.001, 0.02):
        lateness.add(seconds)
    summary = lateness.summary()
    assert summary['published'] == 4 and summary['late'] == 1
    assert summary['max_ms'] == pytest.approx(20.0)


def test_lateness_percentiles_hold_to_a_hundredth_of_a_millisecond_in_bounded_memory():
    lateness = Lateness()
    for index in range(1, 1001):
        lateness.add(index * 1e-5)  # 0.01 ms .. 10 ms
    lateness.add(3600.0)  # an hour late: counted in the last bin, its size exact
    summary = lateness.summary()
    assert summary['p50_ms'] == pytest.approx(5.0, abs=0.025)  # bins of 0.01 ms
    assert summary['p99_ms'] == pytest.approx(9.9, abs=0.025)
    assert summary['max_ms'] == 3.6e6 and len(lateness.counts) == 100_001


@pytest.mark.slow
@pytest.mark.ros
def test_played_into_classifier_node_it_decides_what_predict_decides_when(
        recording, tmp_path, ros_context):
    import rclpy

    from tactex_msgs.msg import TextureEstimate
    checkpoint = write_checkpoints(tmp_path) / 'minirocket'
    expected = replay_recording(load_predictor(checkpoint), recording,
                                live=LiveSettings(contact='auto'))
    assert expected.decision == 'ridged'
    node = rclpy.create_node('play_test', context=ros_context)
    estimates = []
    node.create_subscription(TextureEstimate, 'texture/estimate', estimates.append, 100)
    executor = rclpy.executors.SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    classifier = start_node(checkpoint, 'contact:=auto', 'use_sim_time:=true')
    try:
        deadline = time.monotonic() + 60
        while node.count_publishers('texture/estimate') == 0 and time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.1)
        # The node must hear the contact's start, or it has nothing to decide on: a fixed
        # --delay of 2 s once was not enough on two busy cores; --wait-for waits for it.
        player = subprocess.run([str(TACTEX), 'bag', 'play', str(recording), '--clock',
                                 '--wait-for', *NODE_READS, '/clock'],
                                capture_output=True, text=True, timeout=90)
        assert player.returncode == 0, player.stderr
        assert 'published 2,883 messages' in player.stdout
        end = time.monotonic() + 5
        while time.monotonic() < end:
            executor.spin_once(timeout_sec=0.1)
    finally:
        output = stop(classifier)
    decided = [e for e in estimates if e.decided]
    assert decided, f'{len(estimates)} estimates, none decided; the node said: {output}'
    first = decided[0]
    stamp_ns = first.header.stamp.sec * 10**9 + first.header.stamp.nanosec
    hop_ns = 16 * PERIOD_NS  # the checkpoint's hop
    assert first.label == expected.decision
    assert abs(stamp_ns - expected.decisions[0][0]) <= hop_ns


@pytest.mark.slow
@pytest.mark.ros
def test_ctrl_c_stops_playback_cleanly_and_reports_what_was_played(recording):
    player = subprocess.Popen([str(TACTEX), 'bag', 'play', str(recording), '--delay', '0.2'],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    time.sleep(4)
    player.send_signal(signal.SIGINT)
    out, err = player.communicate(timeout=30)
    assert player.returncode == 0, err
    assert 'stopped by SIGINT' in err and 'Traceback' not in err
    published = int(out.split('published ')[1].split(' ')[0].replace(',', ''))
    assert 0 < published < 2883


@pytest.mark.ros
def test_a_play_that_publishes_nothing_fails_naming_the_options_that_emptied_it(recording):
    played = subprocess.run([str(TACTEX), 'bag', 'play', str(recording), '--delay', '0',
                             '--topics', '/nonexistent', '--start-offset', '100'],
                            capture_output=True, text=True, timeout=120)
    assert played.returncode == 1 and 'Traceback' not in played.stderr
    assert ('error: published nothing: --topics /nonexistent names no recorded topic or '
            '--start-offset 100 s is past the end') in played.stderr


class CountingPublisher:
    """A publisher whose subscription count turns 1 once asked `after` times."""

    def __init__(self, after: int | None) -> None:
        self.after, self.asked = after, 0

    def get_subscription_count(self) -> int:
        self.asked += 1
        return int(self.after is not None and self.asked > self.after)


def test_the_wait_ends_when_every_named_topic_has_a_subscriber():
    publishers = {'/left/tactile/imu': CountingPublisher(after=2),
                  '/sweep/active': CountingPublisher(after=5)}
    wait_for_subscribers(publishers, ['left/tactile/imu', '/sweep/active/'], timeout_s=5.0)
    assert publishers['/sweep/active'].asked == 6  # asked again until it matched


def test_the_wait_names_only_the_topics_left_without_a_subscriber():
    publishers = {'/a': CountingPublisher(after=0), '/b': CountingPublisher(after=None)}
    with pytest.raises(NoSubscriberError, match=r'^no subscriber to /b within 0.2 s; start the '
                                                r'node that reads it first'):
        wait_for_subscribers(publishers, ['a', 'b'], timeout_s=0.2)


def test_a_name_that_is_not_played_is_refused_before_any_wait():
    publishers = {'/a': CountingPublisher(after=None)}
    with pytest.raises(NoSubscriberError, match='^/c not played; the played topics are /a$'):
        wait_for_subscribers(publishers, ['/a', 'c'], timeout_s=60.0)
    assert publishers['/a'].asked == 0
    with pytest.raises(NoSubscriberError, match='the played topics are none$'):
        wait_for_subscribers({}, ['c'], timeout_s=60.0)


@pytest.mark.ros
def test_waiting_for_a_topic_that_is_not_played_names_the_played_ones(recording):
    played = subprocess.run([str(TACTEX), 'bag', 'play', str(recording), '--delay', '0',
                             '--wait-for', 'tactile/nothing'],
                            capture_output=True, text=True, timeout=120)
    assert played.returncode == 1 and 'Traceback' not in played.stderr
    error = played.stderr.strip().splitlines()[-1]
    assert error.startswith('error: --wait-for: /tactile/nothing not played; the played '
                            'topics are ')
    assert f'/{topics.IMU_RAW}' in error


@pytest.mark.ros
def test_a_topic_nobody_subscribes_to_ends_the_wait_with_the_way_out(recording):
    played = subprocess.run([str(TACTEX), 'bag', 'play', str(recording), '--delay', '0',
                             '--wait-for', topics.PRESSURE, '--wait-timeout', '0.5'],
                            capture_output=True, text=True, timeout=120)
    assert played.returncode == 1 and 'Traceback' not in played.stderr
    assert played.stderr.strip().splitlines()[-1] == (
        f'error: --wait-for: no subscriber to /{topics.PRESSURE} within 0.5 s; start the '
        'node that reads it first, or give a longer --wait-timeout')
    assert 'published' not in played.stdout  # nothing was played
