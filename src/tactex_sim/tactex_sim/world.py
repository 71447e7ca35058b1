# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The simulator core: arm + surface in MuJoCo, stepped from Python, sampled like the sensor.

`World(scene)` builds only what the scene's effects call for (the compliant joints, the
collision of sensor and surface) and every sensor period returns a reading (accel, gyro
from MuJoCo's site sensors; the rest from the effects; NaN where no effect simulates a
channel) with the ground truth: contact point, surface normal and force, the attitude of
`sensor_link`, the texture under the edge. The physics steps at the largest step no
longer than the scene's `timestep_s` that divides the sensor period (2 ms asked at
350 Hz: 1.43 ms, two steps per sample; at 120 Hz: 1.67 ms, five), so every sample falls
on a physics instant and sample k is taken at exactly k / rate, as a sensor would.
edge. At each sample the world computes the inputs its enabled effects declare
(`tactex_sim.inputs.Inputs`) and gives each effect those it declared.
"""

from __future__ import annotations

from dataclasses import dataclass
import math
from typing import Any

import mujoco
import numpy as np

from tactex_common import frames
from tactex_description.geometry import JOINT_STATE_NAMES, OPEN_MANIPULATOR_X, PRESS_TRAVEL_M
from tactex_description.mjcf import build_mjcf, IMU_SITE, SENSOR_EDGE_GEOM, SENSOR_GEOM
from tactex_sim.effects import Effect, effect_class, EFFECTS, Reading
from tactex_sim.errors import SimError
from tactex_sim.inputs import Contact, Inputs, NO_CONTACT
from tactex_sim.scene import Scene
from tactex_sim.textures import texture as find_texture

SURFACE_GEOM = 'surface'
PRESS_STIFFNESS_N_M = OPEN_MANIPULATOR_X.joint('sensor_press').stiffness
# The most simulated seconds per wall second the bridge is asked for (0: as fast as it can).
MAX_RATE_FACTOR = 1000.0
# A placed arm settles this long under its servos before its clock starts (s): it sags
# about 4 mrad at joints 2 and 3 and is within 1e-5 rad/s of rest by then.
SETTLE_S = 0.5
# MuJoCo's warnings that the state went non-finite or huge (it resets the state then).
_DIVERGED = (mujoco.mjtWarning.mjWARN_BADQPOS, mujoco.mjtWarning.mjWARN_BADQVEL,
             mujoco.mjtWarning.mjWARN_BADQACC)


@dataclass(frozen=True)
class GroundTruth:
    """What really happened at a sample."""

    time_s: float
    contact: Contact
    sensor_quaternion: np.ndarray  # (w, x, y, z) of sensor_link in world
    edge_position: np.ndarray
    texture: str  # '' when the edge is not over a patch


@dataclass(frozen=True)
class Sample:
    """One sensor sample (sensor frame, SI units) and its ground truth."""

    time_s: float
    accel: np.ndarray
    gyro: np.ndarray
    mag: np.ndarray
    pressure: float
    temperature: float
    truth: GroundTruth


class World:
    """A scene built in MuJoCo.

    Args:
        scene: what to build.
        seed: overrides the scene's seed (each sweep of a dataset has its own).
        texture_heading_rad: rotation of the texture on its patch.
        noise_scale: multiplies every noise level.
        drift_pa_per_s: barometer drift of this run.
        patch_texture: replaces the texture of every patch (dataset collection).
    """

    def __init__(self, scene: Scene, *, seed: int | None = None,
                 texture_heading_rad: float = 0.0, noise_scale: float = 1.0,
                 drift_pa_per_s: float = 0.0, patch_texture: str | None = None) -> None:
        self.scene = scene
        self.rng = np.random.default_rng(scene.seed if seed is None else seed)
        self._patches = scene.patches
        self.set_patch_texture(patch_texture)
        self.effects: list[Effect] = []
        # Registry order, whatever the scene's order (effect_class names unknown ones).
        for cls in sorted(map(effect_class, scene.effects), key=list(EFFECTS.values()).index):
            options = dict(scene.effect_options.get(cls.name, {}))
            if cls.name == 'texture':
                options.setdefault('heading_rad', texture_heading_rad)
            if cls.name == 'barometer':
                options.setdefault('drift_pa_per_s', drift_pa_per_s)
            self.effects.append(cls(self.rng, noise_scale, **options))
        written = frozenset().union(*(e.writes for e in self.effects))
        self.period_s = 1.0 / scene.sensor_rate_hz
        # Steps per sample; the tolerance keeps a step that divides the period exactly.
        self.substeps = max(1, math.ceil(self.period_s / scene.timestep_s - 1e-9))
        self.model = mujoco.MjModel.from_xml_string(build_mjcf(
            timestep_s=self.period_s / self.substeps, compliant='sensor pose' in written,
            assets_xml=self._surface_assets(), worldbody_xml=self._surface_geoms(),
            sensors_xml=f'<accelerometer name="accel" site="{IMU_SITE}"/>'
                        f'<gyro name="gyro" site="{IMU_SITE}"/>'))
        if scene.surface.kind == 'uneven':
            self._fill_heightfield()
        if 'contact' not in written:
            self.model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
        self.data = mujoco.MjData(self.model)
        self._arm_qpos = [self.model.joint(n).qposadr[0] for n in JOINT_STATE_NAMES]
        self._press = (self.model.joint('sensor_press').qposadr[0]
                       if 'sensor pose' in written else None)
        self._sensor_geoms = {self.model.geom(SENSOR_GEOM).id,
                              self.model.geom(SENSOR_EDGE_GEOM).id}
        self._surface_geom = self.model.geom(SURFACE_GEOM).id
        self._edge_body = self.model.body(frames.EDGE).id
        self._sensor_body = self.model.body(frames.SENSOR).id
        self._site = self.model.site(IMU_SITE).id
        self._samples_taken = 0
        self._sample_time_s = 0.0
        self._force = np.zeros(6)
        self._edge_velocity = np.zeros(6)
        self._cache: dict[str, Any] = {}
        self._inputs_read = frozenset().union(*(effect.reads for effect in self.effects))
        self.controller = None  # callable(time_s) -> joint targets, before every step
        for effect in self.effects:
            effect.after_compile(self.model, self.data)
        mujoco.mj_forward(self.model, self.data)

    # -- building -------------------------------------------------------------------
    def _surface_assets(self) -> str:
        surface = self.scene.surface
        if surface.kind == 'flat':
            return ''
        half_x, half_y = (s / 2 for s in surface.size_m)
        ncol, nrow = surface.cells
        return (f'<hfield name="surface" nrow="{nrow}" ncol="{ncol}" size="{half_x} {half_y} '
                f'{max(2 * surface.amplitude_m, 1e-6)} {surface.thickness_m}"/>')

    def _surface_geoms(self) -> str:
        surface = self.scene.surface
        x, y, z = surface.origin_m
        common = f'name="{SURFACE_GEOM}" rgba="0.55 0.45 0.35 1" friction="0.5 0.005 0.0001"'
        floor = '<light pos="0 0 1.5" dir="0 0 -1"/>'
        if surface.kind == 'flat':
            # Tilted about y through the top face's centre (slope_rad 0: level).
            half = f'{surface.size_m[0] / 2} {surface.size_m[1] / 2} {surface.thickness_m / 2}'
            slope = surface.slope_rad
            cx = x + math.sin(slope) * surface.thickness_m / 2
            cz = surface.top_z - math.cos(slope) * surface.thickness_m / 2
            return floor + (f'<geom {common} type="box" size="{half}" pos="{cx} {y} {cz}" '
                            f'quat="{math.cos(slope / 2)} 0 {-math.sin(slope / 2)} 0"/>')
        return floor + (f'<geom {common} type="hfield" hfield="surface" '
                        f'pos="{x} {y} {z + surface.thickness_m}"/>')

    def _fill_heightfield(self) -> None:
        surface = self.scene.surface
        ncol, nrow = surface.cells
        xs = surface.origin_m[0] + np.linspace(-surface.size_m[0] / 2, surface.size_m[0] / 2,
                                               ncol)
        heights = surface.height(xs) - (surface.top_z - surface.amplitude_m)
        normalised = np.clip(heights / max(2 * surface.amplitude_m, 1e-12), 0.0, 1.0)
        self.model.hfield_data[:] = np.tile(normalised, nrow)

    def set_patch_texture(self, name: str | None) -> None:
        """Give every patch the texture `name` (None: the scene's own), from the next sample.

        Raises:
            SimError: no texture of that name (the message names the known ones).
        """
        if name is not None:  # checked even where the scene has no patch to give it
            find_texture(name)
        patches = self.scene.patches if name is None else tuple(
            type(p)(name, p.x_m, p.y_m) for p in self.scene.patches)
        for patch in patches:
            find_texture(patch.texture)
        self._patches = patches

    # -- control ----------------------------------------------------------------------
    @property
    def time_s(self) -> float:
        """Simulated time (s)."""
        return float(self.data.time)

    def set_arm_targets(self, positions) -> None:
        """Position-servo goals of joint1..joint4 (rad) and the gripper (m)."""
        self.data.ctrl[:len(JOINT_STATE_NAMES)] = positions

    def place_arm(self, positions) -> None:
        """Put the arm at `positions` at rest (start of a run), its servos holding it.

        A servo holds its load by sagging until its error balances the load, and a real
        arm has long done so when its sensor stream starts. Put there with its joints
        still, the simulated arm would fall freely at first, and its accelerometer read
        about 0 instead of gravity (the attitude filter rejects such a sample). So the
        physics runs `SETTLE_S` with the servos holding `positions`, and the clock
        starts at 0 from there.
        """
        self.data.qpos[self._arm_qpos] = positions
        self.data.qvel[:] = 0.0
        self.set_arm_targets(positions)
        for _ in range(round(SETTLE_S / self.model.opt.timestep)):
            mujoco.mj_step(self.model, self.data)
        self.data.time = 0.0
        mujoco.mj_forward(self.model, self.data)

    def joint_positions(self) -> np.ndarray:
        """Present joint1..joint4 (rad) and gripper (m)."""
        return self.data.qpos[self._arm_qpos].copy()

    def joint_velocities(self) -> np.ndarray:
        """Present joint velocities."""
        return self.data.qvel[[self.model.joint(n).dofadr[0] for n in JOINT_STATE_NAMES]]

    def next_sample(self) -> Sample:
        """Step to the next sensor instant and return what the sensor reads there.

        The first sample is the initial state (time 0); sample k is taken at exactly
        k / sensor_rate_hz, `substeps` physics steps after the previous one.

        Raises:
            SimError: the physics diverged (MuJoCo found a non-finite or huge state and
                reset it) or the controller gave non-finite targets.
        """
        warnings = [self.data.warning[w].number for w in _DIVERGED]
        for _ in range(self.substeps if self._samples_taken else 0):
            if self.controller is not None:
                targets = np.asarray(self.controller(self.data.time), dtype=float)
                if not np.all(np.isfinite(targets)):
                    raise SimError(f'controller gave non-finite joint targets {targets!r} at '
                                   f't={self.data.time:.4f} s')
                self.set_arm_targets(targets)
            mujoco.mj_step(self.model, self.data)
        if [self.data.warning[w].number for w in _DIVERGED] != warnings:
            raise SimError(f'the physics diverged before t={self.data.time:.4f} s (a '
                           f'non-finite or huge state; MuJoCo reset it)')
        self._sample_time_s = sample_time_s = self._samples_taken * self.period_s
        self._samples_taken += 1
        sensordata = self.data.sensordata
        reading = Reading(sensordata[0:3].copy(), sensordata[3:6].copy())
        self._cache.clear()
        values = {name: self.input(name) for name in self._inputs_read}
        for effect in self.effects:
            effect.apply(reading, Inputs(**{name: values[name] for name in effect.reads}))
        truth = GroundTruth(sample_time_s, self.input('contact'),
                            self.data.xquat[self._sensor_body].copy(),
                            self.data.xpos[self._edge_body].copy(),
                            self._texture_name_at(self.data.xpos[self._edge_body]))
        return Sample(sample_time_s, reading.accel, reading.gyro, reading.mag,
                      reading.pressure, reading.temperature, truth)

    # -- inputs -----------------------------------------------------------------------
    def _texture_name_at(self, position) -> str:
        patch = next((p for p in self._patches if p.contains(position[0], position[1])), None)
        return '' if patch is None else patch.texture

    def input(self, key: str) -> Any:
        """An effect input at the present sample, computed once per sample.

        Raises:
            KeyError: no such input.
        """
        if key not in self._cache:
            self._cache[key] = self._compute(key)
        return self._cache[key]

    def _compute(self, key: str) -> Any:
        if key == 'contact':
            return self.contact()
        if key == 'edge_velocity':
            mujoco.mj_objectVelocity(self.model, self.data, mujoco.mjtObj.mjOBJ_BODY,
                                     self._edge_body, self._edge_velocity, 0)
            return self._edge_velocity[3:].copy()
        if key == 'texture':
            name = self._texture_name_at(self.input('contact').point) \
                if self.input('contact').touching else ''
            return find_texture(name) if name else None
        if key == 'sensor_rotation':
            return self.data.site_xmat[self._site].reshape(3, 3).copy()
        if key == 'sensor_position':
            return self.data.site_xpos[self._site].copy()
        if key == 'compression_m':
            if self._press is not None:
                return max(0.0, -float(self.data.qpos[self._press]))
            # Welded body: what the compliant one would compress under this force.
            return min(self.input('contact').force / PRESS_STIFFNESS_N_M, PRESS_TRAVEL_M)
        if key == 'time_s':
            return self._sample_time_s
        if key == 'sample_rate_hz':
            return self.scene.sensor_rate_hz
        if key == 'sensor_filters_hz':  # (accelerometer, gyro) low-pass cut-offs, Hz
            chip = next((e for e in self.effects if e.name == 'sensor'), None)
            return (math.inf, math.inf) if chip is None else chip.filters_hz
        raise KeyError(f'no input {key!r}')

    def contact(self) -> Contact:
        """The sensor's contact with the surface now (the deepest one)."""
        best = None
        for index in range(self.data.ncon):
            item = self.data.contact[index]
            pair = {int(item.geom1), int(item.geom2)}
            if self._surface_geom not in pair or not pair & self._sensor_geoms:
                continue
            if best is None or item.dist < best[1].dist:
                best = (index, item)
        if best is None:
            return NO_CONTACT
        index, item = best
        mujoco.mj_contactForce(self.model, self.data, index, self._force)
        normal = item.frame[:3].copy()
        if int(item.geom2) == self._surface_geom:
            normal = -normal
        return Contact(True, item.pos.copy(), normal, float(abs(self._force[0])))

