# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The soak test's client of a launched system: the demo's, plus what recovery is judged by.

Besides the demo's goals and parameters it hears classifier_node's diagnostics (its
window counters), the raw IMU and joint_states (when each last carried a finite sample)
and which nodes are on the graph.
"""

from __future__ import annotations

import math
import time

from diagnostic_msgs.msg import DiagnosticArray
from sensor_msgs.msg import Imu, JointState

from tactex.demo_session import SystemClient
from tactex.soak import COUNTERS, WindowLedger
from tactex_common import topics
from tactex_common.ros import COMMAND, SENSOR_DATA

CLASSIFIER_STATUS = 'tactex_classify: classifier_node'


class SoakClient(SystemClient):
    """SystemClient that also watches the streams, the classifier's counters and the graph."""

    def __init__(self) -> None:
        super().__init__()
        self.ledger = WindowLedger()
        self._heard = {topics.IMU_RAW: 0.0, topics.JOINT_STATES: 0.0}
        node = self._node
        node.create_subscription(DiagnosticArray, topics.DIAGNOSTICS, self._on_diagnostics,
                                 COMMAND)
        node.create_subscription(Imu, topics.IMU_RAW, self._on_imu, SENSOR_DATA)
        node.create_subscription(JointState, topics.JOINT_STATES, self._on_joints,
                                 SENSOR_DATA)

    def _on_diagnostics(self, msg: DiagnosticArray) -> None:
        for status in msg.status:
            if status.name == CLASSIFIER_STATUS:
                values = {kv.key: kv.value for kv in status.values}
                with self._lock:
                    self.ledger.update({key: int(values[key]) for key in COUNTERS})

    def _on_imu(self, msg: Imu) -> None:
        if math.isfinite(msg.linear_acceleration.z):
            self._heard[topics.IMU_RAW] = time.monotonic()

    def _on_joints(self, msg: JointState) -> None:
        self._heard[topics.JOINT_STATES] = time.monotonic()

    def heard_since(self, topic: str, since: float) -> bool:
        """Whether `topic` carried a finite sample after monotonic time `since`."""
        return self._heard[topic] > since

    def windows(self) -> tuple[dict[str, int], int]:
        """The classifier's window counters over all its lives, and how many lives."""
        with self._lock:
            return self.ledger.totals(), self.ledger.lives

    def on_graph(self, name: str) -> bool:
        """Whether a node of that name is on the ROS graph."""
        return name in self._node.get_node_names()
