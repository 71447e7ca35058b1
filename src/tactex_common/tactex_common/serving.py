# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The server side of a tactex action: one goal at a time, and the pathway a goal slides on."""

from __future__ import annotations

from rclpy.action import GoalResponse
from rclpy.node import Node

from tactex_common import frames, topics


class OneGoal:
    """A goal callback that accepts a goal only while none runs (`done()` frees it)."""

    def __init__(self, node: Node, what: str) -> None:
        self._node, self._what = node, what
        self.busy = False

    def __call__(self, _request) -> GoalResponse:
        """Accept the goal, or refuse it (logged) while another runs."""
        if self.busy:
            self._node.get_logger().warning(f'{self._what} goal rejected: another '
                                            f'{self._what} goal is running')
            return GoalResponse.REJECT
        self.busy = True
        return GoalResponse.ACCEPT

    def done(self) -> None:
        """The running goal ended: the next may come."""
        self.busy = False


def goal_pathway(given, latest):
    """The pathway a goal slides on: its own, or when it has no contacts the latest probed.

    Args:
        given: the goal's tactex_msgs/Pathway.
        latest: the latest on probe/pathway (None before one arrived).

    Raises:
        ValueError: no contacts anywhere, or a pathway in another frame than base_link.
    """
    pathway = given if given.contacts else latest
    if pathway is None or not pathway.contacts:
        raise ValueError('the goal has no contacts and nothing was published on '
                         f'{topics.PROBE_PATHWAY}; probe the surface first')
    if pathway.header.frame_id not in ('', frames.BASE):
        raise ValueError(f'the pathway must be in {frames.BASE}, got frame '
                         f'{pathway.header.frame_id!r}')
    return pathway
