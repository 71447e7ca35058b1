# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""tactex_msgs through rclpy: each message published and received, each action served."""

import threading
import time

import pytest

pytestmark = [pytest.mark.integration, pytest.mark.ros]
TIMEOUT_S = 15.0


def stamp(ns):
    from builtin_interfaces.msg import Time
    sec, nanosec = divmod(int(ns), 10**9)
    return Time(sec=sec, nanosec=nanosec)


def contact(i=0, status=None):
    from geometry_msgs.msg import Point, Vector3
    from std_msgs.msg import Header

    from tactex_msgs.msg import Contact
    ok = status in (None, Contact.STATUS_OK)
    return Contact(header=Header(stamp=stamp(10**9 + i * 10**8), frame_id='base_link'),
                   position=Point(x=0.2 + 0.01 * i, y=0.0, z=0.03),
                   normal=Vector3(x=0.0, y=0.6, z=0.8) if ok else Vector3(),
                   force_proxy=0.8 if ok else 0.0, confidence=0.875 if ok else 0.0,
                   status=Contact.STATUS_OK if ok else status)


def pathway(count=3):
    from geometry_msgs.msg import Point, Vector3
    from std_msgs.msg import Header

    from tactex_msgs.msg import Pathway
    return Pathway(header=Header(stamp=stamp(2 * 10**9), frame_id='base_link'),
                   contacts=[contact(i) for i in range(count)],
                   start=Point(x=0.2, y=0.0, z=0.03), direction=Vector3(x=1.0, y=0.0, z=0.0),
                   span=0.01 * (count - 1), step=0.01, approach_height=0.02,
                   descent_speed=0.005, max_descent_depth=0.015, force_limit=2.0)


def texture_estimate():
    from std_msgs.msg import Header

    from tactex_msgs.msg import TextureEstimate
    return TextureEstimate(
        header=Header(stamp=stamp(5 * 10**9), frame_id='sensor_edge'), label='wood',
        class_id=1, confidence=0.75, class_names=['cork', 'wood', 'felt'],
        probabilities=[0.2, 0.75, 0.05], decided=True, contact_seconds=2.1, windows_used=2,
        window_starts=[stamp(3 * 10**9 - 10**8), stamp(4 * 10**9 - 10**8)],
        window_ends=[stamp(4 * 10**9), stamp(5 * 10**9)], model_id='cnn_3@test')


def wait_until(condition, what):
    deadline = time.monotonic() + TIMEOUT_S
    while not condition():
        assert time.monotonic() < deadline, f'timed out waiting for {what}'
        time.sleep(0.01)


def result_of(future, what):
    wait_until(future.done, what)
    return future.result()


@pytest.mark.parametrize('make', [contact, pathway, texture_estimate],
                         ids=['Contact', 'Pathway', 'TextureEstimate'])
def test_message_is_published_and_received_unchanged(ros_context, make):
    import rclpy
    from rclpy.qos import QoSDurabilityPolicy, QoSProfile

    sent = make()
    node = rclpy.create_node('interfaces_pubsub', context=ros_context)
    # Transient local, as probe/pathway: a late subscriber still gets the message.
    qos = QoSProfile(depth=1, durability=QoSDurabilityPolicy.TRANSIENT_LOCAL)
    publisher = node.create_publisher(type(sent), 'interfaces/test', qos)
    received = []
    node.create_subscription(type(sent), 'interfaces/test', received.append, qos)
    executor = rclpy.executors.SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    publisher.publish(sent)
    deadline = time.monotonic() + TIMEOUT_S
    while not received and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.05)
    executor.shutdown()
    node.destroy_node()
    assert received and received[0] == sent
    assert type(received[0]).__module__.startswith('tactex_msgs.msg')
    # Through Fast DDS: its typesupport library of tactex_msgs was found and loaded.
    assert rclpy.utilities.get_rmw_implementation_identifier() == 'rmw_fastrtps_cpp'


class TinyServers:
    """A Probe and a Sweep action server that pretend to move, one step per 20 ms."""

    def __init__(self, context):
        import rclpy
        from rclpy.action import ActionServer, CancelResponse, GoalResponse
        from rclpy.callback_groups import ReentrantCallbackGroup

        from tactex_msgs.action import Probe, Sweep
        self.node = rclpy.create_node('tiny_action_servers', context=context)
        group = ReentrantCallbackGroup()
        self.servers = [
            ActionServer(self.node, action, name, execute, callback_group=group,
                         goal_callback=lambda goal: GoalResponse.ACCEPT,
                         cancel_callback=lambda handle: CancelResponse.ACCEPT)
            for action, name, execute in ((Probe, 'probe', self.probe),
                                          (Sweep, 'sweep', self.sweep))]

    def probe(self, handle):
        from tactex_msgs.action import Probe
        from tactex_msgs.msg import Contact
        goal, started = handle.request, time.monotonic()
        result = Probe.Result()
        result.pathway = pathway(0)
        result.pathway.start, result.pathway.direction = goal.start, goal.direction
        for name in ('span', 'step', 'approach_height', 'descent_speed', 'max_descent_depth',
                     'force_limit'):
            setattr(result.pathway, name, getattr(goal, name))
        count = int(goal.span / goal.step + 1e-9) + 1
        for i in range(count):
            if handle.is_cancel_requested:
                handle.canceled()
                result.message = 'canceled'
                return result
            found = contact(i, None if i % 3 else Contact.STATUS_NO_CONTACT)
            result.outcomes.append(found.status)
            if found.status == Contact.STATUS_OK:
                result.pathway.contacts.append(found)
            for phase in (Probe.Feedback.PHASE_MOVING, Probe.Feedback.PHASE_DESCENDING):
                handle.publish_feedback(Probe.Feedback(
                    phase=phase, probe_index=i, probe_count=count,
                    contacts_found=len(result.pathway.contacts), last_contact=found))
                time.sleep(0.01)
        result.elapsed.sec, result.elapsed.nanosec = divmod(
            int((time.monotonic() - started) * 1e9), 10**9)
        handle.succeed()
        return result

    def sweep(self, handle):
        from tactex_msgs.action import Sweep
        goal, steps = handle.request, 10 * len(handle.request.pathway.contacts)
        result = Sweep.Result()
        for i in range(steps):
            if handle.is_cancel_requested:
                handle.canceled()
                result.message = 'canceled'
                return result
            handle.publish_feedback(Sweep.Feedback(
                progress=(i + 1) / steps, in_contact=0 < i < steps - 1, tracking_error=0.0004,
                sliding_speed=goal.sliding_speed))
            time.sleep(0.02)
        result.contact_fraction = (steps - 2) / steps
        result.speed_mean, result.speed_std = goal.sliding_speed, 0.001
        result.press_depth_error = 0.0002
        result.contact_starts, result.contact_ends = [stamp(10**9)], [stamp(3 * 10**9)]
        result.recording_path = f'/tmp/{goal.label}_{goal.trial}' if goal.record else ''
        handle.succeed()
        return result

    def destroy(self):
        for server in self.servers:
            server.destroy()
        self.node.destroy_node()


@pytest.fixture
def actions(ros_context):
    """(client node, tiny servers) spun by a multi-threaded executor in the background."""
    import rclpy
    from rclpy.executors import MultiThreadedExecutor

    servers = TinyServers(ros_context)
    client = rclpy.create_node('action_client', context=ros_context)
    executor = MultiThreadedExecutor(num_threads=4, context=ros_context)
    executor.add_node(servers.node)
    executor.add_node(client)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    yield client
    executor.shutdown()
    spinner.join(timeout=5)
    client.destroy_node()
    servers.destroy()


def send(client_node, action, name, goal):
    """Send `goal`; return (goal handle, list that feedback messages land in)."""
    from rclpy.action import ActionClient
    client = ActionClient(client_node, action, name)
    assert client.wait_for_server(timeout_sec=TIMEOUT_S)
    feedback = []
    handle = result_of(client.send_goal_async(goal, feedback_callback=feedback.append),
                       f'{name} goal response')
    return handle, feedback


def probe_goal(span):
    from geometry_msgs.msg import Point, Vector3

    from tactex_msgs.action import Probe
    return Probe.Goal(start=Point(x=0.2, y=0.0, z=0.03), direction=Vector3(x=1.0),
                      span=span, step=0.01, approach_height=0.02, descent_speed=0.005,
                      max_descent_depth=0.015, force_limit=2.0)


def sweep_goal(contacts, record=False):
    from tactex_msgs.action import Sweep
    return Sweep.Goal(pathway=pathway(contacts), sliding_speed=0.015, edge_offset_angle=0.26,
                      press_depth=0.002, label='wood', trial=7, record=record)


def test_probe_goal_is_accepted_gets_feedback_and_can_be_cancelled(actions):
    from action_msgs.msg import GoalStatus

    from tactex_msgs.action import Probe
    handle, feedback = send(actions, Probe, 'probe', probe_goal(span=2.0))  # 201 probes
    assert handle.accepted
    wait_until(lambda: len(feedback) >= 3, 'probe feedback')
    latest = feedback[-1].feedback
    assert latest.probe_count == 201 and latest.probe_index < 201
    assert latest.last_contact.header.frame_id == 'base_link'
    cancel = result_of(handle.cancel_goal_async(), 'cancel response')
    assert len(cancel.goals_canceling) == 1
    response = result_of(handle.get_result_async(), 'probe result')
    assert response.status == GoalStatus.STATUS_CANCELED
    assert response.result.message == 'canceled'
    assert 0 < len(response.result.outcomes) < 201


def test_probe_goal_runs_to_a_pathway_result(actions):
    from action_msgs.msg import GoalStatus

    from tactex_msgs.action import Probe
    from tactex_msgs.msg import Contact
    handle, feedback = send(actions, Probe, 'probe', probe_goal(span=0.05))  # 6 probes
    response = result_of(handle.get_result_async(), 'probe result')
    assert response.status == GoalStatus.STATUS_SUCCEEDED
    result = response.result
    assert list(result.outcomes) == [Contact.STATUS_NO_CONTACT, 0, 0, 1, 0, 0]
    assert len(result.pathway.contacts) == 4 and result.pathway.step == 0.01
    assert all(c.status == Contact.STATUS_OK for c in result.pathway.contacts)
    assert (result.elapsed.sec, result.elapsed.nanosec) > (0, 0) and result.message == ''
    assert feedback and feedback[-1].feedback.contacts_found == 4


def test_sweep_goal_is_accepted_gets_feedback_and_can_be_cancelled(actions):
    from action_msgs.msg import GoalStatus

    from tactex_msgs.action import Sweep
    handle, feedback = send(actions, Sweep, 'sweep', sweep_goal(contacts=100))  # 20 s
    assert handle.accepted
    wait_until(lambda: len(feedback) >= 3, 'sweep feedback')
    progress = [f.feedback.progress for f in feedback]
    assert progress == sorted(progress) and 0 < progress[-1] < 1
    assert feedback[-1].feedback.sliding_speed == 0.015
    cancel = result_of(handle.cancel_goal_async(), 'cancel response')
    assert len(cancel.goals_canceling) == 1
    response = result_of(handle.get_result_async(), 'sweep result')
    assert response.status == GoalStatus.STATUS_CANCELED
    assert response.result.message == 'canceled' and response.result.recording_path == ''


def test_sweep_goal_runs_to_a_result_with_contact_segments(actions):
    from action_msgs.msg import GoalStatus

    from tactex_msgs.action import Sweep
    handle, feedback = send(actions, Sweep, 'sweep', sweep_goal(contacts=2, record=True))
    response = result_of(handle.get_result_async(), 'sweep result')
    assert response.status == GoalStatus.STATUS_SUCCEEDED
    result = response.result
    assert result.contact_fraction == pytest.approx(0.9) and result.speed_mean == 0.015
    assert len(result.contact_starts) == len(result.contact_ends) == 1
    assert result.recording_path == '/tmp/wood_7'
    assert feedback[-1].feedback.progress == pytest.approx(1.0)
