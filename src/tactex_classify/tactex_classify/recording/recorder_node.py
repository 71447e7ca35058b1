# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""ROS 2 node recording the tactile topics, joint_states, contacts, sweep segments, metadata."""

from __future__ import annotations

import json
from pathlib import Path
import time

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor

from tactex_classify.recording.recorder import RECORDED_TOPICS, SplitRecorder
from tactex_common import topics
from tactex_common.ros import COMMAND, message_class, RECORDING, spin, TactexNode

# Seconds without a message after which the recorder reports WARN (sensors stream at
# 120-350 Hz, so a quiet second means nothing is being recorded).
QUIET_WARN_S = 2.0


class RecorderNode(TactexNode):
    """Subscribe with raw=True and write the bytes as they come."""

    def __init__(self, **kwargs) -> None:
        super().__init__('recorder_node', **kwargs)
        describe = ParameterDescriptor
        out = self.declare_parameter('output', '', describe(
            description='recording directory to create', read_only=True)).value
        label = self.declare_parameter('label', '', describe(
            description='texture class of the recording', read_only=True)).value
        trial = self.declare_parameter('trial', -1, describe(
            description='recording / trajectory id (-1: none)', read_only=True,
            integer_range=[IntegerRange(from_value=-1, to_value=2**31 - 1, step=1)])).value
        surface = self.declare_parameter('surface', '', describe(
            description='surface description (e.g. uneven)', read_only=True)).value
        extra = self.declare_parameter('metadata', '{}', describe(
            description='more metadata as a JSON object', read_only=True)).value
        split_s = self.declare_parameter('split_s', 1.0, describe(
            description='seconds per part bag (the most a crash can lose)', read_only=True,
            floating_point_range=[FloatingPointRange(from_value=0.1, to_value=3600.0)])).value
        compress = self.declare_parameter('compress', False, describe(
            description='zstd-compress messages', read_only=True)).value
        if not out:
            raise self.refused_parameter('output', 'the recording directory to create')
        try:
            metadata = json.loads(extra)
        except ValueError:
            metadata = None
        if not isinstance(metadata, dict):
            raise self.refused_parameter('metadata', 'a JSON object')
        metadata.update({k: v for k, v in (('label', label), ('surface', surface)) if v})
        if trial >= 0:
            metadata['trial'] = trial
        self._recorder = SplitRecorder(Path(out), metadata, split_s=split_s,
                                       compress=compress).__enter__()
        for topic, type_name, qos in RECORDED_TOPICS:
            self._recorder.add_topic(topic, type_name)
            self.create_subscription(message_class(type_name), topic, self._writer_for(topic),
                                     RECORDING[qos], raw=True)
        self._out, self._last_message = out, time.monotonic()
        self._diagnostics_pub = self.create_publisher(DiagnosticArray, topics.DIAGNOSTICS,
                                                      COMMAND)
        self.create_timer(1.0, self._publish_diagnostics)
        self.get_logger().info(f'recording to {out} ({metadata})')

    def _writer_for(self, topic: str):
        def write(data: bytes) -> None:
            self._recorder.write(topic, self.get_clock().now().nanoseconds, data)
            self._last_message = time.monotonic()
        return write

    def _publish_diagnostics(self) -> None:
        """Messages and part bags written; WARN while nothing arrives."""
        quiet_s = time.monotonic() - self._last_message
        level = DiagnosticStatus.WARN if quiet_s > QUIET_WARN_S else DiagnosticStatus.OK
        message = (f'nothing received for {quiet_s:.0f} s' if level == DiagnosticStatus.WARN
                   else f'recording to {self._out}')
        self.publish_diagnostics(self._diagnostics_pub, level, 'recorder', message, {
            'output': self._out, 'messages': self._recorder.messages,
            'parts': self._recorder.parts, 'quiet_s': f'{quiet_s:.1f}'})

    def destroy_node(self) -> None:
        """Close the last part bag."""
        self._recorder.close()
        self.get_logger().info(f'recorded {self._recorder.messages} messages')
        super().destroy_node()


def main(args: list[str] | None = None) -> None:
    """Record until SIGINT, SIGTERM or SIGHUP, which close the last part bag cleanly."""
    spin(RecorderNode, args)
