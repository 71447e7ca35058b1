# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The live system as a Foxglove WebSocket server, no RViz needed: ViewNode (view_node).

Subscribes to the tactile topics, the joint states, the probed pathway, the sweep state
and the texture estimates, and logs each to a Foxglove channel (tactex.view.channels) on
ws://HOST:PORT (localhost unless told otherwise). Foxglove opens it with
config/foxglove_layout.json. Started by `tactex view` or `view:=true` on a launch.
"""

from __future__ import annotations

import math
import os

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
import foxglove
from foxglove.channels import FrameTransformsChannel, SceneUpdateChannel
from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
from sensor_msgs.msg import FluidPressure, Imu, JointState, MagneticField
from std_msgs.msg import Bool

from tactex.view.channels import (
    asset,
    channel_name,
    frame_transforms,
    JSON_CHANNELS,
    PATHWAY_CHANNEL,
    pathway_scene,
    schema_bytes,
    TF_CHANNEL,
)
from tactex_common import topics
from tactex_common.ros import COMMAND, LATCHED, SENSOR_DATA, spin, TactexNode
from tactex_common.stamps import stamp_ns
from tactex_msgs.msg import Pathway, TextureEstimate
from tactex_probe.messages import contact_arrays


def _number(value: float) -> float | None:
    """A value JSON can carry: a non-finite one (a silent chip's NaN) as null."""
    return float(value) if math.isfinite(value) else None


def _vector(v) -> dict[str, float | None]:
    return {'x': _number(v.x), 'y': _number(v.y), 'z': _number(v.z)}


class ViewNode(TactexNode):
    """Forwards the system's topics to a Foxglove WebSocket server it runs."""

    def __init__(self, **kwargs) -> None:
        super().__init__('view_node', **kwargs)
        describe = ParameterDescriptor
        host = self.declare_parameter('host', '127.0.0.1', describe(
            description='address the WebSocket server binds to (0.0.0.0: every interface)',
            read_only=True)).value
        port = self.declare_parameter('port', 8765, describe(
            description='its TCP port (0: any free one, logged)', read_only=True,
            integer_range=[IntegerRange(from_value=0, to_value=65535, step=1)])).value
        tf_rate = self.declare_parameter('tf_rate_hz', 30.0, describe(
            description='most arm transforms per second sent', read_only=True,
            floating_point_range=[FloatingPointRange(from_value=1.0, to_value=1000.0)])).value
        niceness = self.declare_parameter('nice', 10, describe(
            description='scheduling niceness added to this process: the view yields the CPU '
                        'to the nodes that measure and command (0: as they)', read_only=True,
            integer_range=[IntegerRange(from_value=0, to_value=19, step=1)])).value
        sample_rate = self.declare_parameter('max_rate_hz', 60.0, describe(
            description='most messages per second forwarded per tactile channel (a display '
                        'rate; 0: every sample, which costs the sensor path latency on a '
                        'loaded machine: bench/bench_observers.py)', read_only=True,
            floating_point_range=[FloatingPointRange(from_value=0.0, to_value=10000.0)])).value
        self._sample_period_ns = int(1e9 / sample_rate) if sample_rate > 0 else 0
        self._last_sample_ns: dict[str, int] = {}
        self._tf_period_ns = int(1e9 / tf_rate)
        self._server = None
        try:
            self._server = foxglove.start_server(name='tactex', host=host, port=port,
                                                 asset_handler=asset)
        except RuntimeError as err:  # an address this machine has not, or a port in use
            name = 'port' if 'in use' in str(err) else 'host'
            raise self.refused_parameter(name, f'a {name} this machine can listen on '
                                               f'({str(err).split(": ", 1)[-1]})') from None
        os.nice(niceness)  # once listening: a refused host or port leaves the caller as it was
        self._tf = FrameTransformsChannel(TF_CHANNEL)
        self._pathway = SceneUpdateChannel(PATHWAY_CHANNEL)
        self._json = {topic: foxglove.Channel(
            channel_name(topic), message_encoding='json',
            schema=foxglove.Schema(name=name, encoding='jsonschema', data=schema_bytes(schema)))
            for topic, (name, schema) in JSON_CHANNELS.items()}
        self.forwarded = dict.fromkeys([TF_CHANNEL, PATHWAY_CHANNEL,
                                        *map(channel_name, JSON_CHANNELS)], 0)
        self.create_subscription(Imu, topics.IMU_RAW, self._on_imu_raw, SENSOR_DATA)
        self.create_subscription(Imu, topics.IMU_FILTERED, self._on_imu, SENSOR_DATA)
        self.create_subscription(MagneticField, topics.MAG, self._on_mag, SENSOR_DATA)
        self.create_subscription(FluidPressure, topics.PRESSURE, self._on_pressure, SENSOR_DATA)
        self.create_subscription(JointState, topics.JOINT_STATES, self._on_joints, COMMAND)
        self.create_subscription(Pathway, topics.PROBE_PATHWAY, self._on_pathway, LATCHED)
        self.create_subscription(Bool, topics.SWEEP_ACTIVE, self._on_sweep, COMMAND)
        self.create_subscription(TextureEstimate, topics.TEXTURE_ESTIMATE, self._on_estimate,
                                 COMMAND)
        self._diagnostics_pub = self.create_publisher(DiagnosticArray, topics.DIAGNOSTICS,
                                                      COMMAND)
        self.create_timer(1.0, self._publish_diagnostics)
        self.url = f'ws://{host}:{self._server.port}'
        self.get_logger().info(f'Foxglove live view on {self.url}: open it in Foxglove '
                               '(Open connection, Foxglove WebSocket) with the layout '
                               'config/foxglove_layout.json')

    def destroy_node(self) -> None:
        """Stop the WebSocket server with the node."""
        if self._server is not None:
            self._server.stop()
        super().destroy_node()

    def _log(self, topic: str, message: dict, header) -> None:
        self._json[topic].log(message, log_time=stamp_ns(header.stamp) or None)
        self.forwarded[channel_name(topic)] += 1

    def _due(self, topic: str, header, period_ns: int | None = None) -> bool:
        """Whether a message on `topic` is forwarded: one a period (default max_rate_hz's).

        The arm's transforms pass tf_rate_hz's period.
        """
        period_ns = self._sample_period_ns if period_ns is None else period_ns
        stamp, last = stamp_ns(header.stamp), self._last_sample_ns.get(topic)
        if last is not None and last <= stamp < last + period_ns:
            return False  # a stamp going back (a restart, a looped bag) starts anew
        self._last_sample_ns[topic] = stamp
        return True

    # -- the topics ---------------------------------------------------------------------
    def _on_imu_raw(self, msg: Imu) -> None:
        if not self._due(topics.IMU_RAW, msg.header):
            return
        self._log(topics.IMU_RAW, {'linear_acceleration': _vector(msg.linear_acceleration),
                                   'angular_velocity': _vector(msg.angular_velocity)},
                  msg.header)

    def _on_imu(self, msg: Imu) -> None:
        if not self._due(topics.IMU_FILTERED, msg.header):
            return
        q = msg.orientation
        self._log(topics.IMU_FILTERED, {'orientation': {**_vector(q), 'w': _number(q.w)}},
                  msg.header)

    def _on_mag(self, msg: MagneticField) -> None:
        if not self._due(topics.MAG, msg.header):
            return
        self._log(topics.MAG, {'magnetic_field': _vector(msg.magnetic_field)}, msg.header)

    def _on_pressure(self, msg: FluidPressure) -> None:
        if not self._due(topics.PRESSURE, msg.header):
            return
        self._log(topics.PRESSURE, {'fluid_pressure': _number(msg.fluid_pressure)}, msg.header)

    def _on_joints(self, msg: JointState) -> None:
        if not self._due(topics.JOINT_STATES, msg.header, self._tf_period_ns):
            return
        stamp = stamp_ns(msg.header.stamp)
        positions = dict(zip(msg.name, msg.position, strict=False))
        self._tf.log(frame_transforms(positions, stamp), log_time=stamp or None)
        self.forwarded[TF_CHANNEL] += 1

    def _on_pathway(self, msg: Pathway) -> None:
        points, normals = contact_arrays(msg)
        stamp = stamp_ns(msg.header.stamp)
        self._pathway.log(pathway_scene(points, normals, msg.header.frame_id, stamp),
                          log_time=stamp or None)
        self.forwarded[PATHWAY_CHANNEL] += 1

    def _on_sweep(self, msg: Bool) -> None:
        self._json[topics.SWEEP_ACTIVE].log({'active': bool(msg.data)})
        self.forwarded[channel_name(topics.SWEEP_ACTIVE)] += 1

    def _on_estimate(self, msg: TextureEstimate) -> None:
        self._log(topics.TEXTURE_ESTIMATE, {
            'label': msg.label, 'confidence': _number(msg.confidence),
            'decided': bool(msg.decided), 'windows_used': int(msg.windows_used),
            'contact_seconds': _number(msg.contact_seconds),
            'probabilities': dict(zip(msg.class_names, map(_number, msg.probabilities),
                                      strict=False))}, msg.header)

    def _publish_diagnostics(self) -> None:
        values = {'url': self.url, **{f'forwarded{name.replace("/", "_")}': str(count)
                                      for name, count in self.forwarded.items()}}
        self.publish_diagnostics(self._diagnostics_pub, DiagnosticStatus.OK, 'view',
                                 f'serving {self.url}', values)


def serve(args: list[str] | None = None) -> None:
    """Run ViewNode until a stop signal (`args`: ROS arguments, as view_node takes them)."""
    spin(ViewNode, args)
