# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""ROS 2 node: tactile/imu/data_raw (+ tactile/imu/mag) -> tactile/imu/data with orientation.

Diagnostics count the samples fused and those the filter rejected, by kind.
"""

from __future__ import annotations

import dataclasses
import math
import time

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor, SetParametersResult
from sensor_msgs.msg import Imu, MagneticField

from tactex_common import topics
from tactex_common.ros import COMMAND, DIAGNOSTICS_PERIOD_RANGE, SENSOR_DATA, spin, TactexNode
from tactex_sensor.madgwick import MadgwickConfig, MadgwickFilter, REJECTED_DT, REJECTED_GYRO

# Diagnostics warn while samples were rejected within this many seconds (wall clock); a
# rejection long ago stays in the counts only.
RECENT_REJECTION_S = 10.0
# Roll and pitch error of the filter: the tilt error `tactex sim stats` measures against
# the simulator's true attitude is below 2 degrees in median.
ORIENTATION_STDDEV_RAD = math.radians(2.0)


def orientation_covariance(stddev_rad: float, use_mag: bool) -> list[float]:
    """Row-major 3x3 covariance of roll, pitch, yaw (REP-145: never all zeros, 'unknown').

    Without the magnetometer nothing observes yaw: its variance is that of an angle
    uniform over +-pi, pi^2 / 3.
    """
    yaw = stddev_rad ** 2 if use_mag else math.pi ** 2 / 3
    return [stddev_rad ** 2, 0.0, 0.0, 0.0, stddev_rad ** 2, 0.0, 0.0, 0.0, yaw]


def _stamp_s(msg) -> float:
    return msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9


class MadgwickNode(TactexNode):
    """Fuse each raw IMU message as it comes, with the latest magnetometer sample if fresh.

    Unlike an exact-time synchroniser, output never waits for the magnetometer: an IMU
    message uses the newest mag message no older than `mag_timeout_s`, else IMU only.
    """

    def __init__(self, **kwargs) -> None:
        super().__init__('madgwick_node', **kwargs)
        defaults, describe = MadgwickConfig(), ParameterDescriptor
        gain_range = FloatingPointRange(from_value=0.0, to_value=10.0, step=0.0)
        gain = self.declare_parameter('gain', defaults.gain, ParameterDescriptor(
            description='filter gain beta (rad/s)', floating_point_range=[gain_range])).value
        rate_range = FloatingPointRange(from_value=0.1, to_value=1000.0, step=0.0)
        max_rate = self.declare_parameter(
            'max_rate_rad_s', defaults.max_rate_rad_s, ParameterDescriptor(
                description='a gyro axis beyond this (rad/s) is a corrupted sample: rejected, '
                            'counted', read_only=True, floating_point_range=[rate_range])).value
        use_mag = self.declare_parameter('use_mag', False, ParameterDescriptor(
            description='fuse tactile/imu/mag (MARG)', read_only=True)).value
        world_frame = self.declare_parameter('world_frame', 'enu', ParameterDescriptor(
            description='world frame of the output; only enu (REP-145)', read_only=True)).value
        self._mag_timeout = self.declare_parameter('mag_timeout_s', 0.1, ParameterDescriptor(
            description='oldest magnetometer sample still fused (s)',
            floating_point_range=[FloatingPointRange(from_value=0.0, to_value=10.0)])).value
        stddev = self.declare_parameter('orientation_stddev', ORIENTATION_STDDEV_RAD, describe(
            description='standard deviation of roll and pitch (rad) in orientation_covariance; '
                        'yaw without the magnetometer is unobserved (variance pi^2/3)',
            read_only=True, floating_point_range=[FloatingPointRange(  # 0: all zeros, unknown
                from_value=1e-4, to_value=math.pi)])).value
        self._orientation_covariance = orientation_covariance(stddev, use_mag)
        diagnostics_period = self.declare_parameter(
            'diagnostics_period_s', 1.0, ParameterDescriptor(
                description='diagnostics period (s)', read_only=True,
                floating_point_range=[DIAGNOSTICS_PERIOD_RANGE])).value
        if world_frame != 'enu':
            raise self.refused_parameter('world_frame', "'enu' only (REP-145)")
        self._filter = MadgwickFilter(MadgwickConfig(gain=gain, use_mag=use_mag,
                                                     max_rate_rad_s=max_rate))
        self._last_stamp: float | None = None
        self._received = 0
        self._published = 0
        self._mag: tuple[float, tuple[float, float, float]] | None = None
        # Rejections counted so far, and when the count last grew (wall clock).
        self._rejections_seen, self._last_rejection = 0, -math.inf
        self._publisher = self.create_publisher(Imu, topics.IMU_FILTERED, SENSOR_DATA)
        self.create_subscription(Imu, topics.IMU_RAW, self._on_imu,
                                 SENSOR_DATA)
        if use_mag:
            self.create_subscription(MagneticField, topics.MAG, self._on_mag,
                                     SENSOR_DATA)
        self._diagnostics_pub = self.create_publisher(DiagnosticArray, topics.DIAGNOSTICS,
                                                      COMMAND)
        self.create_timer(diagnostics_period, self._publish_diagnostics)
        self.add_on_set_parameters_callback(self._on_set_parameters)

    def _on_set_parameters(self, parameters) -> SetParametersResult:
        for parameter in parameters:
            if parameter.name == 'gain':  # its descriptor's range is checked before this
                self._filter.config = dataclasses.replace(self._filter.config,
                                                          gain=float(parameter.value))
            elif parameter.name == 'mag_timeout_s':
                self._mag_timeout = float(parameter.value)
        return SetParametersResult(successful=True)

    def _on_mag(self, msg: MagneticField) -> None:
        field = msg.magnetic_field
        self._mag = (_stamp_s(msg), (field.x, field.y, field.z))

    def _on_imu(self, msg: Imu) -> None:
        self._received += 1
        stamp = _stamp_s(msg)
        dt = 0.0 if self._last_stamp is None else stamp - self._last_stamp
        self._last_stamp = stamp if self._last_stamp is None else max(stamp, self._last_stamp)
        mag = None
        if self._mag is not None and abs(stamp - self._mag[0]) <= self._mag_timeout:
            mag = self._mag[1]
        w = msg.angular_velocity
        a = msg.linear_acceleration
        self._filter.update((w.x, w.y, w.z), (a.x, a.y, a.z), dt, mag)
        if self._filter.last_flags & REJECTED_GYRO:
            self.get_logger().warning(f'gyro samples rejected (an axis beyond max_rate_rad_s or '
                                      f'not finite): {self._filter.rejected["gyro"]} so far',
                                      throttle_duration_sec=5.0)
        if self._filter.last_flags & REJECTED_DT:
            self.get_logger().warning(f'a step of {dt:.6g} s between IMU stamps (not in (0, '
                                      f'{self._filter.config.max_dt_s:g}] s): no gyro '
                                      f'integration over it; {self._filter.rejected["dt"]} so far',
                                      throttle_duration_sec=5.0)
        if not self._filter.initialised:
            return
        out = Imu()
        out.header = msg.header
        out.angular_velocity = msg.angular_velocity
        out.angular_velocity_covariance = msg.angular_velocity_covariance
        out.linear_acceleration = msg.linear_acceleration
        out.linear_acceleration_covariance = msg.linear_acceleration_covariance
        out.orientation_covariance = self._orientation_covariance
        q = self._filter.quaternion
        out.orientation.w, out.orientation.x, out.orientation.y, out.orientation.z = (
            float(v) for v in q)
        self._publisher.publish(out)
        self._published += 1

    def _publish_diagnostics(self) -> None:
        """WARN before the first sample, and while samples were rejected lately (counts kept)."""
        rejected = self._filter.rejected
        total = sum(rejected.values())
        if total != self._rejections_seen:
            self._rejections_seen, self._last_rejection = total, time.monotonic()
        if not self._received:
            level, message = DiagnosticStatus.WARN, f'no {topics.IMU_RAW} yet'
        elif time.monotonic() - self._last_rejection < RECENT_REJECTION_S:
            level = DiagnosticStatus.WARN
            message = 'samples rejected: ' + ', '.join(
                f'{count} {kind}' for kind, count in rejected.items() if count)
        else:
            level, message = DiagnosticStatus.OK, 'fusing'
        values = {'received': self._received, 'published': self._published,
                  'gain': self._filter.config.gain, 'restarts': self._filter.restarts,
                  **{f'rejected_{kind}': count for kind, count in rejected.items()}}
        self.publish_diagnostics(self._diagnostics_pub, level, 'madgwick', message,
                                 values)


def main(args: list[str] | None = None) -> None:
    """Run the node until shutdown."""
    spin(MadgwickNode, args)
