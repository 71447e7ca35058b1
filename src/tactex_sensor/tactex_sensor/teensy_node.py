# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""ROS 2 node publishing the tactile module's stream from the Teensy serial link."""

from __future__ import annotations

import threading

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
from sensor_msgs.msg import FluidPressure, Imu, MagneticField, Temperature

from tactex_common import frames, topics
from tactex_common.ros import COMMAND, DIAGNOSTICS_PERIOD_RANGE, SENSOR_DATA, spin, TactexNode
from tactex_sensor.link import SerialLink
from tactex_sensor.messages import NoiseVariances, tactile_cdr, TACTILE_TOPICS
from tactex_sensor.protocol import DEFAULT_BAUD
from tactex_sensor.reader import TeensyReader

VARIANCE_UNITS = {'accel': '(m/s^2)^2', 'gyro': '(rad/s)^2', 'mag': 'T^2', 'pressure': 'Pa^2',
                  'temperature': 'degC^2'}
# Line rates a serial port can be opened at (a Teensy's USB serial ignores the rate).
BAUD_RANGE = IntegerRange(from_value=300, to_value=12_000_000, step=1)


class TeensyNode(TactexNode):
    """Serial reader thread -> tactile/imu/data_raw, imu/mag, pressure, temperature."""

    def __init__(self, **kwargs) -> None:
        super().__init__('teensy_node', **kwargs)
        port = self.declare_parameter(
            'port', '/dev/ttyACM0',
            ParameterDescriptor(description='serial device of the Teensy', read_only=True)).value
        baud = self.declare_parameter(
            'baud', DEFAULT_BAUD,
            ParameterDescriptor(description='line rate (baud)', read_only=True,
                                integer_range=[BAUD_RANGE])).value
        self._frame_id = self.declare_parameter(
            'frame_id', frames.SENSOR, ParameterDescriptor(description='frame of the samples',
                                                           read_only=True)).value
        diagnostics_period = self.declare_parameter(
            'diagnostics_period_s', 1.0,
            ParameterDescriptor(description='diagnostics period (s)', read_only=True,
                                floating_point_range=[DIAGNOSTICS_PERIOD_RANGE])).value
        # One `<channel>_variance` parameter per covariance the messages carry.
        self._noise = NoiseVariances(**{
            channel: self.declare_parameter(
                f'{channel}_variance', getattr(NoiseVariances, channel), ParameterDescriptor(
                    description=f'{channel} noise variance {unit}', read_only=True,
                    floating_point_range=[FloatingPointRange(from_value=0.0, to_value=1e6)])
            ).value for channel, unit in VARIANCE_UNITS.items()})
        self._reader = TeensyReader(SerialLink(port, int(baud)),
                                    lambda: self.get_clock().now().nanoseconds)
        # Publishers in the order of tactex_sensor.messages.TACTILE_TOPICS.
        self._tactile_pubs = [
            self.create_publisher(message_class, topic, SENSOR_DATA)
            for message_class, (topic, _) in zip(
                (Imu, MagneticField, FluidPressure, Temperature), TACTILE_TOPICS, strict=True)]
        self._diagnostics_pub = self.create_publisher(DiagnosticArray, topics.DIAGNOSTICS,
                                                      COMMAND)
        self.create_timer(diagnostics_period, self._publish_diagnostics)
        self._running = True
        self._thread = threading.Thread(target=self._read_loop, name='teensy_reader',
                                        daemon=True)
        self._thread.start()
        self.get_logger().info(f'reading {port} at {baud} baud')

    def _read_loop(self) -> None:
        """Blocking serial reads live here, never in the executor."""
        while self._running:
            for stamp_ns, sample in self._reader.poll():
                self._publish(stamp_ns, sample)

    def _publish(self, stamp_ns: int, sample) -> None:
        for publisher, data in zip(self._tactile_pubs, tactile_cdr(
                stamp_ns, self._frame_id, sample.accel, sample.gyro, sample.mag,
                sample.pressure_pa, sample.temperature_c, self._noise), strict=True):
            publisher.publish(data)

    def _publish_diagnostics(self) -> None:
        ok, summary, values = self._reader.health()
        level = DiagnosticStatus.OK if ok else (
            DiagnosticStatus.ERROR if values['link'] != 'connected' else DiagnosticStatus.WARN)
        self.publish_diagnostics(self._diagnostics_pub, level, 'teensy', summary,
                                 values, hardware_id=values['port'])
        if values['link'] != 'connected':
            self.get_logger().warning(
                f'no sensor stream: {summary}. Check the port (ls -l {values["port"]}; the '
                'user in the dialout group), that the Teensy runs the tactex firmware, or '
                'launch with sim:=true to use the simulator', throttle_duration_sec=10.0)

    def destroy_node(self) -> None:
        """Stop the reader thread and close the port."""
        self._running = False
        self._thread.join(timeout=1.0)
        self._reader.link.close()
        super().destroy_node()


def main(args: list[str] | None = None) -> None:
    """Run the node until shutdown."""
    spin(TeensyNode, args)
