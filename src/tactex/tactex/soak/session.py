# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The soak test's client of a launched system: the demo's, plus what recovery is judged by.

Besides the demo's goals and parameters it adds up classifier_node's counters from its
diagnostics, hears the raw IMU, joint_states and texture/estimate (when each last carried
a finite sample), when each decided texture estimate came, and which nodes are on the
graph.
"""

from __future__ import annotations

import math
import time

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from sensor_msgs.msg import Imu, JointState

from tactex.demo.session import CLASSIFIER_STATUS, SystemClient
from tactex.soak.bookkeeping import COUNTERS, WindowLedger
from tactex_common import topics
from tactex_common.ros import SENSOR_DATA
from tactex_msgs.msg import TextureEstimate


class SoakClient(SystemClient):
    """SystemClient that also watches the streams, the classifier's counters and the graph."""

    def __init__(self) -> None:
        # Before SystemClient starts spinning: its diagnostics and estimate callbacks,
        # overridden here, read these.
        self.ledger = WindowLedger()
        self._heard = {topics.IMU_RAW: 0.0, topics.JOINT_STATES: 0.0}
        self.decisions: list[float] = []  # when each decided estimate was heard (monotonic)
        self._classifier_ok_at = 0.0  # when its diagnostics last said OK
        super().__init__()
        node = self._node
        node.create_subscription(Imu, topics.IMU_RAW, self._on_imu, SENSOR_DATA)
        node.create_subscription(JointState, topics.JOINT_STATES, self._on_joints,
                                 SENSOR_DATA)

    def _on_diagnostics(self, msg: DiagnosticArray) -> None:
        super()._on_diagnostics(msg)
        for status in msg.status:
            if status.name == CLASSIFIER_STATUS:
                if status.level == DiagnosticStatus.OK:
                    self._classifier_ok_at = time.monotonic()
                values = {kv.key: kv.value for kv in status.values}
                with self._lock:
                    self.ledger.update({key: int(values[key]) for key in COUNTERS})

    def _on_imu(self, msg: Imu) -> None:
        if math.isfinite(msg.linear_acceleration.z):
            self._heard[topics.IMU_RAW] = time.monotonic()

    def _on_joints(self, msg: JointState) -> None:
        self._heard[topics.JOINT_STATES] = time.monotonic()

    def _on_estimate(self, msg: TextureEstimate) -> None:
        super()._on_estimate(msg)
        if msg.decided:
            self.decisions.append(time.monotonic())

    def classifier_ok_since(self, since: float) -> bool:
        """Whether classifier_node's diagnostics said OK after monotonic time `since`."""
        return self._classifier_ok_at > since

    def heard_since(self, topic: str, since: float) -> bool:
        """Whether `topic` carried a finite sample after monotonic time `since`."""
        return self._heard[topic] > since

    def windows(self) -> tuple[dict[str, int], int]:
        """The classifier's counters over all its lives, and how many lives."""
        with self._lock:
            return self.ledger.totals(), self.ledger.lives

    def on_graph(self, name: str) -> bool:
        """Whether a node of that name is on the ROS graph."""
        return name in self._node.get_node_names()
