# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""ROS 2 node: the `probe` action, driving the arm through the exploration core.

joint_states, tactile/imu/data (Madgwick attitude) and tactile/pressure in;
arm/joint_trajectory out. While a goal runs the core (`tactex_probe.exploration`) steps at
`control_rate_hz` on the node's clock (simulated time with use_sim_time); every probe's
outcome is published on probe/contacts (PoseArray, z axis = outward normal), probe/pathway
(tactex_msgs/Pathway, transient-local), probe/markers and as action feedback, and the
pathway file is rewritten atomically. `probe_on_start` sends the node's own goal, built
from its `goal.*` parameters, as soon as the arm and the sensor are heard.
"""

from __future__ import annotations

import math
from pathlib import Path

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import Point, Pose, PoseArray
from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
from rclpy.action import ActionClient, ActionServer, CancelResponse, GoalResponse
from rclpy.qos import QoSProfile
from rclpy.task import Future
from rclpy.time import Time
from sensor_msgs.msg import FluidPressure, Imu, JointState
from std_msgs.msg import Header
from trajectory_msgs.msg import JointTrajectory
from visualization_msgs.msg import MarkerArray

from tactex_common import topics
from tactex_common.ros import COMMAND, LATCHED, SENSOR_DATA, spin, TactexNode
from tactex_common.stamps import stamp_ns
from tactex_description.geometry import ARM_JOINT_NAMES
from tactex_msgs.action import Probe
from tactex_msgs.msg import Pathway as PathwayMsg
from tactex_probe.detection import DEFAULT_PA_PER_NEWTON, DetectorConfig
from tactex_probe.errors import ParameterError
from tactex_probe.exploration import Explorer
from tactex_probe.explorer_interface import (
    Command,
    ExplorerConfig,
    Feedback,
    Finished,
    Method,
    Outcome,
    Recorded,
    Stop,
)
from tactex_probe.messages import (
    duration_message,
    feedback_message,
    goal_message,
    marker_message,
    orientation_message,
    parameters_from_goal,
    pathway_message,
    stop_message,
    trajectory_message,
)
from tactex_probe.pathway import (
    DEFAULT_GOAL,
    FRAME_ID,
    PARAMETER_RANGES,
    Pathway,
    ProbeParameters,
)

# Samples each sensor subscription may queue while the node is busy.
INPUT_QUEUE = 100
# The latest feedback is sent again at least this often (s): a descent takes seconds.
FEEDBACK_PERIOD_S = 0.5


def _float_range(low: float, high: float) -> list[FloatingPointRange]:
    return [FloatingPointRange(from_value=float(low), to_value=float(high), step=0.0)]


class ProbeNode(TactexNode):
    """Serves the probe action; one goal at a time."""

    def __init__(self, **kwargs) -> None:
        super().__init__('probe_node', **kwargs)
        describe = ParameterDescriptor
        self._rate_hz = self.declare_parameter('control_rate_hz', 50.0, describe(
            description='how often the exploration steps (Hz, node clock)', read_only=True,
            floating_point_range=_float_range(5.0, 500.0))).value
        pathway_file = self.declare_parameter('pathway_file', '~/.ros/tactex/pathway.json',
                                              describe(description='where the pathway JSON is '
                                                       'written (the sweep reads it)',
                                                       read_only=True)).value
        self._probe_on_start = self.declare_parameter('probe_on_start', False, describe(
            description='send the goal of the goal.* parameters once the inputs arrive',
            read_only=True)).value
        self._config = self._declare_config()
        self._goal_values = {}
        for name, default in DEFAULT_GOAL.items():
            allowed = PARAMETER_RANGES.get(name)
            self._goal_values[name] = self.declare_parameter(f'goal.{name}', default, describe(
                description=(f'probe_on_start goal: {allowed.description} ({allowed.unit})'
                             if allowed else f'probe_on_start goal: {name} (base_link)'),
                read_only=True, **({'floating_point_range': _float_range(
                    allowed.low, allowed.high)} if allowed else {}))).value
        try:  # start and direction (points) are checked as a goal is
            self._own_goal = ProbeParameters(**self._goal_values)
        except ParameterError as err:
            field = str(err).split(' ', 1)[0]  # the message opens with the field's name
            raise self.refused_parameter(f'goal.{field}', str(err)) from None
        self._pathway_file = Path(pathway_file).expanduser()
        self._explorer: Explorer | None = None
        self._goal_handle = None
        self._finished: Future | None = None  # done when the running goal's core finishes
        self._started_ns = 0
        self._last_outcome = 'idle'
        self._last_input_ns = {'joint_states': None, 'imu': None, 'pressure': None}
        self._rejected_goals = 0
        self._feedback, self._feedback_ns = None, 0  # the latest feedback, when it was sent

        # Sensor-data QoS with a deeper queue: a busy moment must not cost samples.
        queued = QoSProfile(depth=INPUT_QUEUE, reliability=SENSOR_DATA.reliability,
                            durability=SENSOR_DATA.durability, history=SENSOR_DATA.history)
        self.create_subscription(JointState, topics.JOINT_STATES, self._on_joints, COMMAND)
        self.create_subscription(Imu, topics.IMU_FILTERED, self._on_imu, queued)
        self.create_subscription(FluidPressure, topics.PRESSURE, self._on_pressure, queued)
        self._trajectory_pub = self.create_publisher(JointTrajectory, topics.JOINT_TRAJECTORY,
                                                     COMMAND)
        self._contacts_pub = self.create_publisher(PoseArray, topics.PROBE_CONTACTS, LATCHED)
        self._pathway_pub = self.create_publisher(PathwayMsg, topics.PROBE_PATHWAY, LATCHED)
        self._markers_pub = self.create_publisher(MarkerArray, topics.PROBE_MARKERS, LATCHED)
        self._diagnostics_pub = self.create_publisher(DiagnosticArray, topics.DIAGNOSTICS,
                                                      COMMAND)
        self._server = ActionServer(
            self, Probe, topics.PROBE_ACTION, execute_callback=self._execute,
            goal_callback=self._on_goal, cancel_callback=self._on_cancel)
        self.create_timer(1.0 / self._rate_hz, self._step)
        self.create_timer(1.0, self._publish_diagnostics)
        if self._probe_on_start:
            self._client = ActionClient(self, Probe, topics.PROBE_ACTION)
            self._start_timer = self.create_timer(0.5, self._send_own_goal)
        self.get_logger().info(f'probe action ready; pathway file {self._pathway_file}')

    def _declare_config(self) -> ExplorerConfig:
        """The exploration's tuning as read-only parameters (see config/probe.yaml)."""
        describe = ParameterDescriptor
        defaults = ExplorerConfig()

        def number(name, default, description, low, high):
            return self.declare_parameter(name, float(default), describe(
                description=description, read_only=True,
                floating_point_range=_float_range(low, high))).value

        method = self.declare_parameter('method', defaults.method.value, describe(
            description='tip_then_face (locate with the tip, measure with the face) or '
                        'face_only (the original single pass)', read_only=True)).value
        refinements = self.declare_parameter('refinements', defaults.refinements, describe(
            description='touches again while the face did not lie flat', read_only=True,
            integer_range=[IntegerRange(from_value=0, to_value=10, step=1)])).value
        align = self.declare_parameter('align_tool', defaults.align_tool, describe(
            description='face_only: turn the tool to the extrapolated normal',
            read_only=True)).value
        try:
            method = Method(method)
        except ValueError:
            raise self.refused_parameter('method', ' or '.join(m.value for m in Method)) from None
        detector = DetectorConfig(pa_per_newton=number(
            'pa_per_newton', DEFAULT_PA_PER_NEWTON, 'barometer rise per newton of contact '
            'force (Pa/N): the force proxy calibration', 10.0, 1e6))
        return ExplorerConfig(
            method=method, refinements=refinements, align_tool=align, detector=detector,
            press_force_n=number('press_force', defaults.press_force_n,
                                 'force proxy pressed to before measuring (N)', 0.1, 10.0),
            press_speed_m_s=number('press_speed', defaults.press_speed_m_s,
                                   'speed along the tool axis while pressing (m/s)', 1e-4, 0.02),
            move_speed_m_s=number('move_speed', defaults.move_speed_m_s,
                                  'speed of motions in free air (m/s)', 0.001, 0.1),
            settle_s=number('settle_time', defaults.settle_s,
                            'hold after pressing before measuring (s)', 0.01, 5.0),
            measure_s=number('measure_time', defaults.measure_s,
                             'length of a measuring window (s)', 0.01, 5.0),
            refine_tolerance_rad=math.radians(number(
                'flat_tolerance_deg', math.degrees(defaults.refine_tolerance_rad),
                'the face lies flat when it turned less than this (deg)', 0.05, 10.0)),
            tip_margin_rad=math.radians(number(
                'tip_margin_deg', math.degrees(defaults.tip_margin_rad),
                'lean past the predicted tilt when locating with the tip (deg)', 0.0, 60.0)),
            max_tilt_rad=math.radians(number(
                'max_tilt_deg', math.degrees(defaults.max_tilt_rad),
                'largest tilt of the tool from vertical (deg)', 0.0, 80.0)),
            joint_timeout_s=number('joint_timeout', defaults.joint_timeout_s,
                                   'abort when no joint state came for this long (s)', 0.05,
                                   10.0))

    # -- state, read-only ----------------------------------------------------------------
    @property
    def inputs_heard(self) -> bool:
        """True once joint_states, tactile/imu/data and tactile/pressure each arrived."""
        return all(stamp is not None for stamp in self._last_input_ns.values())

    @property
    def arm_listening(self) -> bool:
        """True when something (the driver, the simulator) subscribes to the arm commands."""
        return self._trajectory_pub.get_subscription_count() > 0

    # -- inputs -------------------------------------------------------------------------
    def _on_joints(self, msg: JointState) -> None:
        index = {name: i for i, name in enumerate(msg.name)}
        if not all(name in index and index[name] < len(msg.position)
                   for name in ARM_JOINT_NAMES):
            return
        stamp = stamp_ns(msg.header.stamp)
        self._last_input_ns['joint_states'] = stamp
        if self._explorer is not None:
            self._explorer.joint_state(stamp, [msg.position[index[n]]
                                               for n in ARM_JOINT_NAMES])

    def _on_imu(self, msg: Imu) -> None:
        stamp = stamp_ns(msg.header.stamp)
        self._last_input_ns['imu'] = stamp
        a, q = msg.linear_acceleration, msg.orientation
        if self._explorer is not None:
            self._explorer.imu(stamp, (a.x, a.y, a.z), (q.w, q.x, q.y, q.z))

    def _on_pressure(self, msg: FluidPressure) -> None:
        stamp = stamp_ns(msg.header.stamp)
        self._last_input_ns['pressure'] = stamp
        if self._explorer is not None:
            self._explorer.pressure(stamp, msg.fluid_pressure)

    # -- the action ---------------------------------------------------------------------
    def _on_goal(self, goal: Probe.Goal) -> GoalResponse:
        if self._finished is not None:
            self.get_logger().warning('probe goal refused: a goal is already running')
            self._rejected_goals += 1
            return GoalResponse.REJECT
        if not self.arm_listening:
            self.get_logger().error(f'probe goal refused: nobody subscribes to '
                                    f'{topics.JOINT_TRAJECTORY} (start the arm driver or the '
                                    'simulator)')
            self._rejected_goals += 1
            return GoalResponse.REJECT
        self._finished = Future()  # busy from acceptance on: a second goal is refused
        return GoalResponse.ACCEPT  # (a goal of bad values is aborted with the reason)

    def _on_cancel(self, goal_handle) -> CancelResponse:
        if self._explorer is not None:
            self._explorer.cancel()
        return CancelResponse.ACCEPT

    async def _execute(self, goal_handle) -> Probe.Result:
        try:
            parameters = parameters_from_goal(goal_handle.request)
        except ParameterError as err:  # aborted, not refused: a client sees only a result
            self._finished, self._last_outcome = None, f'not probed: {err}'
            self._rejected_goals += 1
            self.get_logger().warning(f'probe goal aborted: {err}')
            goal_handle.abort()
            return Probe.Result(message=f'not probed: {err}')
        self._explorer = Explorer(parameters, self._config)
        self._feedback = None
        if goal_handle.is_cancel_requested:  # canceled before the explorer existed
            self._explorer.cancel()
        self._goal_handle = goal_handle
        self._started_ns = self.get_clock().now().nanoseconds
        self.get_logger().info(f'probing {parameters.probe_count} points from '
                               f'{list(parameters.start)} along {list(parameters.direction)}')
        finished = await self._finished
        self._explorer, self._goal_handle, self._finished = None, None, None
        result = Probe.Result(pathway=pathway_message(finished.pathway),
                              outcomes=[int(p.status) for p in finished.pathway.probes],
                              elapsed=duration_message(self.get_clock().now().nanoseconds
                                                - self._started_ns),
                              message=finished.message)
        self._last_outcome = f'{finished.outcome.value}: {finished.message}'.rstrip(': ')
        contacts = len(finished.pathway.contacts)
        seconds = result.elapsed.sec + result.elapsed.nanosec / 1e9
        self.get_logger().info(
            f'probe goal {finished.outcome.value}: {contacts} of {len(finished.pathway.probes)} '
            f'probes touched in {seconds:.1f} s; '
            + (f'pathway in {self._pathway_file}' if contacts else 'the last pathway stays')
            + (f' ({finished.message})' if finished.message else ''))
        if finished.outcome is Outcome.SUCCEEDED:
            goal_handle.succeed()
        elif finished.outcome is Outcome.CANCELED:
            goal_handle.canceled()
        else:
            self.get_logger().error(f'probe goal aborted: {finished.message}')
            goal_handle.abort()
        return result

    def _step(self) -> None:
        if self._explorer is None:
            return
        now = self.get_clock().now().nanoseconds
        if (self._feedback is not None and not self._finished.done()
                and now - self._feedback_ns >= FEEDBACK_PERIOD_S * 1e9):
            self._goal_handle.publish_feedback(self._feedback)  # alive within a long phase
            self._feedback_ns = now
        events = self._explorer.step(now)
        records = self._explorer.records
        for event in events:
            if isinstance(event, Command):
                self._trajectory_pub.publish(trajectory_message(event.path))
            elif isinstance(event, Stop):
                self._trajectory_pub.publish(stop_message())
            elif isinstance(event, Feedback):
                self._feedback = feedback_message(event)
                self._goal_handle.publish_feedback(self._feedback)
                self._feedback_ns = now
            elif isinstance(event, Recorded):
                self._broadcast(records, event.record.stamp_ns)
                self._log_probe(event.record)
            elif isinstance(event, Finished):
                self._broadcast(event.pathway.probes, event.pathway.stamp_ns)
                self._finished.set_result(self._explorer.finished)

    def _log_probe(self, record) -> None:
        """One INFO line per finished probe: its outcome and where."""
        x, y, z = record.position
        total = self._explorer.parameters.probe_count if self._explorer else '?'
        self.get_logger().info(f'probe {record.index + 1}/{total}: {record.status.name} at '
                               f'({x:.4f}, {y:.4f}, {z:.4f}) m'
                               + (f', {record.detail}' if record.detail else ''))

    def _broadcast(self, records, stamp: int) -> None:
        """Publish contacts, pathway and markers, and rewrite the pathway file.

        Only once the goal has a contact: a goal canceled or failing before its first one
        leaves the previous pathway in place (the sweep may still use it).
        """
        pathway = Pathway(self._explorer.parameters, tuple(records), int(stamp))
        if not pathway.contacts:
            return
        header = Header(frame_id=FRAME_ID, stamp=Time(nanoseconds=stamp).to_msg())
        contacts = PoseArray(header=header, poses=[
            Pose(position=Point(x=p.position[0], y=p.position[1], z=p.position[2]),
                 orientation=orientation_message(p.normal)) for p in pathway.contacts])
        self._contacts_pub.publish(contacts)
        self._pathway_pub.publish(pathway_message(pathway))
        self._markers_pub.publish(marker_message(pathway, header))
        try:
            self._pathway_file.parent.mkdir(parents=True, exist_ok=True)
            pathway.save(self._pathway_file)
        except OSError as err:
            self.get_logger().error(f'cannot write the pathway file {self._pathway_file}: {err}')

    # -- probe_on_start ------------------------------------------------------------------
    def _send_own_goal(self) -> None:
        if not self.inputs_heard:
            self.get_logger().info('probe_on_start: waiting for joint_states, '
                                   'tactile/imu/data and tactile/pressure',
                                   throttle_duration_sec=5.0)
            return
        if not self._client.server_is_ready() or not self.arm_listening:
            return
        self._start_timer.cancel()
        goal = goal_message(self._own_goal)
        self._client.send_goal_async(goal)
        self.get_logger().info('probe_on_start: goal sent')

    # -- diagnostics ---------------------------------------------------------------------
    def _publish_diagnostics(self) -> None:
        now = self.get_clock().now().nanoseconds
        ages = {name: (f'{(now - stamp) * 1e-9:.2f}' if stamp is not None else 'never')
                for name, stamp in self._last_input_ns.items()}
        explorer = self._explorer
        running = explorer is not None
        records = explorer.records if running else []
        dropped = explorer.history.dropped if running else 0
        phase = explorer.phase.name.lower() if running else 'idle'
        silent = [name for name, stamp in self._last_input_ns.items() if stamp is None]
        if self._last_outcome.startswith('aborted'):
            level, message = DiagnosticStatus.ERROR, self._last_outcome
        elif silent or self._last_outcome.startswith('not probed') and not running:
            # a client's goal of bad values: the node itself is fine
            level = DiagnosticStatus.WARN
            message = f'no {", ".join(silent)} yet' if silent else self._last_outcome
        else:
            level = DiagnosticStatus.OK
            message = f'probing: {phase}' if running else self._last_outcome
        values = {'phase': phase, 'probes_done': str(len(records)),
                  'contacts': str(sum(r.ok for r in records)),
                  'samples_dropped': str(dropped), 'rejected_goals': str(self._rejected_goals),
                  'pathway_file': str(self._pathway_file),
                  **{f'{name}_age_s': age for name, age in ages.items()}}
        self.publish_diagnostics(self._diagnostics_pub, level, 'probe', message,
                                 values)


def main(args: list[str] | None = None) -> None:
    """Run the node until shutdown."""
    spin(ProbeNode, args)

