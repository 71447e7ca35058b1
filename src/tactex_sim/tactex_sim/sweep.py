# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Scripted sweeps: the sensor edge pressed into the surface and dragged along it.

A sweep recorded without the trajectory executor is planned here: approach above the
start point, descend to the press depth, slide along the surface (radially, in the arm's
plane) at the sweep speed with the sensor axis tilted by the edge offset from the inward
normal, lift off. Where the scene asks for speed ramps, the slide ramps up to the speed
and down from it as the Sweep action does, pressed in, around the contact. Each phase is
solved with the analytic IK every 10 ms; the contact at full speed is the "moving and in
contact" part of a recording.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
import math
import time
from typing import TYPE_CHECKING

import numpy as np

from tactex_description.kinematics import inverse_kinematics
from tactex_description.mjcf import EDGE_TIP_RADIUS_M
from tactex_description.speed_ramp import ramp_duration_s, ramped_law
from tactex_sim.errors import SimError
from tactex_sim.scene import Scene

if TYPE_CHECKING:
    from tactex_sim.world import Sample, World

PLAN_STEP_S = 0.01
APPROACH_HEIGHT_M = 0.02
SETTLE_S = 0.5
DESCEND_S = 1.5
LIFT_S = 0.8


@dataclass(frozen=True)
class SweepParameters:
    """One sweep's draw of the scene's variability."""

    start_x_m: float
    speed_m_s: float
    press_depth_m: float
    edge_offset_rad: float
    heading_rad: float
    noise_scale: float
    drift_pa_per_s: float
    direction: int = 1

    @classmethod
    def nominal(cls, scene: Scene) -> SweepParameters:
        """The scene's sweep as laid out, before any variability is drawn."""
        sweep = scene.sweep
        return cls(start_x_m=sweep.start_x_m, speed_m_s=sweep.speed_m_s,
                   press_depth_m=scene.variability.press_depth_m[0],
                   edge_offset_rad=sweep.edge_offset_rad, heading_rad=0.0, noise_scale=1.0,
                   drift_pa_per_s=0.0, direction=sweep.direction)

    @classmethod
    def draw(cls, scene: Scene, rng: np.random.Generator) -> SweepParameters:
        """Nominal sweep of the scene varied as its [variability] table says.

        Start, speed and mount tilt are drawn within two standard deviations, so every
        sweep stays in the part of the workspace the scene was laid out for (`extremes`).
        """
        sweep, spread = scene.sweep, scene.variability
        depth_mean, depth_sd = spread.press_depth_m
        return cls(
            start_x_m=sweep.start_x_m + _bounded_normal(rng, spread.start_x_m),
            speed_m_s=sweep.speed_m_s * (1.0 + _bounded_normal(rng, spread.speed_fraction)),
            press_depth_m=float(np.clip(rng.normal(depth_mean, depth_sd), 0.3 * depth_mean,
                                        2.0 * depth_mean)),
            edge_offset_rad=sweep.edge_offset_rad + _bounded_normal(rng, spread.mount_tilt_rad),
            heading_rad=rng.uniform(-spread.heading_rad, spread.heading_rad),
            noise_scale=max(0.2, 1.0 + rng.normal(0.0, spread.noise_scale)),
            drift_pa_per_s=rng.normal(0.0, spread.drift_pa_per_s),
            direction=sweep.direction)

    @classmethod
    def extremes(cls, scene: Scene) -> list[SweepParameters]:
        """The draws at the corners of what `draw` can draw of the pose and the path.

        Every start (+-2 sd), mount tilt (+-2 sd) and press depth (0.3 to 2 x the mean)
        combined, at the fastest speed (+2 sd: the longest path): a scene whose extremes
        the arm can sweep can sweep every draw between them.
        """
        sweep, spread = scene.sweep, scene.variability
        depth_mean = spread.press_depth_m[0]
        nominal = cls.nominal(scene)
        return [replace(nominal, start_x_m=sweep.start_x_m + start * 2.0 * spread.start_x_m,
                        speed_m_s=sweep.speed_m_s * (1.0 + 2.0 * spread.speed_fraction),
                        edge_offset_rad=sweep.edge_offset_rad
                        + tilt * 2.0 * spread.mount_tilt_rad,
                        press_depth_m=depth * depth_mean)
                for start in (-1.0, 1.0) for tilt in (-1.0, 1.0) for depth in (0.3, 2.0)]


@dataclass(frozen=True)
class SweepPlan:
    """Joint targets every 10 ms and when the edge slides in contact."""

    times_s: np.ndarray
    joints: np.ndarray  # (n, 5): joint1..joint4 rad, gripper m
    slide_start_s: float
    slide_end_s: float

    def targets(self, t_s: float) -> np.ndarray:
        """Interpolated joint targets at `t_s`."""
        index = min(max(int(t_s / PLAN_STEP_S), 0), len(self.times_s) - 2)
        fraction = min(max((t_s - self.times_s[index]) / PLAN_STEP_S, 0.0), 1.0)
        return self.joints[index] + fraction * (self.joints[index + 1] - self.joints[index])


def plan_sweep(scene: Scene, parameters: SweepParameters, duration_s: float | None = None
               ) -> SweepPlan:
    """Solve the sweep's joint targets.

    Raises:
        SimError: a point of the path is out of the arm's reach (with the IK's reason).
    """
    surface = scene.surface
    contact_s = scene.sweep.contact_s if duration_s is None else duration_s
    speed = parameters.speed_m_s
    ramp_s = ramp_duration_s(speed, scene.sweep.ramp_acceleration_m_s2)
    slide_begin = SETTLE_S + DESCEND_S  # pressed in: the speed ramps up from here
    slide_start = slide_begin + ramp_s
    slide_end = slide_start + contact_s
    total = slide_end + ramp_s + LIFT_S
    if ramp_s > 0.0:
        law = ramped_law(speed * (contact_s + ramp_s), speed, ramp_s)
        travelled = law.position
    else:
        def travelled(t):
            return speed * min(max(t, 0.0), contact_s)
    times = np.arange(0.0, total + PLAN_STEP_S, PLAN_STEP_S)
    joints = np.zeros((times.size, 5))
    seed = np.array([0.0, 0.3, 0.0, 1.0])
    # The script places the edge's centre; a rim pressed d in puts it d - r in.
    centre_depth = parameters.press_depth_m - (
        EDGE_TIP_RADIUS_M if scene.sweep.press == 'rim' else 0.0)
    for i, t in enumerate(times):
        travel = float(travelled(t - slide_begin))
        x = parameters.start_x_m + parameters.direction * travel
        height = float(surface.height(x))
        slope = float(surface.slope(x))
        normal = surface.normal(x)
        if t < SETTLE_S:
            lift = APPROACH_HEIGHT_M
        elif t < slide_begin:
            lift = APPROACH_HEIGHT_M * (1.0 - _smooth((t - SETTLE_S) / DESCEND_S))
        elif t <= slide_end + ramp_s:
            lift = 0.0
        else:
            lift = APPROACH_HEIGHT_M * _smooth((t - slide_end - ramp_s) / LIFT_S)
        depth = centre_depth * (1.0 if lift == 0.0 else max(0.0, 1.0 - lift / 0.003))
        point = np.array([x, height]) + (lift - depth) * normal
        pitch = math.pi / 2 - math.atan(slope) - parameters.edge_offset_rad
        result = inverse_kinematics([point[0], 0.0, point[1]], pitch, seed=seed)
        if not result.reachable:
            raise SimError(f'sweep point x={x:.3f} m z={point[1]:.3f} m unreachable: '
                           f'{result.detail}')
        seed = result.solutions[0]
        joints[i, :4] = seed
    return SweepPlan(times, joints, slide_start, slide_end)


def _bounded_normal(rng: np.random.Generator, sd: float) -> float:
    """A normal draw with standard deviation `sd`, clipped to two of them."""
    return float(np.clip(rng.normal(0.0, sd), -2.0 * sd, 2.0 * sd))


def _smooth(fraction: float) -> float:
    """Smoothstep from 0 to 1."""
    f = min(max(fraction, 0.0), 1.0)
    return f * f * (3.0 - 2.0 * f)


def play(world: World, plan: SweepPlan,
         on_sample: Callable[[Sample], None] = lambda sample: None) -> float:
    """Run `plan` in `world` from its first pose to its end; the wall seconds it took."""
    world.place_arm(plan.joints[0])
    world.controller = plan.targets
    began = time.perf_counter()
    while world.time_s < plan.times_s[-1]:
        on_sample(world.next_sample())
    return time.perf_counter() - began
