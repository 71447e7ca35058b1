# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The demo's client of a launched system: the actions' goals, the texture, the estimates.

`tactex demo` starts the nodes with the launcher and talks to them only through their
interfaces, as a user's script would: the `probe`, `sweep` and `identify` actions, the
broadcast pathway and contacts (latched), the bridge's `patch_texture` parameter and
`texture/estimate`. Nothing here knows how the nodes work inside.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import threading
import time

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import Point, PoseArray, Vector3
from rcl_interfaces.msg import Parameter, ParameterType, ParameterValue
from rcl_interfaces.srv import SetParameters
import rclpy
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor

from tactex.demo.figures import Estimate
from tactex.errors import CommandError
from tactex_common import topics
from tactex_common.goals import GoalSender
from tactex_common.ros import COMMAND, LATCHED
from tactex_common.stamps import stamp_ns
from tactex_msgs.action import Identify, Probe, Sweep
from tactex_msgs.msg import Pathway, TextureEstimate

# The bridge's parameter service (the simulator stands in for the robot under this name).
BRIDGE_PARAMETERS = 'mujoco_bridge/set_parameters'
CLASSIFIER_STATUS = topics.diagnostic_name('/classifier_node', 'classifier')  # diagnostics status
MADGWICK_STATUS = topics.diagnostic_name('/madgwick_node', 'madgwick')


class ProbeAborted(CommandError):
    """The probe node aborted the goal; the message is its reason."""


@dataclass(frozen=True)
class ProbeLine:
    """A Probe goal along x at y = 0 (base_link), m and m/s."""

    start_x_m: float
    span_m: float
    step_m: float
    start_z_m: float = 0.018
    approach_height_m: float = 0.02
    descent_speed_m_s: float = 0.005
    max_descent_depth_m: float = 0.025
    force_limit_n: float = 3.0

    @property
    def points(self) -> int:
        """How many probe points the line has."""
        return int(round(self.span_m / self.step_m)) + 1


@dataclass
class SweepRun:
    """What one sweep goal gave: its result, feedback and the estimates heard meanwhile.

    `feedback` holds (wall s since the goal, progress, in contact, sliding speed m/s);
    `attempts` counts the goals sent for it (an aborted sweep is tried again).
    """

    label: str
    trial: int
    speed_m_s: float
    result: Sweep.Result | None = None
    status_ok: bool = False
    attempts: int = 1
    feedback: list[tuple[float, float, bool, float]] = field(default_factory=list)
    estimates: list[Estimate] = field(default_factory=list)


class SystemClient:
    """A node in this process that drives a launched system; a context manager."""

    def __init__(self) -> None:
        self._context = Context()
        rclpy.init(args=[], context=self._context)  # the command line is not ROS's
        self._node = rclpy.create_node('tactex_demo', context=self._context)
        self._lock = threading.Lock()
        self._pathway: Pathway | None = None
        self._contacts: PoseArray | None = None
        self._estimates: list[Estimate] | None = None
        self._classifier: DiagnosticStatus | None = None  # its newest diagnostics
        self._madgwick: DiagnosticStatus | None = None  # madgwick_node's newest
        node = self._node
        node.create_subscription(Pathway, topics.PROBE_PATHWAY, self._on_pathway, LATCHED)
        node.create_subscription(PoseArray, topics.PROBE_CONTACTS, self._on_contacts, LATCHED)
        node.create_subscription(TextureEstimate, topics.TEXTURE_ESTIMATE, self._on_estimate,
                                 COMMAND)
        node.create_subscription(DiagnosticArray, topics.DIAGNOSTICS, self._on_diagnostics,
                                 COMMAND)
        self._probe = GoalSender(node, Probe, topics.PROBE_ACTION)
        self._sweep = GoalSender(node, Sweep, topics.SWEEP_ACTION)
        self._identify = GoalSender(node, Identify, topics.IDENTIFY_ACTION)
        self._parameters = node.create_client(SetParameters, BRIDGE_PARAMETERS)
        self._executor = SingleThreadedExecutor(context=self._context)
        self._executor.add_node(node)
        self._thread = threading.Thread(target=self._executor.spin, daemon=True)
        self._thread.start()

    def __enter__(self) -> SystemClient:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        """Stop spinning and leave the ROS graph (idempotent)."""
        if self._context.ok():
            self._executor.shutdown(timeout_sec=2.0)
            self._thread.join(timeout=5.0)  # no spin may touch the node while it is destroyed
            self._node.destroy_node()
            rclpy.try_shutdown(context=self._context)

    # -- subscriptions --------------------------------------------------------------------
    def _on_pathway(self, msg: Pathway) -> None:
        with self._lock:
            self._pathway = msg

    def _on_contacts(self, msg: PoseArray) -> None:
        with self._lock:
            self._contacts = msg

    def _on_estimate(self, msg: TextureEstimate) -> None:
        with self._lock:
            if self._estimates is not None and msg.class_id >= 0:
                self._estimates.append(Estimate(msg.label, msg.decided, msg.contact_seconds))

    def _on_diagnostics(self, msg: DiagnosticArray) -> None:
        for status in msg.status:
            if status.name == CLASSIFIER_STATUS:
                with self._lock:
                    self._classifier = status
            elif status.name == MADGWICK_STATUS:
                with self._lock:
                    self._madgwick = status

    def madgwick_rejected(self, kinds: tuple[str, ...] = ('gyro', 'accel')) -> int | None:
        """Samples madgwick_node has rejected so far for `kinds`, by its newest diagnostics.

        The default kinds are the samples' values (beyond the chip's full scale, or not
        finite); 'dt' counts stamps that did not advance (a duplicate or reordered
        delivery) or left a gap. None: no diagnostics heard.
        """
        with self._lock:
            status = self._madgwick
        if status is None:
            return None
        keys = {f'rejected_{kind}' for kind in kinds}
        return sum(int(kv.value) for kv in status.values if kv.key in keys)

    # -- waiting --------------------------------------------------------------------------
    @staticmethod
    def _wait(condition, timeout_s: float, what: str, alive=lambda: True) -> None:
        """Poll `condition` until it holds; CommandError naming `what` after timeout_s."""
        deadline = time.monotonic() + timeout_s
        while not condition():
            if time.monotonic() > deadline:
                raise CommandError(f'{what} within {timeout_s:g} s; the node logs say why')
            if not alive():
                raise CommandError(f'{what}: a node stopped; the node logs say why')
            time.sleep(0.05)

    def wait_ready(self, timeout_s: float, *, sweep: bool = True, bridge: bool = True,
                   alive=lambda: True) -> None:
        """Wait for the probe (and sweep) action servers (and the bridge's parameters)."""
        ready = [('the probe action server', self._probe.client.server_is_ready)]
        if sweep:
            ready.append(('the sweep action server', self._sweep.client.server_is_ready))
        if bridge:
            ready.append(('the simulator', self._parameters.service_is_ready))
        for what, check in ready:
            self._wait(check, timeout_s, f'{what} did not come up', alive)

    def wait_identify_ready(self, timeout_s: float, alive=lambda: True) -> None:
        """Wait for identify_node's action server (its bundle is loaded by then)."""
        self._wait(self._identify.client.server_is_ready, timeout_s,
                   'the identify action server did not come up', alive)

    def wait_classifier_ready(self, timeout_s: float, alive=lambda: True) -> None:
        """Wait for classifier_node's diagnostics to say OK.

        Then its model is loaded and every topic it reads is arriving. CommandError with
        its last diagnostics after `timeout_s`.
        """
        try:
            self._wait(self._classifier_ready, timeout_s, 'classifier_node was not ready',
                       alive)
        except CommandError as err:
            with self._lock:
                said = self._classifier.message if self._classifier else 'no diagnostics'
            raise CommandError(f'{err} (its diagnostics: {said})') from None

    def _classifier_ready(self) -> bool:
        with self._lock:
            return self._classifier is not None and self._classifier.level == \
                DiagnosticStatus.OK

    def _send(self, sender: GoalSender, goal, timeout_s: float, what: str, alive,
              feedback=None):
        """Send a goal, again while refused or unanswered (nodes wait for the arm); its result."""
        from tactex.goal_client import accepted_handle
        handle = accepted_handle(sender, goal, timeout_s, what, alive, feedback)
        result = handle.get_result_async()
        self._wait(result.done, timeout_s, f'{what} did not finish', alive)
        return result.result()

    # -- the jobs -------------------------------------------------------------------------
    def probe(self, line: ProbeLine, timeout_s: float, alive=lambda: True
              ) -> tuple[Probe.Result, Pathway, PoseArray]:
        """Probe `line`; the result and the pathway and contacts as broadcast (latched)."""
        goal = Probe.Goal(start=Point(x=line.start_x_m, y=0.0, z=line.start_z_m),
                          direction=Vector3(x=1.0), span=line.span_m, step=line.step_m,
                          approach_height=line.approach_height_m,
                          descent_speed=line.descent_speed_m_s,
                          max_descent_depth=line.max_descent_depth_m,
                          force_limit=line.force_limit_n)
        answer = self._send(self._probe, goal, timeout_s, 'probing', alive)
        result = answer.result
        if result.message:
            raise ProbeAborted(result.message)
        stamp = stamp_ns(result.pathway.header.stamp)

        def broadcast() -> bool:
            with self._lock:
                return (self._pathway is not None and self._contacts is not None
                        and stamp_ns(self._pathway.header.stamp) == stamp
                        and stamp_ns(self._contacts.header.stamp) == stamp)
        self._wait(broadcast, 10.0, 'the pathway was not broadcast on '
                   f'{topics.PROBE_PATHWAY} and {topics.PROBE_CONTACTS}', alive)
        with self._lock:
            return result, self._pathway, self._contacts

    def send_sweep(self, goal: Sweep.Goal, timeout_s: float, what: str, alive=lambda: True):
        """Send a Sweep goal made elsewhere (e.g. a movement's part); (status code, result)."""
        answer = self._send(self._sweep, goal, timeout_s, what, alive)
        return answer.status, answer.result

    def identify(self, goal: Identify.Goal, timeout_s: float, what: str, alive=lambda: True,
                 feedback=None):
        """Send an Identify goal (`feedback` hears each movement's); (status code, result)."""
        answer = self._send(self._identify, goal, timeout_s, what, alive, feedback)
        return answer.status, answer.result

    def set_texture(self, name: str, alive=lambda: True) -> None:
        """Give the simulator's patches the texture `name` (the bridge's parameter)."""
        self.set_bridge_parameter('patch_texture', name, alive)

    def set_bridge_parameter(self, name: str, value: str, alive=lambda: True) -> None:
        """Set a string parameter of the simulator while it runs."""
        request = SetParameters.Request(parameters=[Parameter(
            name=name, value=ParameterValue(type=ParameterType.PARAMETER_STRING,
                                            string_value=value))])
        future = self._parameters.call_async(request)
        self._wait(future.done, 10.0, f'the simulator did not take {name} {value!r}', alive)
        answer = future.result().results[0]
        if not answer.successful:
            raise CommandError(f'the simulator refused {name} {value!r}: {answer.reason}')

    def sweep(self, run: SweepRun, *, edge_offset_rad: float, press_depth_m: float,
              record: bool, timeout_s: float, alive=lambda: True,
              pathway: Pathway | None = None) -> SweepRun:
        """Sweep along `pathway` (None: the broadcast one); fills `run` and its estimates."""
        goal = Sweep.Goal(sliding_speed=run.speed_m_s, edge_offset_angle=edge_offset_rad,
                          press_depth=press_depth_m, label=run.label, trial=run.trial,
                          record=record)
        if pathway is not None:
            goal.pathway = pathway
        started = time.monotonic()

        def on_feedback(message) -> None:
            f = message.feedback
            run.feedback.append((time.monotonic() - started, float(f.progress),
                                 bool(f.in_contact), float(f.sliding_speed)))
        with self._lock:
            self._estimates = run.estimates
        try:
            answer = self._send(self._sweep, goal, timeout_s, f'sweep {run.trial} ({run.label})',
                                alive, on_feedback)
            time.sleep(0.5)  # the classifier's last windows of this sweep
        finally:
            with self._lock:
                self._estimates = None
        run.result = answer.result
        run.status_ok = not answer.result.message
        return run
