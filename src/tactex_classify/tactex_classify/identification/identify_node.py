# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""ROS 2 node serving the `identify` action: choose movements, sweep, update the belief.

It loads one identification bundle (`tactex train DATA --movements YAML --out RUN`:
RUN/bundle) for the movement file it is given, and refuses a bundle trained for other
movements or textures. Each goal runs the `identification` core's loop: the policy
chooses a movement, the node sends the `sweep` action the part of the pathway that
movement slides along (`pathway_part`: it never leaves the pathway) at the movement's
speed, press depth and tilt, cuts the tactile stream's windows while sweep/active is
true (`online.live.LiveWindows`), gives them to the movement's model, calibrates the
sweep's vector with the movement's temperature and updates the belief; feedback follows
each movement. It imports no trajectory code: the arm's limits are the sweep node's.

Everything runs on one thread: the goal is a coroutine that waits on steady-clock
ticks (`tactex_common.ticks`), so the sample callbacks run between its steps. A cancel
cancels the running sweep (the sweep node lifts the edge off) before the goal ends; every
other wait of a goal (for the sweep server, its answer, the last windows) ends at the
next tick after a cancel request, and the goal ends canceled. A missing or vanished sweep
server, or a sweep that gives no window, aborts the goal with the reason.
"""

from __future__ import annotations

from pathlib import Path
import sys
import time

from action_msgs.msg import GoalStatus
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
import numpy as np
from rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor
from rclpy.action import ActionServer, CancelResponse
from std_msgs.msg import Bool

from tactex_classify.data.bags import sample_values
from tactex_classify.errors import ClassifyError
from tactex_classify.identification.bundle import load_bundle
from tactex_classify.identification.calibration import calibrated
from tactex_classify.identification.movement_evidence import sweep_vector
from tactex_classify.identification.movement_goals import movement_goal, probed_arrays
from tactex_classify.identification.pathway_part import holds, pathway_length
from tactex_classify.identification.selection import Budget, DECIDED, Identification
from tactex_classify.online.evidence import union_seconds
from tactex_classify.online.live import LiveSettings, LiveWindows, Window
from tactex_classify.online.tactile_topics import ROLE_TOPICS, SENSOR_QUEUE
from tactex_common import topics
from tactex_common.goals import GoalSender
from tactex_common.ros import COMMAND, LATCHED, spin, TactexNode
from tactex_common.serving import goal_pathway, OneGoal
from tactex_common.stamps import stamp_ns
from tactex_common.ticks import Ticks
from tactex_description.movements import load_movements, MovementError
from tactex_description.speed_ramp import RAMP_ACCELERATION_M_S2
from tactex_msgs.action import Identify, Sweep
from tactex_msgs.msg import Pathway

TICK_S = 0.05
ANSWER_S = 5.0  # a Sweep goal unanswered this long is sent again (tactex_common.goals)
REFUSED_RETRY_S = 1.0  # a refused Sweep goal is sent again after this long
CANCEL_S = 30.0  # a canceled sweep may take this long to lift the edge off and end
SERVER_LOST_S = 3.0  # the sweep server unseen this long during a sweep: it is gone
RATE_TOLERANCE = 0.05  # relative difference of the stream's rate from the bundle's accepted


class StartError(Exception):
    """The node cannot start: a refused movement file or bundle."""


def _range(description: str, low: float, high: float) -> ParameterDescriptor:
    return ParameterDescriptor(description=description, read_only=True,
                               floating_point_range=[FloatingPointRange(from_value=low,
                                                                        to_value=high)])


def _cancel_if_accepted(answer) -> None:
    """Cancel the Sweep goal of `answer` (a done future of its handle) if it was accepted."""
    if answer.result().accepted:
        answer.result().cancel_goal_async()


def contact_seconds(result) -> float:
    """Seconds in contact of a Sweep result: the union of its contact spans."""
    return union_seconds([(stamp_ns(start), stamp_ns(end)) for start, end in
                          zip(result.contact_starts, result.contact_ends, strict=False)])


class IdentifyNode(TactexNode):
    """The identify action server."""

    def __init__(self, **kwargs) -> None:
        super().__init__('identify_node', **kwargs)
        p = {
            'bundle': self.declare_parameter('bundle', '', ParameterDescriptor(
                description='identification bundle (RUN/bundle of tactex train --movements)',
                read_only=True)).value,
            'movements': self.declare_parameter('movements', '', ParameterDescriptor(
                description='movement file the bundle was trained for (config/movements.yaml)',
                read_only=True)).value,
            'server_timeout_s': self.declare_parameter('server_timeout_s', 10.0, _range(
                'wait this long for the sweep action server and its answer (s)', 0.1,
                3600.0)).value,
            'sweep_timeout_s': self.declare_parameter('sweep_timeout_s', 300.0, _range(
                'abort a sweep that has not ended after this long (s)', 1.0, 36000.0)).value,
            'ramp_acceleration': self.declare_parameter(
                'ramp_acceleration', RAMP_ACCELERATION_M_S2, _range(
                    "the sweep node's ramp_acceleration (m/s^2): each movement's part of the "
                    'pathway adds its two speed ramps to its contact', 1e-9, 1.0)).value,
            'settle_s': self.declare_parameter('settle_s', 2.0, _range(
                'wait this long after a sweep for its last windows (s)', 0.0, 60.0)).value,
        }
        try:
            for name in ('bundle', 'movements'):
                if not p[name]:
                    raise ValueError(f'parameter {name} is empty: give '
                                     f'{self.describe_parameter(name).description}')
            self._movements = load_movements(Path(p['movements']).expanduser())
            self._bundle = load_bundle(Path(p['bundle']).expanduser(), self._movements)
            self._windows = LiveWindows(self._bundle.stream, LiveSettings(contact='sweep_active'))
        except (MovementError, ClassifyError, OSError, ValueError) as err:
            message = f'cannot start: {err}'
            self.get_logger().fatal(message)
            raise StartError(message) from None
        self._server_timeout_s = p['server_timeout_s']
        self._ramp_acceleration = p['ramp_acceleration']
        self._sweep_timeout_s, self._settle_s = p['sweep_timeout_s'], p['settle_s']
        self._pathway: Pathway | None = None
        self._collected: list[Window] | None = None  # the running sweep's windows
        self._one_goal = OneGoal(self, 'identify')
        self._state = 'idle'
        self._last_outcome = ''
        self._last_aborted = False
        self._goals = {'succeeded': 0, 'aborted': 0, 'canceled': 0}
        self._sweep = GoalSender(self, Sweep, topics.SWEEP_ACTION)
        for role in self._windows.needed_roles:
            message_type, topic = ROLE_TOPICS[role]
            self.create_subscription(message_type, topic, self._on_sample(role),
                                     SENSOR_QUEUE)
        self.create_subscription(Bool, topics.SWEEP_ACTIVE, self._on_active, COMMAND)
        self.create_subscription(Pathway, topics.PROBE_PATHWAY, self._on_pathway, LATCHED)
        self._diagnostics_pub = self.create_publisher(DiagnosticArray, topics.DIAGNOSTICS,
                                                      COMMAND)
        self._ticks = Ticks(self, TICK_S)
        self._server = ActionServer(self, Identify, topics.IDENTIFY_ACTION,
                                    execute_callback=self._execute,
                                    goal_callback=self._one_goal,
                                    cancel_callback=lambda _request: CancelResponse.ACCEPT)
        self.create_timer(TICK_S, self._poll)
        self.create_timer(1.0, self._publish_diagnostics)
        self.get_logger().info(
            f'identify action server ready: {len(self._bundle.classes)} textures, movements '
            f'{", ".join(self._movements.names)}')

    # -- inputs ---------------------------------------------------------------------------
    def _on_sample(self, role: str):
        def on_sample(message) -> None:
            self._windows.add(role, stamp_ns(message.header.stamp),
                              sample_values(role, message), time.monotonic_ns())
        return on_sample

    def _on_active(self, message: Bool) -> None:
        self._windows.set_active(message.data, self.get_clock().now().nanoseconds)

    def _on_pathway(self, message: Pathway) -> None:
        self._pathway = message

    def _poll(self) -> None:
        """Cut what the stream completes; keep the windows while a sweep is collected."""
        for event in self._windows.poll():
            if isinstance(event, Window) and self._collected is not None:
                self._collected.append(event)
        self._windows.prune_active()

    # -- the action -----------------------------------------------------------------------
    async def _execute(self, goal_handle) -> Identify.Result:
        started = time.monotonic()
        result = Identify.Result(class_names=list(self._bundle.classes))
        self._ticks.start()
        try:
            outcome, message = await self._identify(goal_handle, result)
        finally:
            self._ticks.stop()
            self._collected = None
            self._one_goal.done()
            self._state = 'idle'
        result.wall_seconds = time.monotonic() - started
        result.message = message
        self._last_outcome = message or f'{result.texture or "undecided"} after ' \
            f'{len(result.movements)} movement(s)'
        if outcome == 'succeed':
            goal_handle.succeed()
        elif outcome == 'cancel':
            goal_handle.canceled()
        else:
            goal_handle.abort()
        self._last_aborted = outcome == 'abort'
        self._goals[{'succeed': 'succeeded', 'cancel': 'canceled'}.get(outcome, 'aborted')] += 1
        self.get_logger().info(f'identify goal {outcome}: {self._last_outcome}')
        return result

    def _pathway_points(self, goal) -> tuple[Pathway, np.ndarray, np.ndarray]:
        """(pathway, points, normals) of the goal's pathway, or the latest probed one.

        Raises:
            ValueError: no pathway, or one in another frame.
        """
        pathway = goal_pathway(goal.pathway, self._pathway)
        return (pathway, *probed_arrays(pathway))

    async def _identify(self, goal_handle, result: Identify.Result) -> tuple[str, str]:
        """Run the loop of one goal, filling `result`; (outcome, message)."""
        goal = goal_handle.request
        bundle, movements = self._bundle, self._movements.movements
        try:
            budget = Budget(float(goal.threshold), int(goal.budget_movements) or None,
                            float(goal.budget_seconds) or None)
            identification = Identification(bundle.table, goal.policy, budget,
                                            seed=int(goal.seed))
            pathway, points, normals = self._pathway_points(goal)
        except ValueError as err:
            return 'abort', f'refused: {err}'
        shortest_s = float(np.min(bundle.table.seconds))
        if budget.seconds is not None and budget.seconds < shortest_s:  # as the report refuses
            return 'abort', (f'refused: budget_seconds {budget.seconds:g} is shorter than every '
                             f'movement: the shortest contact lasts {shortest_s:.2f} s; give at '
                             'least that')
        ramps = self._ramp_acceleration
        available = np.array([holds(points, movement, ramps) for movement in movements])
        if not available.any():
            shortest = min(movement.part_length_m(ramps) for movement in movements)
            return 'abort', (f'refused: the pathway is {1e3 * pathway_length(points):.0f} mm '
                             f'long; the shortest movement needs {1e3 * shortest:.0f} mm (its '
                             'contact and speed ramps): probe a longer pathway')
        while (index := identification.next_movement(available)) is not None:
            if goal_handle.is_cancel_requested:  # asked between two sweeps
                return 'cancel', 'canceled between movements'
            movement = movements[index]
            self._state = f'sweeping {movement.name} ({len(result.movements) + 1})'
            outcome, message, sweep_result, windows = await self._swept(
                goal_handle, movement_goal(pathway, movement, ramps))
            if sweep_result is not None:
                result.contact_seconds += contact_seconds(sweep_result)
            if outcome != 'succeed':
                return outcome, f'{movement.name}: {message}'
            if not windows:
                return 'abort', (f'{movement.name}: the sweep gave no window of '
                                 f'{bundle.stream.window} samples in contact (is the sensor '
                                 "streaming? see this node's diagnostics)")
            refusal = self._rate_refusal()
            if refusal:
                return 'abort', f'{movement.name}: {refusal}'
            try:
                window_proba = bundle.estimators[index].predict_proba(
                    np.stack([window.values for window in windows]))
                identification.observe(index, calibrated(sweep_vector(window_proba),
                                                         bundle.temperatures[index]))
            except (ValueError, RuntimeError) as err:  # the model or its answer refused
                return 'abort', f'{movement.name}: its windows could not be classified: {err}'
            result.movements.append(movement.name)
            result.windows.append(len(windows))
            result.probabilities = identification.posterior.tolist()
            goal_handle.publish_feedback(Identify.Feedback(
                movement=movement.name, movements_run=len(result.movements),
                windows=len(windows), class_names=list(bundle.classes),
                probabilities=result.probabilities, contact_seconds=result.contact_seconds))
        result.probabilities = identification.posterior.tolist()
        result.stop_reason = identification.stop_reason(available)
        if result.stop_reason == DECIDED:
            result.texture = bundle.classes[identification.leader]
        return 'succeed', ''

    def _rate_refusal(self) -> str:
        """Why the stream's rate does not fit the bundle's ('' when it does or is unknown)."""
        measured = self._windows.stream_rate_hz()
        lines = [] if measured is None else self._bundle.stream.mismatches(
            sampling_rate_hz=measured, rate_tolerance=RATE_TOLERANCE)
        return (f"{lines[0]}: set the sensor to the bundle's rate or train a bundle at this "
                'one') if lines else ''

    async def _swept(self, goal_handle, sweep_goal: Sweep.Goal):
        """Run one sweep; (outcome, message, Sweep result or None, its windows)."""
        handle, refusal = await self._accepted(goal_handle, sweep_goal)
        if handle is None:
            if goal_handle.is_cancel_requested:
                return 'cancel', 'canceled before the sweep started', None, []
            return 'abort', refusal, None, []
        self._collected = []
        answer = handle.get_result_async()
        deadline = time.monotonic() + self._sweep_timeout_s
        canceled_at = None
        last_seen = time.monotonic()
        while not answer.done():
            await self._ticks.pause()
            now = time.monotonic()
            if self._sweep.client.server_is_ready():
                last_seen = now
            if canceled_at is None and (goal_handle.is_cancel_requested or now > deadline):
                handle.cancel_goal_async()  # the sweep node lifts the edge off, then ends
                canceled_at = now
            if canceled_at is not None and now - canceled_at > CANCEL_S:
                return 'abort', (f'the sweep did not end within {CANCEL_S:g} s of its cancel: '
                                 'check the arm'), None, []
            if now - last_seen > SERVER_LOST_S:
                return 'abort', (f'the {topics.SWEEP_ACTION} action server went away during '
                                 'the sweep: is sweep_node running?'), None, []
        ended = answer.result()
        if goal_handle.is_cancel_requested:
            return 'cancel', 'canceled: the edge was lifted off', ended.result, []
        if canceled_at is not None:
            return 'abort', (f'the sweep took longer than sweep_timeout_s '
                             f'({self._sweep_timeout_s:g} s) and was canceled'), ended.result, []
        if ended.status != GoalStatus.STATUS_SUCCEEDED:
            return 'abort', f'the sweep failed: {ended.result.message or ended.status}', \
                ended.result, []
        await self._settled(goal_handle, ended.result)
        if goal_handle.is_cancel_requested:  # asked while the last windows came
            return 'cancel', 'canceled after the sweep ended', ended.result, []
        windows, self._collected = self._collected, None
        return 'succeed', '', ended.result, windows

    async def _waited(self, goal_handle, condition, deadline: float) -> bool:
        """Pause until `condition()` holds (True), `deadline` passes or a cancel comes (False).

        The monotonic `deadline` and `goal_handle.is_cancel_requested` are looked at each
        tick, so a cancel ends the wait within TICK_S; the caller tells which ended it.
        """
        while not condition():
            if goal_handle.is_cancel_requested or time.monotonic() >= deadline:
                return False
            await self._ticks.pause()
        return True

    async def _settled(self, goal_handle, sweep_result) -> None:
        """Wait until the stream is final past the sweep's last contact (or settle_s)."""
        end = max((stamp_ns(end) for end in sweep_result.contact_ends), default=None)

        def final() -> bool:
            horizon = self._windows.horizon_ns()
            return end is not None and horizon is not None and horizon >= end
        await self._waited(goal_handle, final, time.monotonic() + self._settle_s)
        self._poll()

    async def _accepted(self, goal_handle, goal: Sweep.Goal):
        """(goal handle, '') once the sweep server accepts `goal`; (None, why) when it does not.

        A copy unanswered for ANSWER_S is sent again (its request or answer was lost in
        discovery); a refused goal (a sweep is running) again after REFUSED_RETRY_S. A
        cancel of `goal_handle` ends the wait at once: (None, ''); a copy whose answer is
        still to come is then canceled when it is accepted, so no sweep runs unasked.
        """
        deadline = time.monotonic() + self._server_timeout_s
        if not await self._waited(goal_handle, self._sweep.client.server_is_ready, deadline):
            return None, ('' if goal_handle.is_cancel_requested else
                          f'no {topics.SWEEP_ACTION} action server within '
                          f'{self._server_timeout_s:g} s: is sweep_node running in this '
                          'namespace?')
        refused = False
        while time.monotonic() < deadline and not goal_handle.is_cancel_requested:
            answer = self._sweep.send_goal_async(goal)
            await self._waited(goal_handle, answer.done,
                               min(deadline, time.monotonic() + ANSWER_S))
            if not answer.done():
                if goal_handle.is_cancel_requested:
                    answer.add_done_callback(_cancel_if_accepted)
                else:
                    self._sweep.forget(answer)
            elif answer.result().accepted:
                return answer.result(), ''
            else:
                refused = True
                await self._waited(goal_handle, lambda: False,
                                   time.monotonic() + REFUSED_RETRY_S)
        if goal_handle.is_cancel_requested:
            return None, ''
        return None, ('the sweep goal was ' + ('refused' if refused else 'not answered')
                      + f' for {self._server_timeout_s:g} s (a sweep is running, or sweep_node '
                      'has not heard the arm and the sensor)')

    def _publish_diagnostics(self) -> None:
        counts = self._windows.counts
        level = DiagnosticStatus.WARN if self._last_aborted else DiagnosticStatus.OK
        values = {'state': self._state, 'last_outcome': self._last_outcome or 'none',
                  'samples': str(counts['samples']), 'windows_cut': str(counts['windows']),
                  **{f'goals_{name}': str(count) for name, count in self._goals.items()}}
        self.publish_diagnostics(self._diagnostics_pub, level,
                                 'identify',
                                 f'{self._state}; last: {self._last_outcome or "none"}', values)

def main(args: list[str] | None = None) -> None:
    """Serve identification goals until shutdown; a refused start exits with code 1."""
    try:
        spin(IdentifyNode, args)
    except StartError:
        sys.exit(1)
