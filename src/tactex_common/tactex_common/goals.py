# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Action goals answered even when discovery loses the server's answer: by the goal's status.

A server that answers a goal before its response writer has matched the client's reader
drops the answer: rmw_fastrtps waits 100 ms for the match, and rclpy's server then logs
"Failed to send goal response" and runs the goal anyway (ros2/rmw_fastrtps#467). The
client's future never completes, though the goal executes. An accepted goal also appears
in the action's status topic, which is latched, so `GoalSender` settles its answer from
whichever arrives first. Its request can be lost the same way (the server never hears it and
nothing appears in the status): `answer` sends the goal again while none of its copies
was answered, and takes the first answer any copy gets.
"""

from __future__ import annotations

from collections.abc import Callable
import time
import uuid

from action_msgs.msg import GoalStatusArray
from rclpy.action import ActionClient
from rclpy.action.client import ClientGoalHandle
from rclpy.node import Node
from rclpy.qos import qos_profile_action_status_default
from rclpy.task import Future
from unique_identifier_msgs.msg import UUID

# How often `answer` looks for an answer (s).
POLL_S = 0.05


class GoalSender:
    """An action client whose goals are answered by the server's response or its status.

    Attributes:
        client: the rclpy ActionClient (wait_for_server, cancel and result go through it).
    """

    def __init__(self, node: Node, action_type, name: str):
        self.client = ActionClient(node, action_type, name)
        self._response_type = action_type.Impl.SendGoalService.Response
        self._unanswered: dict[bytes, Future] = {}
        node.create_subscription(GoalStatusArray, f'{name}/_action/status', self._on_status,
                                 qos_profile_action_status_default)

    def send_goal_async(self, goal, feedback_callback=None) -> Future:
        """Send `goal`; a future of its ClientGoalHandle (accepted or refused)."""
        goal_id = UUID(uuid=list(uuid.uuid4().bytes))
        key = bytes(goal_id.uuid)
        answer = Future()
        self._unanswered[key] = answer
        sent = self.client.send_goal_async(goal, feedback_callback=feedback_callback,
                                           goal_uuid=goal_id)
        sent.add_done_callback(lambda done: self._settle(key, done.result()))
        return answer

    def answer(self, goal, feedback_callback=None, *, answer_s: float, timeout_s: float,
               alive: Callable[[], bool] = lambda: True) -> ClientGoalHandle | None:
        """Send `goal` until a copy is accepted, or every copy sent is refused; that answer.

        A copy is sent every `answer_s` while one is unanswered (its request or its answer
        lost in discovery). An accepted copy wins; a refusal is the answer only once every
        copy sent was refused: a later copy is refused while an earlier one, whose answer
        was lost, runs, and that one's status may still arrive. The others are forgotten.
        None after `timeout_s` without an answer, or when `alive()` turns false.
        """
        deadline = time.monotonic() + timeout_s
        copies: list[Future] = []
        resend_at = time.monotonic()
        try:
            while time.monotonic() < deadline and alive():
                if time.monotonic() >= resend_at:
                    copies.append(self.send_goal_async(goal,
                                                       feedback_callback=feedback_callback))
                    resend_at = min(deadline, time.monotonic() + answer_s)
                answered = [copy.result() for copy in copies if copy.done()]
                accepted = next((handle for handle in answered if handle.accepted), None)
                if accepted is not None:
                    return accepted
                if len(answered) == len(copies):  # every copy refused
                    return answered[0]
                time.sleep(POLL_S)
            return None
        finally:
            for copy in copies:
                self.forget(copy)

    def forget(self, answer: Future) -> None:
        """Stop waiting for `answer` (its goal was given up as unanswered)."""
        for key, waiting in list(self._unanswered.items()):
            if waiting is answer:
                del self._unanswered[key]

    def _settle(self, key: bytes, handle: ClientGoalHandle) -> None:
        answer = self._unanswered.pop(key, None)
        if answer is not None and not answer.done():
            answer.set_result(handle)

    def _on_status(self, message: GoalStatusArray) -> None:
        for status in message.status_list:
            key = bytes(status.goal_info.goal_id.uuid)
            if key in self._unanswered:
                accepted = self._response_type(accepted=True, stamp=status.goal_info.stamp)
                self._settle(key, ClientGoalHandle(self.client, status.goal_info.goal_id,
                                                   accepted))
