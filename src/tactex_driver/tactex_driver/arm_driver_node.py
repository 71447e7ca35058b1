# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""ROS 2 driver of the OpenMANIPULATOR-X: joint_states out, arm/joint_trajectory in, safely."""

from __future__ import annotations

from collections import deque
import math
import time

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
import numpy as np
from rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor
from sensor_msgs.msg import JointState
from std_srvs.srv import SetBool, Trigger
from trajectory_msgs.msg import JointTrajectory

from tactex_common import topics
from tactex_common.constants import SERVO_IDS
from tactex_common.ros import COMMAND, spin, TactexNode
from tactex_driver import control_table as ct
from tactex_driver.arm import ArmController, Mode
from tactex_driver.bus import DEFAULT_BAUD, ServoBus
from tactex_driver.errors import CommunicationError, DriverError, TrajectoryRejected
from tactex_driver.joints import JointMap, NEWTON_METRE_PER_AMPERE
from tactex_driver.playback import JointLimits

TORQUE_POLICIES = ('hold', 'release')


class ArmDriverNode(TactexNode):
    """100 Hz loop: read servos -> joint_states; controller goal -> servos."""

    def __init__(self, **kwargs) -> None:
        super().__init__('arm_driver', **kwargs)
        describe = ParameterDescriptor
        port = self.declare_parameter('port', '/dev/ttyUSB0', describe(
            description='serial device of the U2D2/OpenCR', read_only=True)).value
        baud = self.declare_parameter('baud', DEFAULT_BAUD, describe(
            description='bus rate (baud): one the servos offer', read_only=True)).value
        ids = self.declare_parameter('servo_ids', list(SERVO_IDS), describe(
            description='IDs of joint1..joint4 and the gripper (distinct, 0 to 252)',
            read_only=True)).value
        rate = self.declare_parameter('control_rate_hz', 100.0, describe(
            description='control loop and joint_states rate (Hz)', read_only=True,
            floating_point_range=[FloatingPointRange(from_value=1.0, to_value=1000.0)])).value
        start_tolerance = self.declare_parameter('start_tolerance', 0.1, describe(
            description='largest distance of a trajectory first point from the state (rad)',
            read_only=True,
            floating_point_range=[FloatingPointRange(from_value=0.0, to_value=math.pi)])).value
        gripper_ratio = self.declare_parameter('gripper_m_per_rad', 0.015, describe(
            description='gripper travel per servo radian (m/rad)', read_only=True,
            floating_point_range=[FloatingPointRange(from_value=1e-4, to_value=0.1)])).value
        self._profile_velocity = self.declare_parameter('profile_velocity', 2.0, describe(
            description='servo profile velocity (rad/s), a second speed limit in the servos',
            read_only=True, floating_point_range=[FloatingPointRange(
                from_value=ct.PROFILE_VELOCITY_RANGE_RAD_S[0],
                to_value=ct.PROFILE_VELOCITY_RANGE_RAD_S[1])])).value
        self._operating_modes = self.declare_parameter('operating_modes', [
            ct.MODE_POSITION] * 4 + [ct.MODE_CURRENT_BASED_POSITION], describe(
            description='operating mode per servo (3 position, 5 current-based position), '
                        'written while torque is off', read_only=True)).value
        self._torque_on_start = self.declare_parameter('torque_on_start', True, describe(
            description='enable torque once connected', read_only=True)).value
        self._torque_on_exit = self.declare_parameter('torque_on_exit', 'hold', describe(
            description='on shutdown: hold (torque stays on at the present pose) or release',
            read_only=True)).value
        self._max_backoff = self.declare_parameter('max_backoff_s', 2.0, describe(
            description='longest wait between reconnection attempts (s)', read_only=True,
            floating_point_range=[FloatingPointRange(from_value=0.05, to_value=60.0)])).value
        if self._torque_on_exit not in TORQUE_POLICIES:
            raise self.refused_parameter('torque_on_exit', ' or '.join(TORQUE_POLICIES))
        if baud not in ct.BAUD_RATES.values():
            raise self.refused_parameter('baud', ', '.join(map(str, ct.BAUD_RATES.values())))
        low, high = ct.SERVO_ID_RANGE
        if not all(low <= i <= high for i in ids) or len(set(ids)) != len(ids):
            raise self.refused_parameter('servo_ids', f'distinct IDs from {low} to {high}')
        if not set(self._operating_modes) <= set(ct.HOLDING_MODES):
            raise self.refused_parameter('operating_modes', 'modes that hold a position: '
                                         + ' or '.join(map(str, ct.HOLDING_MODES)))

        self._limits = JointLimits.of_robot()
        if len(ids) != len(self._limits.names):
            raise self.refused_parameter('servo_ids', f'{len(self._limits.names)} IDs, of '
                                                      f'{", ".join(self._limits.names)}')
        if len(self._operating_modes) != len(ids):
            raise self.refused_parameter('operating_modes', f'one mode per servo ({len(ids)})')
        self._joints = JointMap(gripper_ratio)
        self._bus = ServoBus(port, baud=baud, ids=ids)
        self._controller = ArmController(self._limits, start_tolerance=start_tolerance)
        self._period = 1.0 / rate
        self._connected = False
        self._backoff = 0.05
        self._next_attempt = 0.0
        self._comm_errors = 0
        self._last_error = ''
        self._hardware_errors: dict[int, int] = {}
        self._tick_times: deque[float] = deque(maxlen=1000)

        self._state_pub = self.create_publisher(JointState, topics.JOINT_STATES, COMMAND)
        self._diagnostics_pub = self.create_publisher(DiagnosticArray, topics.DIAGNOSTICS, COMMAND)
        self.create_subscription(JointTrajectory, topics.JOINT_TRAJECTORY, self._on_trajectory,
                                 10)
        self.create_service(Trigger, 'arm/stop', self._on_stop)
        self.create_service(SetBool, 'arm/torque', self._on_torque)
        self.create_service(Trigger, 'arm/reset', self._on_reset)
        self.create_timer(self._period, self._tick)
        self.create_timer(1.0, self._publish_diagnostics)
        self.get_logger().info(f'arm driver on {port} ({baud} baud), servos {ids}, {rate} Hz')

    # -- state, read-only (diagnostics publish the same) --------------------------------
    @property
    def mode(self) -> Mode:
        """The controller's mode."""
        return self._controller.mode

    @property
    def last_event(self) -> str:
        """What last happened to the motion (executing, stopped, rejected, fault)."""
        return self._controller.last_event

    @property
    def connected(self) -> bool:
        """True while the servos answer."""
        return self._connected

    @property
    def rejected_trajectories(self) -> int:
        """Trajectories refused so far."""
        return self._controller.rejected

    @property
    def communication_errors(self) -> int:
        """Failed bus exchanges and connection attempts so far."""
        return self._comm_errors

    # -- control loop ---------------------------------------------------------------
    def _now(self) -> float:
        return time.monotonic()

    def _tick(self) -> None:
        now = self._now()
        self._tick_times.append(now)
        if not self._connected:
            if now >= self._next_attempt:
                self._connect(now)
            return
        try:
            state = self._bus.read_state()
        except CommunicationError as err:
            self._lost(now, err)
            return
        positions = self._joints.to_joint(state.positions)
        self._controller.update_measured(positions)
        self._publish_state(positions, self._joints.to_joint(state.velocities),
                            self._joints.to_joint_effort(state.currents * NEWTON_METRE_PER_AMPERE))
        if state.alerts and self._controller.mode is not Mode.FAULT:
            self._on_alert(state.alerts)
        goal = self._controller.goal(now)
        if goal is None:
            return
        try:
            self._bus.write_goals(self._joints.to_servo(self._limits.clamp(goal)))
        except CommunicationError as err:
            self._lost(now, err)

    def _connect(self, now: float) -> None:
        try:
            if not self._bus.is_open:
                self._bus.open()
            self._bus.ping()
            errors = {k: v for k, v in self._bus.hardware_errors().items() if v}
            if not any(self._bus.read_byte(ct.TORQUE_ENABLE).values()):
                self._bus.write_byte(ct.OPERATING_MODE, self._operating_modes)
            state = self._bus.read_state()
            self._controller.update_measured(self._joints.to_joint(state.positions))
            self._bus.write_word(ct.PROFILE_VELOCITY, int(ct.rad_s_to_velocity(
                self._profile_velocity)))
        except DriverError as err:
            self._last_error = str(err)
            self._comm_errors += 1
            self._next_attempt = now + self._backoff
            self._backoff = min(2 * self._backoff, self._max_backoff)
            self.get_logger().warning(f'servos unreachable ({err}); retrying in '
                                      f'{self._next_attempt - now:.2f} s. Check the U2D2 '
                                      'port, power, baud rate and servo IDs against '
                                      'config/driver.yaml, or launch with sim:=true',
                                      throttle_duration_sec=5.0)
            return
        self._connected = True
        self._backoff = 0.05
        self.get_logger().info('servos connected')
        if errors:
            self._on_alert(tuple(errors))
        elif self._controller.mode is Mode.TORQUE_OFF and self._torque_on_start:
            self._set_torque(True)
        elif self._controller.mode is not Mode.TORQUE_OFF:
            self._controller.torque_on(now)  # back after a loss: hold where the arm is

    def _lost(self, now: float, err: Exception) -> None:
        self._comm_errors += 1
        self._last_error = str(err)
        self._controller.stop(now, 'communication lost')
        self._connected = False
        self._next_attempt = now + self._backoff
        self._backoff = min(2 * self._backoff, self._max_backoff)
        self.get_logger().error(f'communication lost: {err}; holding the last goal and '
                                'retrying', throttle_duration_sec=2.0)

    def _on_alert(self, servos) -> None:
        try:
            self._hardware_errors = {k: v for k, v in self._bus.hardware_errors().items() if v}
        except DriverError:
            self._hardware_errors = {servo: -1 for servo in servos}
        detail = '; '.join(f'servo {servo}: {ct.describe_hardware_error(code)}'
                           if code >= 0 else f'servo {servo}: unknown'
                           for servo, code in self._hardware_errors.items())
        self._controller.fault(detail or f'alert from servos {list(servos)}')
        self.get_logger().error(f'hardware error ({detail}); motion disabled until arm/reset')

    def _publish_state(self, positions, velocities, efforts) -> None:
        msg = JointState()
        msg.header.stamp = self.get_clock().now().to_msg()
        msg.name = list(self._limits.names)
        msg.position = [float(v) for v in positions]
        msg.velocity = [float(v) for v in velocities]
        msg.effort = [float(v) for v in efforts]
        self._state_pub.publish(msg)

    # -- commands -------------------------------------------------------------------
    def _on_trajectory(self, msg: JointTrajectory) -> None:
        if not self._connected:
            self._controller.reject('servos not connected')
            self.get_logger().error('trajectory rejected: servos not connected')
            return
        ok, report = self._controller.execute_message(msg, self._now())
        if ok:
            self.get_logger().info(report)
        else:
            self.get_logger().error(report)

    def _on_stop(self, request, response):
        self._controller.stop(self._now())
        response.success = True
        response.message = f'holding ({self._controller.mode.value})'
        return response

    def _on_torque(self, request, response):
        try:
            self._set_torque(request.data)
        except DriverError as err:
            response.success, response.message = False, str(err)
            return response
        response.success = True
        response.message = f'torque {"on" if request.data else "off"}'
        return response

    def _set_torque(self, enabled: bool) -> None:
        if not self._connected:
            raise CommunicationError('servos not connected')
        if enabled and self._controller.mode is Mode.FAULT:
            raise TrajectoryRejected(f'in fault ({self._controller.fault_reason}); call '
                                     'arm/reset first')
        if enabled:
            state = self._bus.read_state()
            self._controller.update_measured(self._joints.to_joint(state.positions))
            # Goal = present pose before torque, so the arm does not jump.
            self._bus.write_goals(state.positions)
            self._bus.set_torque(True)
            self._controller.torque_on(self._now())
        else:
            self._bus.set_torque(False)
            self._controller.torque_off()

    def _on_reset(self, request, response):
        try:
            for servo in list(self._hardware_errors) or list(self._bus.ids):
                self._bus.reboot(servo)
        except DriverError as err:
            response.success, response.message = False, f'reset failed: {err}'
            return response
        self._hardware_errors = {}
        self._controller.reset()
        response.success = True
        response.message = 'servos rebooted; torque is off, enable it with arm/torque'
        return response

    # -- health ---------------------------------------------------------------------
    def loop_jitter_ms(self) -> tuple[float, float]:
        """Median and p99 of |period - nominal| over the last ticks (ms)."""
        if len(self._tick_times) < 3:
            return 0.0, 0.0
        jitter = np.abs(np.diff(np.array(self._tick_times)) - self._period) * 1e3
        return float(np.median(jitter)), float(np.percentile(jitter, 99))

    def _publish_diagnostics(self) -> None:
        median, p99 = self.loop_jitter_ms()
        mode = self._controller.mode
        if not self._connected:
            level, message = DiagnosticStatus.ERROR, f'disconnected: {self._last_error}'
        elif mode is Mode.FAULT:
            level, message = DiagnosticStatus.ERROR, f'fault: {self._controller.fault_reason}'
        elif self._controller.last_event.startswith('rejected'):
            level, message = DiagnosticStatus.WARN, self._controller.last_event
        else:
            level, message = DiagnosticStatus.OK, f'{mode.value}: {self._controller.last_event}'
        values = {'mode': mode.value, 'connected': str(self._connected),
                  'last_event': self._controller.last_event,
                  'communication_errors': str(self._comm_errors),
                  'rejected_trajectories': str(self._controller.rejected),
                  'last_error': self._last_error,
                  'hardware_errors': str(self._hardware_errors),
                  'loop_jitter_median_ms': f'{median:.3f}', 'loop_jitter_p99_ms': f'{p99:.3f}'}
        self.publish_diagnostics(self._diagnostics_pub, level, 'arm', message,
                                 values, hardware_id=self._bus.port_name)

    def destroy_node(self) -> None:
        """Apply the torque policy and close the bus."""
        if self._connected:
            try:
                if self._torque_on_exit == 'release':
                    self._bus.set_torque(False)
                else:
                    state = self._bus.read_state()
                    self._bus.write_goals(state.positions)  # hold where it stands
            except DriverError as err:
                self.get_logger().warning(f'could not apply the exit torque policy: {err}')
        self._bus.close()
        super().destroy_node()


def main(args: list[str] | None = None) -> None:
    """Run the driver until shutdown."""
    spin(ArmDriverNode, args)
