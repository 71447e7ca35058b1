# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""GoalSender: a goal is answered by the server's response or, if that is lost, by its status."""

from contextlib import contextmanager
import threading
import time

import pytest
from support.processes import wait_for

pytest.importorskip('tactex_msgs', reason='tactex_msgs is not built in this environment')

pytestmark = pytest.mark.ros


@contextmanager
def served(ros_context, name: str, execute, on_goal, executor_type):
    """A Probe action server `name` (execute, goal callback) and a GoalSender to it, spun."""
    from rclpy.action import ActionServer
    import rclpy.node

    from tactex_common.goals import GoalSender
    from tactex_msgs.action import Probe

    nodes = [rclpy.node.Node(f'{name}_server', context=ros_context),
             rclpy.node.Node(f'{name}_client', context=ros_context)]
    server = ActionServer(nodes[0], Probe, name, execute_callback=execute,
                          goal_callback=on_goal)
    sender = GoalSender(nodes[1], Probe, name)
    executor = executor_type(context=ros_context)
    for node in nodes:
        executor.add_node(node)
    thread = threading.Thread(target=executor.spin, daemon=True)
    thread.start()
    try:
        assert sender.client.wait_for_server(timeout_sec=10.0)
        yield sender, Probe
    finally:
        executor.shutdown(timeout_sec=5.0)
        thread.join(timeout=5.0)
        server.destroy()
        for node in nodes:
            node.destroy_node()


@pytest.fixture
def action_pair(ros_context):
    """A Probe action server that accepts goals with span > 0, and a GoalSender to it."""
    from rclpy.action import GoalResponse
    from rclpy.executors import SingleThreadedExecutor

    from tactex_msgs.action import Probe

    def execute(handle):
        handle.succeed()
        return Probe.Result(message=f'span {handle.request.span:g}')

    with served(ros_context, 'probe', execute,
                lambda goal: GoalResponse.ACCEPT if goal.span > 0 else GoalResponse.REJECT,
                SingleThreadedExecutor) as pair:
        yield pair


def result_message(handle):
    result = handle.get_result_async()
    assert wait_for(result.done, 10)
    return result.result().result.message


def test_an_answered_goal_is_accepted_and_its_result_arrives(action_pair):
    sender, Probe = action_pair
    sent = sender.send_goal_async(Probe.Goal(span=0.05))
    assert wait_for(sent.done, 10)
    assert sent.result().accepted
    assert result_message(sent.result()) == 'span 0.05'


def test_a_refused_goal_is_answered_as_refused(action_pair):
    sender, Probe = action_pair
    sent = sender.send_goal_async(Probe.Goal(span=0.0))
    assert wait_for(sent.done, 10)
    assert not sent.result().accepted


def test_a_goal_whose_answer_is_lost_is_found_by_its_status_and_its_result_arrives(
        action_pair, monkeypatch):
    from rclpy.task import Future

    sender, Probe = action_pair
    send = sender.client.send_goal_async
    # The server accepts and runs the goal, but its answer never reaches the client, as
    # when the server answers before discovery has matched the client's reader.
    monkeypatch.setattr(sender.client, 'send_goal_async',
                        lambda *args, **kwargs: (send(*args, **kwargs), Future())[1])
    sent = sender.send_goal_async(Probe.Goal(span=0.07))
    assert wait_for(sent.done, 10)
    assert sent.result().accepted
    assert result_message(sent.result()) == 'span 0.07'


def test_a_goal_whose_request_is_lost_is_sent_again_until_a_copy_is_answered(action_pair,
                                                                            monkeypatch):
    from rclpy.task import Future

    sender, Probe = action_pair
    send = sender.client.send_goal_async
    sent = []

    def lose_the_first(*args, **kwargs):
        # The first request never reaches the server, as when it is written before
        # discovery matched the server's reader: no answer, nothing in the status.
        sent.append(args)
        return send(*args, **kwargs) if len(sent) > 1 else Future()
    monkeypatch.setattr(sender.client, 'send_goal_async', lose_the_first)
    handle = sender.answer(Probe.Goal(span=0.03), answer_s=0.5, timeout_s=10.0)
    assert handle is not None and handle.accepted and len(sent) == 2
    assert result_message(handle) == 'span 0.03'


def test_no_answer_at_all_is_none_after_the_timeout(action_pair, monkeypatch):
    from rclpy.task import Future

    sender, Probe = action_pair
    # Every request is lost.
    monkeypatch.setattr(sender.client, 'send_goal_async', lambda *args, **kwargs: Future())
    assert sender.answer(Probe.Goal(span=0.03), answer_s=0.2, timeout_s=0.7) is None


def test_a_copy_refused_while_an_earlier_copy_runs_does_not_hide_that_copy(ros_context,
                                                                           monkeypatch):
    """A later copy refused because an earlier one runs does not hide the earlier one.

    The first copy's answer is lost and its status comes late; a second copy, sent
    meanwhile, is refused because the first one runs. The answer is the first copy.
    """
    from rclpy.action import GoalResponse
    from rclpy.executors import MultiThreadedExecutor
    from rclpy.task import Future

    from tactex_msgs.action import Probe

    running = threading.Event()

    def execute(handle):
        threading.Event().wait(1.5)  # runs long enough for a second copy to be refused
        running.clear()
        handle.succeed()
        return Probe.Result(message='first copy')

    def on_goal(_request):
        if running.is_set():
            return GoalResponse.REJECT
        running.set()
        return GoalResponse.ACCEPT

    with served(ros_context, 'busy', execute, on_goal, MultiThreadedExecutor) as (sender, _):
        send, settle = sender.client.send_goal_async, sender._settle
        sent = []

        def lose_the_first_answer(*args, **kwargs):
            sent.append(send(*args, **kwargs))
            return Future() if len(sent) == 1 else sent[-1]
        started = time.monotonic()
        monkeypatch.setattr(sender.client, 'send_goal_async', lose_the_first_answer)
        # Nothing is heard for a second (discovery under load); the first copy's status
        # is heard when it ends, a refusal of a later copy before that.
        monkeypatch.setattr(sender, '_settle', lambda key, handle: settle(key, handle)
                            if time.monotonic() - started > 1.0 else None)
        handle = sender.answer(Probe.Goal(span=0.03), answer_s=0.3, timeout_s=10.0)
        assert len(sent) >= 2
        assert handle is not None and handle.accepted
        assert result_message(handle) == 'first copy'
