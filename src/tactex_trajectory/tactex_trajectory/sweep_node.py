# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""ROS 2 node serving the `sweep` action: plan, execute, watch, record, retract.

A goal's pathway (or, when it has no contacts, the latest on probe/pathway) is planned
from the present joint_states; the trajectory goes to arm/joint_trajectory; the monitor
follows joint_states and tactile/pressure, publishes sweep/active and the feedback, and
aborts (lifting the edge off) on contact lost, over-force or a tracking error. A cancel
lifts the edge off before the goal ends. recording/metadata (label, trial, surface,
parameters) is published latched at the start of each goal; with `record: true` the node
records the tactile topics itself, one labelled recording per goal.

One thread runs everything: the goal's execute callback is a coroutine that waits on the
ticks of a steady-clock timer, so the inputs are handled between its steps and no lock is
needed (rclpy's multi-threaded executor fell behind the streams on two cores).

Longer than 500 lines: the goal's coroutine and the input callbacks share that one
thread's state, which a split into modules would hand across by reference; planning,
monitoring and recording themselves live in `planner`, `monitor` and the recorder.
"""

from __future__ import annotations

from collections import deque
from dataclasses import asdict, replace
import json
import math
from pathlib import Path
import time

from builtin_interfaces.msg import Duration, Time
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import Point
import numpy as np
from rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor
from rclpy.action import ActionServer, CancelResponse
from sensor_msgs.msg import FluidPressure, JointState
from std_msgs.msg import Bool, ColorRGBA, String
from std_srvs.srv import Trigger
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint
from visualization_msgs.msg import Marker, MarkerArray

from tactex_classify.recording.recorder import RECORDED_TOPICS, SplitRecorder
from tactex_common import frames, topics
from tactex_common.ros import (
    COMMAND,
    LATCHED,
    message_class,
    RECORDING,
    SENSOR_DATA,
    spin,
    TactexNode,
    time_message,
)
from tactex_common.serving import goal_pathway, OneGoal
from tactex_common.stamps import stamp_ns
from tactex_common.ticks import Ticks
from tactex_description.geometry import ARM_JOINT_NAMES
from tactex_description.movements import NAME as MOVEMENT_NAME
from tactex_msgs.action import Sweep
from tactex_msgs.msg import Contact, Pathway
from tactex_probe.messages import contact_arrays
from tactex_trajectory.errors import TrajectoryError
from tactex_trajectory.monitor import MonitorSettings, SweepMonitor, SweepResult
from tactex_trajectory.path import PathSettings
from tactex_trajectory.planner import plan_sweep, retract, SweepPlan, SweepSettings
from tactex_trajectory.poses import ARM, PoseSettings
from tactex_trajectory.timing import TimedJoints

# Period of the watch loop and of the feedback (s, node clock).
WATCH_PERIOD_S = 0.01
FEEDBACK_PERIOD_S = 0.1
# The goal ends this long after the trajectory (s), so the last samples arrive.
TAIL_S = 0.3
# Abort when joint_states stop for this long (s, wall clock: a stopped driver stops a
# simulated clock too), or finite pressures while the arm's clock runs (s, node clock).
JOINT_STATE_TIMEOUT_S = 5.0
PRESSURE_TIMEOUT_S = 1.0
# Abort when the arm has not started to follow the trajectory after this long (s).
START_TIMEOUT_S = 10.0
# How long a goal waits for the driver to subscribe to the trajectory topic (s, wall).
SUBSCRIBER_WAIT_S = 5.0
# A retract is waited for at most this long (s, wall clock), and is done when the edge
# has covered this fraction of its lift.
RETRACT_WAIT_S = 60.0
LIFTED_FRACTION = 0.8
# arm/stop and the arm coming to rest are waited for at most this long (s, wall clock).
SERVICE_WAIT_S = 5.0
# The arm is at rest when no joint moves more than this over this much time (rad, s).
REST_TOLERANCE_RAD = 2e-4
REST_INTERVAL_S = 0.1


def _positive(description: str, *, high: float = 1e9) -> ParameterDescriptor:
    return ParameterDescriptor(description=description, read_only=True,
                               floating_point_range=[FloatingPointRange(from_value=1e-9,
                                                                        to_value=high)])


class SweepNode(TactexNode):
    """The sweep action server."""

    def __init__(self, **kwargs) -> None:
        super().__init__('sweep_node', **kwargs)
        declare = self.declare_parameter
        defaults = SweepSettings()
        self._settings = SweepSettings(
            approach_height_m=declare('approach_height', defaults.approach_height_m, _positive(
                'height above the surface where the descent starts and the lift ends (m)',
                high=0.1)).value,
            descent_speed_m_s=declare('descent_speed', defaults.descent_speed_m_s, _positive(
                'peak speed of the descent and the lift (m/s)', high=0.1)).value,
            ramp_acceleration_m_s2=declare(
                'ramp_acceleration', defaults.ramp_acceleration_m_s2, _positive(
                    'largest edge acceleration of the speed ramps (m/s^2)', high=1.0)).value,
            settle_s=declare('settle_time', 0.3, _positive(
                'dwell pressed in before sliding (s)', high=10.0)).value,
            path=PathSettings(
                spacing_m=declare('sample_spacing', 0.002, _positive(
                    'arc length between path samples (m)', high=0.05)).value,
                merge_within_m=declare('merge_within', 0.001, _positive(
                    'contacts closer than this are merged (m)', high=0.01)).value,
                position_noise_m=declare('position_noise', 0.001, _positive(
                    "standard deviation of the probe's contact positions (m)",
                    high=0.01)).value,
                normal_noise_rad=declare('normal_noise', 0.035, _positive(
                    "standard deviation of the probe's normals (rad)", high=0.5)).value,
                position_tolerance_m=declare('position_tolerance', 0.004, _positive(
                    "a contact this far off its neighbours' curve is dropped (m)",
                    high=0.05)).value,
                normal_tolerance_rad=declare('normal_tolerance', 0.35, _positive(
                    "a normal this far off its neighbours' is dropped (rad)",
                    high=3.0)).value),
            pose=PoseSettings(max_residual_rad=declare('max_residual', 0.2, _positive(
                'largest angle between an asked pose and the one the arm can take (rad)',
                high=1.0)).value))
        self._monitor_settings = MonitorSettings(
            contact_threshold_pa=declare('contact_threshold', 150.0, _positive(
                'pressure rise over the baseline that means contact (Pa)')).value,
            pressure_pa_per_m=declare('pressure_per_compression', 1.5e6, _positive(
                'pressure rise per metre of body compression (Pa/m)')).value,
            force_limit_n=declare('force_limit', 3.0, _positive(
                'abort above this force proxy (N)', high=50.0)).value,
            contact_loss_tolerance_s=declare('contact_loss_tolerance', 0.5, _positive(
                'abort when contact is lost this long while sliding (s)', high=10.0)).value,
            tracking_tolerance_m=declare('tracking_tolerance', 0.01, _positive(
                'abort when the edge is this far from where it is commanded (m)',
                high=0.1)).value)
        self._recording_root = Path(declare('recording_root', 'recordings', ParameterDescriptor(
            description='directory under which `record: true` goals write their recording',
            read_only=True)).value).expanduser()
        self._surface = declare('surface', 'uneven', ParameterDescriptor(
            description='surface written to recording/metadata', read_only=True)).value

        self.create_subscription(JointState, topics.JOINT_STATES, self._on_joints, COMMAND)
        self.create_subscription(FluidPressure, topics.PRESSURE, self._on_pressure,
                                 SENSOR_DATA)
        self.create_subscription(Pathway, topics.PROBE_PATHWAY, self._on_pathway, LATCHED)
        self._trajectory_pub = self.create_publisher(JointTrajectory, topics.JOINT_TRAJECTORY,
                                                     COMMAND)
        self._active_pub = self.create_publisher(Bool, topics.SWEEP_ACTIVE, COMMAND)
        self._metadata_pub = self.create_publisher(String, topics.RECORDING_METADATA, LATCHED)
        self._markers_pub = self.create_publisher(MarkerArray, topics.SWEEP_MARKERS, LATCHED)
        self._diagnostics_pub = self.create_publisher(DiagnosticArray, topics.DIAGNOSTICS,
                                                      COMMAND)
        self._joints: tuple[float, np.ndarray] | None = None
        self._joints_wall_s = -math.inf
        self._pressure_s = -math.inf
        self._active: bool | None = None
        self._joint_queue: deque = deque(maxlen=10_000)
        self._pressure_queue: deque = deque(maxlen=10_000)
        self._pathway: Pathway | None = None
        self._recorder: SplitRecorder | None = None
        self._one_goal = OneGoal(self, 'sweep')
        self._state = 'idle'
        self._last_outcome = ''
        self._last_planning_s = math.nan
        self._recording_subscriptions: list = []
        self._stop_client = self.create_client(Trigger, 'arm/stop')
        self._server = ActionServer(self, Sweep, topics.SWEEP_ACTION,
                                    execute_callback=self._execute,
                                    goal_callback=self._one_goal,
                                    cancel_callback=lambda _request: CancelResponse.ACCEPT)
        # The running goal's waits end on these ticks (wall clock, only while a goal runs).
        self._ticks = Ticks(self, WATCH_PERIOD_S)
        self.create_timer(1.0, self._publish_diagnostics)
        self.get_logger().info('sweep action server ready')

    # -- inputs ---------------------------------------------------------------------------
    def _stamp_s(self, header) -> float:
        stamp = stamp_ns(header.stamp)
        return stamp * 1e-9 if stamp else self.get_clock().now().nanoseconds * 1e-9

    def _on_joints(self, msg: JointState) -> None:
        try:
            joints = np.array([msg.position[list(msg.name).index(n)] for n in ARM_JOINT_NAMES])
        except (ValueError, IndexError):
            return
        sample = (self._stamp_s(msg.header), joints)
        self._joints = sample
        self._joints_wall_s = time.monotonic()
        self._joint_queue.append(sample)

    def _on_pressure(self, msg: FluidPressure) -> None:
        self._pressure_queue.append((self._stamp_s(msg.header), float(msg.fluid_pressure)))
        if math.isfinite(msg.fluid_pressure):
            self._pressure_s = self._now_s()

    def _on_pathway(self, msg: Pathway) -> None:
        self._pathway = msg

    def _writer_for(self, topic: str):
        def write(data: bytes) -> None:
            if self._recorder is not None:
                self._recorder.write(topic, self.get_clock().now().nanoseconds, data)
        return write

    # -- the action -----------------------------------------------------------------------
    async def _execute(self, goal_handle) -> Sweep.Result:
        result = Sweep.Result()
        self._ticks.start()
        try:
            try:
                outcome, message = await self._run(goal_handle, result)
            finally:
                # Everything ends before the goal does: its result is kept only so long.
                self._publish_active(False)
                self._stop_recording()
                self._state = 'idle'
            return self._finish(goal_handle, result, message, outcome)
        finally:
            self._ticks.stop()
            self._one_goal.done()

    async def _run(self, goal_handle, result: Sweep.Result) -> tuple[str, str]:
        """Plan and execute a goal, filling `result`; return (outcome, message)."""
        goal = goal_handle.request
        # A goal sent as the system comes up waits for the arm's first joint state.
        deadline = time.monotonic() + JOINT_STATE_TIMEOUT_S
        while self._joints is None and time.monotonic() < deadline:
            await self._ticks.pause()
        try:
            plan = self._plan(goal)
        except (TrajectoryError, ValueError) as err:
            return 'abort', f'not planned: {err}'
        metadata = self._metadata(goal, plan)
        self._metadata_pub.publish(String(data=json.dumps(metadata, sort_keys=True)))
        self._publish_markers(plan)
        if goal.record:
            try:
                result.recording_path = str(self._start_recording(goal, metadata))
            except (OSError, ValueError) as err:
                return 'abort', f'cannot record: {err}'
        if not await self._wait_for_subscriber():
            return 'abort', (f'nothing subscribes to {topics.JOINT_TRAJECTORY}: is the arm '
                             'driver (or the simulator) running?')
        monitor = SweepMonitor(plan, self._monitor_settings)
        self._joint_queue.clear()
        self._pressure_queue.clear()
        start_s = self._now_s()
        sent_wall_s = time.monotonic()
        self._send(plan.trajectory)
        self._state = 'sweeping'
        next_feedback = 0.0
        while True:
            await self._ticks.pause()
            elapsed = self._now_s() - start_s
            status = self._feed(monitor, start_s, elapsed)
            self._publish_active(status.active)
            if elapsed >= next_feedback:
                next_feedback = elapsed + FEEDBACK_PERIOD_S
                goal_handle.publish_feedback(Sweep.Feedback(
                    progress=float(min(max(status.progress, 0.0), 1.0)),
                    in_contact=status.in_contact, tracking_error=status.tracking_error_m,
                    sliding_speed=status.sliding_speed_m_s))
            if goal_handle.is_cancel_requested:
                failed = await self._retract(plan)
                self._fill(result, monitor.result(), start_s)
                return 'cancel', (f'canceled: {failed}' if failed else
                                  'canceled: the edge was lifted off the surface')
            reason = status.abort_reason
            joints_silent_s = time.monotonic() - max(self._joints_wall_s, sent_wall_s)
            pressure_silent_s = self._now_s() - max(self._pressure_s, start_s)
            if joints_silent_s > JOINT_STATE_TIMEOUT_S:
                reason = (f'no {topics.JOINT_STATES} for {joints_silent_s:.1f} s: the arm '
                          'driver (or the simulator) stopped')
            elif pressure_silent_s > PRESSURE_TIMEOUT_S:
                reason = (f'no finite {topics.PRESSURE} for {pressure_silent_s:.1f} s while '
                          'the arm runs: contact cannot be watched; check the tactile module')
            if not monitor.started and elapsed > START_TIMEOUT_S:
                reason = (f'the arm did not start moving within {START_TIMEOUT_S:g} s: did '
                          f'the driver reject the trajectory? (see its log and diagnostics)')
            if reason:
                failed = await self._retract(plan)
                self._fill(result, monitor.result(), start_s)
                return 'abort', (f'aborted: {reason}; '
                                 f'{failed or "the edge was lifted off"}')
            if monitor.trajectory_time(elapsed) > plan.trajectory.duration_s + TAIL_S:
                break
        self._fill(result, monitor.result(), start_s)
        return 'succeed', ''

    def _plan(self, goal) -> SweepPlan:
        if goal.movement and not MOVEMENT_NAME.match(goal.movement):
            raise ValueError(f'movement must start with a letter and hold only letters, '
                             f'digits, _ and - (at most 64), got {goal.movement!r}')
        for name in ('sliding_speed', 'edge_offset_angle', 'press_depth'):
            if not math.isfinite(getattr(goal, name)):
                raise ValueError(f'{name} must be finite, got {getattr(goal, name)!r}')
        if goal.sliding_speed <= 0.0:
            raise ValueError(f'sliding_speed must be > 0 m/s (the original work used 0.015), '
                             f'got {goal.sliding_speed!r}')
        pathway = goal_pathway(goal.pathway, self._pathway)
        joints = self._joints
        if joints is None:
            raise ValueError(f'no {topics.JOINT_STATES} received yet: is the arm driver (or '
                             'the simulator) running?')
        points, normals = contact_arrays(pathway)
        ok = np.array([c.status == Contact.STATUS_OK for c in pathway.contacts])
        settings = replace(self._settings, sliding_speed_m_s=float(goal.sliding_speed),
                           pose=replace(self._settings.pose,
                                        edge_offset_rad=float(goal.edge_offset_angle),
                                        press_depth_m=float(goal.press_depth)))
        began = time.perf_counter()
        plan = plan_sweep(points, normals, ok, joints[1], settings)
        self._last_planning_s = time.perf_counter() - began
        self.get_logger().info(
            f'planned in {self._last_planning_s * 1e3:.0f} ms: {plan.path.report()}; '
            f'{plan.trajectory.duration_s:.1f} s, contact '
            f'{plan.contact_start_s:.1f}..{plan.contact_end_s:.1f} s, largest pose residual '
            f'{math.degrees(float(np.max(plan.poses.residual_rad))):.1f} deg')
        return plan

    def _metadata(self, goal, plan: SweepPlan) -> dict:
        settings = plan.settings
        return {'label': goal.label, 'trial': int(goal.trial), 'surface': self._surface,
                **({'movement': goal.movement} if goal.movement else {}),
                'source': 'tactex_trajectory', 'sweep': {
                    'sliding_speed_m_s': settings.sliding_speed_m_s,
                    'edge_offset_rad': settings.pose.edge_offset_rad,
                    'press_depth_m': settings.pose.press_depth_m,
                    'path_length_m': plan.path.length_m,
                    'contacts_used': len(plan.path.kept),
                    'contacts_dropped': [asdict(d) for d in plan.path.dropped],
                    'contact_start_s': plan.contact_start_s,
                    'contact_end_s': plan.contact_end_s}}

    def _feed(self, monitor: SweepMonitor, start_s: float, elapsed: float):
        joints = list(self._joint_queue)
        pressures = list(self._pressure_queue)
        self._joint_queue.clear()
        self._pressure_queue.clear()
        samples = sorted([(t, 0, q) for t, q in joints] + [(t, 1, p) for t, p in pressures],
                         key=lambda item: (item[0], item[1]))
        for stamp, kind, value in samples:
            if kind == 0:
                monitor.update_joints(stamp - start_s, value)
            else:
                monitor.update_pressure(stamp - start_s, value)
        return monitor.status(elapsed)

    async def _wait_for_subscriber(self) -> bool:
        deadline = time.monotonic() + SUBSCRIBER_WAIT_S
        while self._trajectory_pub.get_subscription_count() == 0:
            if time.monotonic() > deadline:
                return False
            await self._ticks.pause()
        return True

    async def _retract(self, plan: SweepPlan) -> str:
        """Stop the arm, then lift the edge off from where it stopped; '' or what failed.

        Stopping first (arm/stop holds the commanded pose) makes the lift start where the
        arm really is, however late the driver hears of it.
        """
        self._state = 'retracting'
        deadline = time.monotonic() + SERVICE_WAIT_S
        while not self._stop_client.service_is_ready() and time.monotonic() < deadline:
            await self._ticks.pause()
        if self._stop_client.service_is_ready():
            future = self._stop_client.call_async(Trigger.Request())
            while not future.done() and time.monotonic() < deadline:
                await self._ticks.pause()
        joints = await self._joints_at_rest()
        if joints is None:
            return f'no {topics.JOINT_STATES}: the edge could not be lifted'
        lift = retract(plan, joints)
        if len(lift.times_s) == 1:
            return ''
        self._send(lift)
        start, _ = ARM.tool_pose(joints)
        goal, _ = ARM.tool_pose(lift.positions[-1])
        deadline = time.monotonic() + RETRACT_WAIT_S
        while time.monotonic() < deadline:
            await self._ticks.pause()
            edge, _ = ARM.tool_pose(self._joints[1])
            if np.linalg.norm(edge - start) >= LIFTED_FRACTION * np.linalg.norm(goal - start):
                return ''
        return 'the lift did not complete in time: check the arm'

    async def _joints_at_rest(self) -> np.ndarray | None:
        """The newest joints once they stop changing (or after a while, the newest)."""
        deadline = time.monotonic() + SERVICE_WAIT_S
        previous = None
        while time.monotonic() < deadline:
            latest = self._joints
            if latest is not None and previous is not None and \
                    latest[0] - previous[0] >= REST_INTERVAL_S:
                if np.max(np.abs(latest[1] - previous[1])) < REST_TOLERANCE_RAD:
                    return latest[1]
                previous = latest
            elif previous is None:
                previous = latest
            await self._ticks.pause()
        return None if self._joints is None else self._joints[1]

    def _finish(self, goal_handle, result: Sweep.Result, message: str, outcome: str):
        result.message = message
        self._last_outcome = message or 'succeeded'
        if outcome == 'succeed':
            goal_handle.succeed()
            self.get_logger().info(f'sweep done: contact {100 * result.contact_fraction:.1f} %,'
                                   f' speed {result.speed_mean * 1e3:.2f} mm/s, press depth '
                                   f'error {result.press_depth_error * 1e3:.2f} mm')
        elif outcome == 'cancel':
            goal_handle.canceled()
            self.get_logger().info(message)
        else:
            goal_handle.abort()
            self.get_logger().error(message)
        return result

    @staticmethod
    def _fill(result: Sweep.Result, numbers: SweepResult, start_s: float) -> None:
        result.contact_fraction = numbers.contact_fraction
        result.speed_mean = numbers.speed_mean_m_s
        result.speed_std = numbers.speed_std_m_s
        result.press_depth_error = numbers.press_depth_error_m
        result.contact_starts = [_time(start_s + a) for a, _ in numbers.active_spans_s]
        result.contact_ends = [_time(start_s + b) for _, b in numbers.active_spans_s]

    # -- outputs --------------------------------------------------------------------------
    def _now_s(self) -> float:
        return self.get_clock().now().nanoseconds * 1e-9

    def _send(self, timed: TimedJoints) -> None:
        msg = JointTrajectory(joint_names=list(timed.joint_names))
        for t, q, v, a in zip(timed.times_s, timed.positions, timed.velocities,
                              timed.accelerations, strict=True):
            seconds = int(t)
            msg.points.append(JointTrajectoryPoint(
                positions=q.tolist(), velocities=v.tolist(), accelerations=a.tolist(),
                time_from_start=Duration(sec=seconds, nanosec=int(round((t - seconds) * 1e9)))))
        self._trajectory_pub.publish(msg)

    def _publish_active(self, active: bool) -> None:
        if self._active is not active:
            self._active = active
            self._active_pub.publish(Bool(data=active))

    def _start_recording(self, goal, metadata: dict) -> Path:
        stamp = time.strftime('%Y%m%d_%H%M%S')
        label = ''.join(c if c.isalnum() or c in '-_' else '_' for c in goal.label) or 'sweep'
        root = self._recording_root / f'{label}_{goal.trial:04d}_{stamp}'
        recorder = SplitRecorder(root, metadata).__enter__()
        for topic, type_name, _qos in RECORDED_TOPICS:
            recorder.add_topic(topic, type_name)
        self._recorder = recorder
        # Made at the first recording and kept; between recordings the writers drop what
        # arrives.
        if not self._recording_subscriptions:
            self._recording_subscriptions = [
                self.create_subscription(message_class(type_name), topic,
                                         self._writer_for(topic), RECORDING[qos], raw=True)
                for topic, type_name, qos in RECORDED_TOPICS
                if topic != topics.RECORDING_METADATA]
        self.get_logger().info(f'recording to {root}')
        return root

    def _stop_recording(self) -> None:
        recorder, self._recorder = self._recorder, None
        if recorder is not None:
            recorder.close()

    def _publish_markers(self, plan: SweepPlan) -> None:
        stamp = self.get_clock().now().to_msg()
        path = Marker(type=Marker.LINE_STRIP, ns='sweep_path', id=0, action=Marker.ADD,
                      color=ColorRGBA(r=0.1, g=0.8, b=0.2, a=1.0))
        path.header.frame_id, path.header.stamp = frames.BASE, stamp
        path.scale.x = 0.001
        path.pose.orientation.w = 1.0
        path.points = [Point(x=float(p[0]), y=float(p[1]), z=float(p[2]))
                       for p in plan.path.points]
        normals = Marker(type=Marker.LINE_LIST, ns='sweep_normals', id=1, action=Marker.ADD,
                         color=ColorRGBA(r=0.6, g=0.2, b=0.9, a=1.0))
        normals.header.frame_id, normals.header.stamp = frames.BASE, stamp
        normals.scale.x = 0.0005
        normals.pose.orientation.w = 1.0
        for point, normal in zip(plan.path.points[::5], plan.path.normals[::5], strict=True):
            tip = point + 0.01 * normal
            normals.points += [Point(x=float(point[0]), y=float(point[1]), z=float(point[2])),
                               Point(x=float(tip[0]), y=float(tip[1]), z=float(tip[2]))]
        self._markers_pub.publish(MarkerArray(markers=[path, normals]))

    def _publish_diagnostics(self) -> None:
        level = DiagnosticStatus.OK
        if self._last_outcome.startswith(('aborted', 'not planned', 'cannot')):
            level = DiagnosticStatus.WARN
        values = {'state': self._state, 'last_outcome': self._last_outcome or 'none',
                  'last_planning_ms': f'{self._last_planning_s * 1e3:.1f}'}
        self.publish_diagnostics(self._diagnostics_pub, level, 'sweep',
                                 f'{self._state}; last: {self._last_outcome or "none"}', values)

    def destroy_node(self) -> None:
        """Close a recording that is still open."""
        self._stop_recording()
        super().destroy_node()


def _time(seconds: float) -> Time:
    """A stamp of `seconds`, to the nearest nanosecond (5.9999999996 s is 6 s)."""
    return time_message(round(seconds * 1e9))


def main(args: list[str] | None = None) -> None:
    """Serve sweeps until shutdown."""
    spin(SweepNode, args)
