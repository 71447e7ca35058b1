# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Sweeps played in the simulator and measured against its ground truth.

`execute` plays a planned trajectory through the driver's own controller in a
`tactex_sim` World (as the bridge does) and records the ground truth at every sensor
sample; `measure` scores it over the planned contact segment: the fraction of it in
contact, the sliding speed along the path (in windows), and the press depth the arm
really held (its joints' edge position against the true surface) minus the one asked.
`probed_pathway` probes the scene in closed loop with tactex_probe's explorer (what a
sweep of a real surface starts from); `probe_like_pathway` makes the contacts a probe
would report from the scene's surface, with the probe's noise, for planning without
probing.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
import math

import numpy as np

from tactex_description.geometry import ARM_JOINT_NAMES
from tactex_description.mjcf import EDGE_TIP_RADIUS_M
from tactex_driver.arm import ArmController
from tactex_driver.playback import JointLimits
from tactex_probe.closed_loop import run_probe
from tactex_probe.pathway import DEFAULT_GOAL, ProbeParameters
from tactex_sim.scene import Scene, Surface
from tactex_sim.world import World
from tactex_trajectory.monitor import window_speeds
from tactex_trajectory.path import SweepPath
from tactex_trajectory.planner import SweepPlan
from tactex_trajectory.poses import ARM


@dataclass(frozen=True)
class SweepRecord:
    """Ground truth and the IMU's readings at every sensor sample of a simulated sweep.

    Times from the sweep's start.
    """

    times_s: np.ndarray
    touching: np.ndarray
    force_n: np.ndarray
    edge_positions: np.ndarray  # the compliant body's sensor_edge (m)
    arm_edge_positions: np.ndarray  # sensor_edge of the measured arm joints, body rigid
    pressure_pa: np.ndarray
    joints: np.ndarray  # measured joint1..joint4 (rad)
    accel: np.ndarray  # what the IMU's accelerometer read (m/s^2, sensor frame)
    gyro: np.ndarray  # what its gyro read (rad/s)


@dataclass(frozen=True)
class SweepMeasurement:
    """How well a simulated sweep did over its planned contact segment.

    Attributes:
        contact_fraction: fraction of the segment's samples in contact.
        speed_mean_m_s: mean sliding speed along the path over the segment.
        speed_error_max: largest |window speed / set speed - 1| over the segment.
        speed_errors: that ratio for every window.
        arm_speed_error_max: the same for the edge where the arm's joints hold it (the
            body rigid): what the trajectory itself does, before the body's compliance.
        press_depth_error_rms_m, press_depth_error_mean_m: (held - asked) press depth.
        planned_depth_error_rms_m: (commanded - asked) press depth: the path's share of
            the error (the rest is the arm's tracking).
    """

    contact_fraction: float
    speed_mean_m_s: float
    speed_error_max: float
    speed_errors: np.ndarray
    arm_speed_error_max: float
    press_depth_error_rms_m: float
    press_depth_error_mean_m: float
    planned_depth_error_rms_m: float

    def summary(self) -> str:
        """One line of the numbers."""
        return (f'contact {100 * self.contact_fraction:.1f} %, speed '
                f'{self.speed_mean_m_s * 1e3:.2f} mm/s (worst window '
                f'{100 * self.speed_error_max:.1f} %, of the arm '
                f'{100 * self.arm_speed_error_max:.1f} %), press depth error rms '
                f'{self.press_depth_error_rms_m * 1e3:.2f} mm (mean '
                f'{self.press_depth_error_mean_m * 1e3:+.2f} mm; planned '
                f'{self.planned_depth_error_rms_m * 1e3:.2f} mm)')


def execute(world: World, plan: SweepPlan, *, start_joints=None, tail_s: float = 0.2
            ) -> SweepRecord:
    """Play `plan` in `world` through the driver's controller and record the ground truth.

    Args:
        world: a fresh world (its time is the trajectory's time origin).
        plan: planned from `start_joints`.
        start_joints: where the arm is placed (joint1..joint4 and the gripper); default
            the plan's first point.
        tail_s: simulated time after the trajectory's end.
    """
    goal, on_sample = driven(world, plan, start_joints=start_joints)
    return record(world, goal, plan.trajectory.duration_s + tail_s, on_sample=on_sample)


def driven(world: World, plan: SweepPlan, *, start_joints=None
           ) -> tuple[Callable[[float], np.ndarray], Callable[[], None]]:
    """Place the arm and hand `plan` to the driver's controller, as the bridge does.

    Returns (goal, on_sample): the joint targets at a simulated time, and what to call
    after every sensor sample (the controller reads the measured joints). `start_joints`
    as for `execute`.
    """
    first = plan.trajectory.positions[0]
    start = np.concatenate([first, [0.0]]) if start_joints is None else np.asarray(
        start_joints, dtype=float)
    world.place_arm(start)
    controller = ArmController(JointLimits.of_robot())
    controller.update_measured(world.joint_positions())
    controller.torque_on(world.time_s)
    return handed(world, controller, plan)


def handed(world: World, controller: ArmController, plan: SweepPlan
           ) -> tuple[Callable[[float], np.ndarray], Callable[[], None]]:
    """Hand `plan` to a driver's `controller` already holding the arm in `world`, now.

    Returns (goal, on_sample) as `driven` does; what the controller ran before is replaced
    (the arm goes on from where it is, as after an earlier sweep).
    """
    trajectory = plan.trajectory
    controller.execute(list(ARM_JOINT_NAMES), trajectory.times_s.tolist(),
                       trajectory.positions.tolist(), trajectory.velocities.tolist(),
                       world.time_s)

    def goal(time_s: float) -> np.ndarray:
        target = controller.goal(time_s)
        return world.joint_positions() if target is None else target

    return goal, lambda: controller.update_measured(world.joint_positions())


def record(world: World, controller, duration_s: float, *, on_sample=None) -> SweepRecord:
    """Run `world` under `controller` (time s -> joint targets) for `duration_s`, recording.

    Times in the record start at the world's present time.
    """
    world.controller = controller
    origin = world.time_s
    rows = []
    while world.time_s < origin + duration_s:
        sample = world.next_sample()
        joints = world.joint_positions()
        if on_sample is not None:
            on_sample()
        rows.append((sample.time_s - origin, sample.truth.contact.touching,
                     sample.truth.contact.force, *sample.truth.edge_position,
                     *ARM.tool_pose(joints[:4])[0], sample.pressure, *joints[:4],
                     *sample.accel, *sample.gyro))
    table = np.array(rows, dtype=float)
    return SweepRecord(table[:, 0], table[:, 1] > 0.5, table[:, 2], table[:, 3:6],
                       table[:, 6:9], table[:, 9], table[:, 10:14], table[:, 14:17],
                       table[:, 17:20])


def measure(record: SweepRecord, plan: SweepPlan, surface: Surface) -> SweepMeasurement:
    """Score a simulated sweep over its planned contact segment against the true surface."""
    return measure_segment(record, (plan.contact_start_s, plan.contact_end_s), plan.path,
                           plan.settings.sliding_speed_m_s, plan.settings.pose.press_depth_m,
                           plan.trajectory.interpolant(), surface)


def measure_segment(record: SweepRecord, segment_s: tuple[float, float], path: SweepPath,
                    speed_m_s: float, press_depth_m: float, commanded, surface: Surface
                    ) -> SweepMeasurement:
    """Score a simulated sweep over `segment_s` against the true surface.

    Args:
        record: what happened.
        segment_s: the planned contact segment (s, record time).
        path: the path the edge should slide along (speeds are measured along it).
        speed_m_s: the sliding speed asked.
        press_depth_m: the press depth asked.
        commanded: record time (s) -> the commanded joint1..joint4.
        surface: the true surface.
    """
    segment = (record.times_s >= segment_s[0]) & (record.times_s <= segment_s[1])
    if not np.any(segment):
        raise ValueError('the record does not cover the planned contact segment')
    travel = path.travel_of(record.edge_positions[segment])
    times = record.times_s[segment]
    errors = window_speeds(times, travel, [(times[0], times[-1])]) / speed_m_s - 1.0
    arm_errors = window_speeds(times, path.travel_of(record.arm_edge_positions[segment]),
                               [(times[0], times[-1])]) / speed_m_s - 1.0
    held = rim_press_depth(record.arm_edge_positions[segment], surface)
    depth_error = held - press_depth_m
    planned = rim_press_depth(np.array([ARM.tool_pose(np.asarray(commanded(t))[:4])[0]
                                     for t in times]), surface)
    planned_error = planned - press_depth_m
    return SweepMeasurement(
        contact_fraction=float(np.mean(record.touching[segment])),
        speed_mean_m_s=float((travel[-1] - travel[0]) / (times[-1] - times[0])),
        speed_error_max=float(np.max(np.abs(errors))) if errors.size else math.nan,
        speed_errors=errors,
        arm_speed_error_max=float(np.max(np.abs(arm_errors))) if arm_errors.size else math.nan,
        press_depth_error_rms_m=float(np.sqrt(np.mean(depth_error ** 2))),
        press_depth_error_mean_m=float(np.mean(depth_error)),
        planned_depth_error_rms_m=float(np.sqrt(np.mean(planned_error ** 2))))


def rim_press_depth(edge_positions: np.ndarray, surface: Surface) -> np.ndarray:
    """How deep the rim of an edge at these positions would be in the true surface (m)."""
    x, z = edge_positions[:, 0], edge_positions[:, 2]
    height_above = (z - surface.height(x)) / np.sqrt(1.0 + surface.slope(x) ** 2)
    return EDGE_TIP_RADIUS_M - height_above


def probe_like_pathway(surface: Surface, start_x_m: float, end_x_m: float, step_m: float,
                       rng: np.random.Generator, *, position_sd_m: float = 0.001,
                       normal_sd_rad: float = math.radians(2.0), y_m: float = 0.0
                       ) -> tuple[np.ndarray, np.ndarray]:
    """Contacts every `step_m` along x on the true surface, with probe-like noise.

    Returns (points, normals), (n, 3) each: positions perturbed by isotropic Gaussian
    noise, normals tilted by Gaussian angles about two axes across them.
    """
    xs = np.arange(start_x_m, end_x_m + 1e-9, step_m)
    slopes = surface.slope(xs)
    normals = np.stack([-slopes, np.zeros_like(xs), np.ones_like(xs)], axis=1)
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    points = np.stack([xs, np.full_like(xs, y_m), surface.height(xs)], axis=1)
    points = points + rng.normal(0.0, position_sd_m, points.shape)
    across = np.cross(normals, [0.0, 1.0, 0.0])
    tilts = rng.normal(0.0, normal_sd_rad, (len(xs), 2))
    noisy = (normals + tilts[:, :1] * across + tilts[:, 1:] * np.array([0.0, 1.0, 0.0]))
    return points, noisy / np.linalg.norm(noisy, axis=1, keepdims=True)


def probed_pathway(scene: Scene, start_x_m: float, end_x_m: float, step_m: float, *,
                   seed: int | None = None, y_m: float = 0.0
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The pathway tactex_probe's explorer measures on `scene`, probing along x in MuJoCo.

    Probes every `step_m` from `start_x_m` to `end_x_m` (the probe node's default goal for
    heights, speed and force, from its approach height above the highest surface point) and
    returns (points, normals, ok) as `plan_sweep` takes them: every probe, failed ones
    with ok False.
    """
    top = float(np.max(scene.surface.height(np.linspace(start_x_m, end_x_m, 200))))
    parameters = ProbeParameters(**{
        **DEFAULT_GOAL, 'start': (start_x_m, y_m, top), 'direction': (1.0, 0.0, 0.0),
        'span': end_x_m - start_x_m + 1e-9, 'step': step_m})
    probes = run_probe(scene, parameters, seed=seed).pathway.probes
    return (np.array([p.position for p in probes], dtype=float),
            np.array([p.normal for p in probes], dtype=float),
            np.array([p.ok for p in probes], dtype=bool))
