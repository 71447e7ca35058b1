# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The explorer closed-loop against the MuJoCo world in plain Python (no ROS), and its truth.

`run_probe` wires an `Explorer` to a `tactex_sim` world the way the nodes wire it to the
robot: the world's samples go through the Madgwick filter (as madgwick_node does), its
joints through the driver's `ArmController` (the trajectory semantics of the driver and
the simulator bridge), every `Command` replaces the running trajectory and a `Stop`
stops it. Faults (NaN samples, noise bursts, a servo dropping out, commands that reach
the arm late) are injected on the way. The result holds the pathway and the ground truth
it is scored against (`score`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
import itertools
import math

import numpy as np

from tactex_description.geometry import ARM_JOINT_NAMES
from tactex_driver.arm import ArmController, Mode
from tactex_driver.errors import TrajectoryRejected
from tactex_driver.playback import JointLimits
from tactex_probe.exploration import Explorer
from tactex_probe.explorer_interface import (
    Command,
    ExplorerConfig,
    Feedback,
    Finished,
    Phase,
    Stop,
)
from tactex_probe.motion import PathUnreachable, solve, ToolPose
from tactex_probe.normals import angle_between
from tactex_probe.pathway import Pathway, ProbeParameters, ProbeRecord
from tactex_sensor.madgwick import MadgwickConfig, MadgwickFilter
from tactex_sim.scene import Scene, Surface
from tactex_sim.world import Sample, World

# Gain of madgwick_node in config/sensor.yaml.
NODE_MADGWICK = MadgwickConfig(gain=0.1)
# The line of the uneven plate (probe scene) that the benchmarks and reports probe; give
# step and descent_speed (and span to shorten it) to make `ProbeParameters`.
PLATE_LINE = dict(start=(0.10, 0.0, 0.018), direction=(1.0, 0.0, 0.0), span=0.10,
                  approach_height=0.02, max_descent_depth=0.025, force_limit=3.0)


@dataclass(frozen=True)
class Faults:
    """What goes wrong during a simulated run.

    Attributes:
        perturb: changes each sample before the explorer sees it (NaN, noise bursts).
        servo_dropout_s: from this simulated time on, no joint state arrives and the
            servos stop taking goals (they hold their last one).
        cancel_in_phase: the goal is canceled once the explorer has been in this phase
            for `cancel_delay_s` (None: never).
        cancel_delay_s: see `cancel_in_phase`.
        command_delays_s: how late the arm takes each command, in turn (cycled, never
            before a command sent earlier): the latency of the way to the arm, which
            varies; (): at once.
    """

    perturb: Callable[[Sample], Sample] | None = None
    servo_dropout_s: float = math.inf
    cancel_in_phase: Phase | None = None
    cancel_delay_s: float = 0.0
    command_delays_s: tuple[float, ...] = ()


@dataclass(frozen=True)
class ProbeRun:
    """A finished simulated goal.

    Attributes:
        finished: the explorer's end (pathway, outcome, message).
        sim_time_s: simulated time the goal took, from the first step to the end.
        feedback: every feedback event, in order.
        surface: the true surface, for scoring.
        rejected: trajectories the arm refused (when and why); none in a sound run.
        final_joints: the arm's joints (joint1..joint4) when the goal ended.
        measurements: how each successful probe was measured (`Explorer.measurements`).
        trace: per sample: time s, tip (sensor_edge) x, y, z, pressure Pa, the true
            attitude of sensor_link (w, x, y, z) and 1 while the sensor touches.
    """

    finished: Finished
    sim_time_s: float
    feedback: tuple[Feedback, ...]
    surface: Surface
    rejected: tuple[str, ...]
    final_joints: np.ndarray
    measurements: dict
    trace: np.ndarray = field(repr=False)

    @property
    def pathway(self) -> Pathway:
        """The pathway of the run."""
        return self.finished.pathway


def start_joints(parameters: ProbeParameters) -> np.ndarray:
    """Arm joints with the tool vertical up to 3 cm above the first approach pose.

    Raises:
        PathUnreachable: not even the approach pose itself is reachable.
    """
    approach = parameters.probe_point(0) + [0.0, 0.0, parameters.approach_height]
    for extra in (0.03, 0.015, 0.0):
        try:
            return solve(ToolPose(approach + [0.0, 0.0, extra], 0.0), [0.0, 0.0, 0.0, 1.5])
        except PathUnreachable as err:
            failure = err
    raise failure


def run_probe(scene: Scene, parameters: ProbeParameters,
              config: ExplorerConfig | None = None, *, seed: int | None = None,
              faults: Faults = Faults(), max_time_s: float = 600.0,
              madgwick: MadgwickConfig = NODE_MADGWICK) -> ProbeRun:
    """Probe `scene` closed-loop and return the run.

    Args:
        scene: the world to probe (its effects decide noise, barometer, compliance).
        parameters: the goal.
        config: the explorer's tuning (default `ExplorerConfig()`).
        seed: the world's seed (None: the scene's).
        faults: faults to inject.
        max_time_s: simulated time after which the run is aborted.
        madgwick: the orientation filter's settings.
    """
    world = World(scene, seed=seed)
    controller = ArmController(JointLimits.of_robot())
    world.place_arm(np.append(start_joints(parameters), 0.0))
    controller.update_measured(world.joint_positions())
    controller.torque_on(world.time_s)

    def goal(time_s: float) -> np.ndarray:
        target = controller.goal(time_s)
        return world.joint_positions() if target is None else target

    world.controller = goal
    explorer = Explorer(parameters, config)
    attitude = MadgwickFilter(madgwick)
    feedback: list[Feedback] = []
    trace = []
    rejected: list[str] = []
    previous_s = None
    canceled = False
    phase_since_s = 0.0
    pending: list = []  # (when the arm takes it, command), in the order sent
    delays = itertools.cycle(faults.command_delays_s or (0.0,))
    while explorer.finished is None:
        sample = world.next_sample()
        now_s = sample.time_s
        controller.update_measured(world.joint_positions())
        if now_s >= faults.servo_dropout_s and controller.mode is not Mode.FAULT:
            controller.fault('servo dropped out (simulated)')
        if faults.perturb is not None:
            sample = faults.perturb(sample)
        attitude.update(sample.gyro, sample.accel,
                        0.0 if previous_s is None else now_s - previous_s)
        previous_s = now_s
        now_ns = int(round(now_s * 1e9))
        if now_s < faults.servo_dropout_s:
            explorer.joint_state(now_ns, world.joint_positions()[:len(ARM_JOINT_NAMES)])
        if attitude.initialised:
            explorer.imu(now_ns, sample.accel, attitude.quaternion)
        explorer.pressure(now_ns, sample.pressure)
        if explorer.phase is not faults.cancel_in_phase:
            phase_since_s = now_s
        elif now_s - phase_since_s >= faults.cancel_delay_s and not canceled:
            explorer.cancel()
            canceled = True
        for event in explorer.step(now_ns):
            if isinstance(event, Command | Stop):
                due_s = max(now_s + next(delays), pending[-1][0] if pending else 0.0)
                pending.append((due_s, event))
            elif isinstance(event, Feedback):
                feedback.append(event)
        while pending and pending[0][0] <= now_s + 1e-9:
            _take(controller, pending.pop(0)[1], now_s, rejected)
        truth = sample.truth
        trace.append((now_s, *truth.edge_position, sample.pressure, *truth.sensor_quaternion,
                      float(truth.contact.touching)))
        if now_s > max_time_s and explorer.finished is None:
            explorer.cancel()
            max_time_s = math.inf
    start_s = trace[0][0] if trace else 0.0
    return ProbeRun(explorer.finished, world.time_s - start_s, tuple(feedback), scene.surface,
                    tuple(rejected), world.joint_positions()[:len(ARM_JOINT_NAMES)],
                    dict(explorer.measurements), np.asarray(trace))


def _take(controller: ArmController, command: Command | Stop, now_s: float,
          rejected: list[str]) -> None:
    """The arm takes a command at `now_s`; a refusal is kept in `rejected`."""
    if isinstance(command, Stop):
        controller.stop(now_s)
        return
    path = command.path
    try:
        controller.execute(ARM_JOINT_NAMES, path.times_s.tolist(), path.joints.tolist(), [],
                           now_s)
    except TrajectoryRejected as err:
        rejected.append(f'{now_s:.3f} s: {err}')


@dataclass(frozen=True)
class ContactError:
    """How far one contact is from the truth.

    Attributes:
        index: probe index.
        normal_deg: angle between the reported normal and the true normal at the
            surface point nearest the reported position.
        position_mm: distance from the reported position to the true surface.
        x_m: where along x the nearest surface point lies.
    """

    index: int
    normal_deg: float
    position_mm: float
    x_m: float


def nearest_surface_point(surface: Surface, point) -> np.ndarray:
    """The point of the surface's profile (x, z; it has no y slope) nearest `point`.

    Sampled every 10 um over +-5 cm, then refined by the local tangent.
    """
    p = np.asarray(point, dtype=float)
    xs = p[0] + np.linspace(-0.05, 0.05, 10001)
    distance = np.hypot(xs - p[0], surface.height(xs) - p[2])
    x = float(xs[int(np.argmin(distance))])
    return np.array([x, p[1], float(surface.height(x))])


def true_normal(surface: Surface, x: float) -> np.ndarray:
    """Outward unit normal of the surface at x (3-D, no y component)."""
    nx, nz = surface.normal(x)
    return np.array([nx, 0.0, nz])


def score(record: ProbeRecord, surface: Surface) -> ContactError:
    """The error of one successful contact against the true surface."""
    nearest = nearest_surface_point(surface, record.position)
    distance = float(np.linalg.norm(np.asarray(record.position) - nearest))
    truth = true_normal(surface, float(nearest[0]))
    return ContactError(record.index, math.degrees(angle_between(record.normal, truth)),
                        1e3 * distance, float(nearest[0]))


def score_run(run: ProbeRun) -> list[ContactError]:
    """Errors of every successful contact of a run."""
    return [score(record, run.surface) for record in run.pathway.contacts]


def summary(errors: list[ContactError]) -> dict[str, float]:
    """Mean and max normal (deg) and position (mm) errors, and the count."""
    if not errors:
        return {'contacts': 0, 'normal_mean_deg': math.nan, 'normal_max_deg': math.nan,
                'position_mean_mm': math.nan, 'position_max_mm': math.nan}
    normal = np.array([e.normal_deg for e in errors])
    position = np.array([e.position_mm for e in errors])
    return {'contacts': len(errors), 'normal_mean_deg': float(normal.mean()),
            'normal_max_deg': float(normal.max()), 'position_mean_mm': float(position.mean()),
            'position_max_mm': float(position.max())}

