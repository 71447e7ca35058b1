# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""sweep_node against the simulator: a labelled sweep in contact, a cancel that lifts off."""

import json
import threading
import time

import numpy as np
import pytest

from tactex_classify.data.bags import read_recording
from tactex_sim.scene import load_scene, resolve_scene
from tactex_trajectory.simulated_sweeps import probe_like_pathway

pytestmark = [pytest.mark.integration, pytest.mark.ros, pytest.mark.slow]
pytest.importorskip('tactex_msgs', reason='the interface package tactex_msgs is not built')
SCENE = load_scene(resolve_scene('uneven_texture'))


def pathway_message(start_x, end_x, seed=0):
    from geometry_msgs.msg import Point, Vector3

    from tactex_msgs.msg import Contact, Pathway
    points, normals = probe_like_pathway(SCENE.surface, start_x, end_x, 0.01,
                                         np.random.default_rng(seed))
    message = Pathway()
    message.header.frame_id = 'base_link'
    for point, normal in zip(points, normals, strict=True):
        contact = Contact(position=Point(x=point[0], y=point[1], z=point[2]),
                          normal=Vector3(x=normal[0], y=normal[1], z=normal[2]),
                          force_proxy=0.5, confidence=0.9, status=Contact.STATUS_OK)
        contact.header.frame_id = 'base_link'
        message.contacts.append(contact)
    return message


class Harness:
    """Bridge, sweep node and a client node spun by one executor in a thread."""

    def __init__(self, context, tmp_path, scene='uneven_texture'):
        from geometry_msgs.msg import PoseStamped
        import rclpy
        from rclpy.action import ActionClient
        from rclpy.executors import SingleThreadedExecutor
        from rclpy.parameter import Parameter
        from std_msgs.msg import Bool, String

        from tactex_msgs.action import Sweep
        from tactex_sim.mujoco_bridge_node import MujocoBridgeNode
        from tactex_trajectory.sweep_node import SweepNode

        self.bridge = MujocoBridgeNode(context=context, parameter_overrides=[
            Parameter('scene', value=scene), Parameter('rate_factor', value=4.0)])
        self.sweeper = SweepNode(context=context, parameter_overrides=[
            Parameter('use_sim_time', value=True), Parameter('approach_height', value=0.01),
            Parameter('recording_root', value=str(tmp_path))])
        self.client = rclpy.create_node('sweep_client', context=context)
        self.poses, self.contacts, self.active, self.metadata = [], [], [], []
        lock = threading.Lock()
        self.lock = lock

        def keep(store):
            def callback(msg):
                with lock:
                    store.append((time.monotonic(), msg))
            return callback

        self.client.create_subscription(PoseStamped, 'sim/ground_truth/sensor_pose',
                                        keep(self.poses), 10)
        self.client.create_subscription(PoseStamped, 'sim/ground_truth/contact',
                                        keep(self.contacts), 10)
        self.client.create_subscription(Bool, 'sweep/active', keep(self.active), 10)
        from tactex_common.ros import LATCHED
        self.client.create_subscription(String, 'recording/metadata', keep(self.metadata),
                                        LATCHED)
        self.action = ActionClient(self.client, Sweep, 'sweep')
        self.Sweep = Sweep
        # The bridge spins alone, as in its own process: its busy timer must not hold up
        # the others.
        self.executors = [SingleThreadedExecutor(context=context),
                          SingleThreadedExecutor(context=context)]
        self.executors[0].add_node(self.bridge)
        for node in (self.sweeper, self.client):
            self.executors[1].add_node(node)
        self.threads = [threading.Thread(target=executor.spin, daemon=True)
                        for executor in self.executors]
        for thread in self.threads:
            thread.start()

    def send(self, **fields):
        assert self.action.wait_for_server(timeout_sec=20)
        deadline = time.monotonic() + 20
        while not self.poses and time.monotonic() < deadline:
            time.sleep(0.05)
        future = self.action.send_goal_async(self.Sweep.Goal(**fields))
        return wait(future, 20)

    def sim_time(self):
        """Simulated time of the newest ground truth received (s)."""
        with self.lock:
            return stamp(self.poses[-1][1])

    def close(self):
        for executor, thread in zip(self.executors, self.threads, strict=True):
            executor.shutdown(timeout_sec=5)
            thread.join(timeout=5)
        for node in (self.bridge, self.sweeper, self.client):
            node.destroy_node()


def wait(future, timeout_s):
    deadline = time.monotonic() + timeout_s
    while not future.done() and time.monotonic() < deadline:
        time.sleep(0.02)
    assert future.done(), 'timed out'
    return future.result()


@pytest.fixture
def harness(ros_context, tmp_path):
    harness = Harness(ros_context, tmp_path)
    yield harness
    harness.close()


def test_sweep_slides_in_contact_and_records_one_labelled_bag(harness):
    from action_msgs.msg import GoalStatus
    handle = harness.send(pathway=pathway_message(0.10, 0.17), sliding_speed=0.015,
                          edge_offset_angle=0.5, press_depth=0.0015, label='wood', trial=7,
                          record=True, movement='default')
    assert handle.accepted
    outcome = wait(handle.get_result_async(), 240)
    result = outcome.result
    assert outcome.status == GoalStatus.STATUS_SUCCEEDED, result.message
    assert result.contact_fraction >= 0.95
    assert abs(result.speed_mean / 0.015 - 1.0) < 0.1
    assert result.press_depth_error < 0.0015
    assert len(result.contact_starts) == len(result.contact_ends) >= 1
    with harness.lock:
        active = [msg.data for _, msg in harness.active]
        metadata = json.loads(harness.metadata[-1][1].data)
    assert True in active and active[-1] is False
    assert metadata['label'] == 'wood' and metadata['trial'] == 7
    assert metadata['sweep']['sliding_speed_m_s'] == 0.015
    recording = read_recording(result.recording_path)
    assert recording.metadata['label'] == 'wood' and recording.metadata['trial'] == 7
    assert recording.metadata['movement'] == 'default'  # identification trains on it
    assert len(recording.stamps_ns) > 100


def test_a_goal_that_cannot_be_executed_is_aborted_with_the_reason(harness):
    from action_msgs.msg import GoalStatus
    handle = harness.send(pathway=pathway_message(0.10, 0.11), sliding_speed=0.015,
                          edge_offset_angle=0.35, press_depth=0.0015, label='wood', trial=1)
    assert handle.accepted
    outcome = wait(handle.get_result_async(), 30)
    assert outcome.status == GoalStatus.STATUS_ABORTED
    assert outcome.result.message.startswith('not planned: the path is')
    assert 'probe a longer pathway or slide slower' in outcome.result.message
    assert not harness.metadata, 'a refused goal must not start a recording'


def test_cancel_mid_sweep_lifts_the_edge_off_before_stopping(harness):
    from action_msgs.msg import GoalStatus
    handle = harness.send(pathway=pathway_message(0.10, 0.20), sliding_speed=0.015,
                          edge_offset_angle=0.5, press_depth=0.0015, label='wood', trial=1)
    assert handle.accepted
    deadline = time.monotonic() + 240
    while time.monotonic() < deadline:
        with harness.lock:
            sliding = any(msg.data for _, msg in harness.active)
        if sliding:
            break
        time.sleep(0.05)
    assert sliding
    time.sleep(0.5)
    cancelled_at = harness.sim_time()
    wait(handle.cancel_goal_async(), 20)
    outcome = wait(handle.get_result_async(), 120)
    finished_at = harness.sim_time()
    assert outcome.status == GoalStatus.STATUS_CANCELED
    assert 'lifted' in outcome.result.message
    with harness.lock:
        touching = [stamp(msg) for _, msg in harness.contacts]
        final = harness.poses[-1][1].pose.position
    # In contact when cancelled, out of contact before the result, and lifted clear (the
    # lift leaves the surface in its first 2 mm; the result comes at 80 % of its 20 mm).
    assert any(t > cancelled_at - 0.2 for t in touching)
    assert max(touching) < finished_at - 0.1
    assert final.z - SCENE.surface.height(final.x) > 0.008


def stamp(msg):
    return msg.header.stamp.sec + 1e-9 * msg.header.stamp.nanosec


def test_a_sweep_without_pressure_is_aborted_and_lifted(ros_context, tmp_path):
    from action_msgs.msg import GoalStatus
    # The probe scene without its barometer: pressure is NaN.
    probe = resolve_scene('probe').read_text(encoding='utf-8')
    no_barometer = tmp_path / 'no_barometer.toml'
    head = probe.split('[effect.barometer]')[0]
    no_barometer.write_text(head.replace('"barometer", ', '').replace(', "barometer"]', ']'),
                            encoding='utf-8')
    assert 'barometer' not in load_scene(no_barometer).effects
    harness = Harness(ros_context, tmp_path, scene=str(no_barometer))
    try:
        handle = harness.send(pathway=pathway_message(0.10, 0.17), sliding_speed=0.015,
                              edge_offset_angle=0.5, press_depth=0.0015)
        outcome = wait(handle.get_result_async(), 240)
    finally:
        harness.close()
    assert outcome.status == GoalStatus.STATUS_ABORTED
    assert outcome.result.message.startswith('aborted: no finite tactile/pressure')
    assert outcome.result.message.endswith('the edge was lifted off')


@pytest.mark.parametrize('seconds, stamp', [(5.9999999996, (6, 0)), (1.25, (1, 250_000_000)),
                                            (0.0, (0, 0)), (2.0000000004, (2, 0))])
def test_a_contact_time_becomes_the_stamp_nearest_it(seconds, stamp):
    from tactex_trajectory.sweep_node import _time
    time_msg = _time(seconds)
    assert (time_msg.sec, time_msg.nanosec) == stamp  # 5.9999999996 s was 5 s flat
