# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The simulator core: arm + surface in MuJoCo, stepped from Python, sampled like the sensor.

`World(scene)` builds only what the scene's effects call for (the compliant joints, the
collision of sensor and surface), steps the physics at the scene's timestep, and every
sensor period returns a reading (accel, gyro from MuJoCo's site sensors; the rest from
the effects; NaN where no effect simulates a channel) with the ground truth: contact
point, surface normal and force, the attitude of `sensor_link`, the texture under the
edge. Inputs of the effects are computed only when an enabled effect asks for them.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
import math
from typing import Any

import mujoco
import numpy as np

from tactex_description.geometry import JOINT_STATE_NAMES, OPEN_MANIPULATOR_X
from tactex_description.mjcf import build_mjcf, IMU_SITE, SENSOR_EDGE_GEOM, SENSOR_GEOM
from tactex_sim.effects import Effect, effect_class, Reading
from tactex_sim.scene import Scene
from tactex_sim.textures import texture as find_texture

SURFACE_GEOM = 'surface'
PRESS_STIFFNESS_N_M = OPEN_MANIPULATOR_X.joint('sensor_press').stiffness


@dataclass(frozen=True)
class Contact:
    """Contact of the sensor with the surface (normal points out of the surface)."""

    touching: bool
    point: np.ndarray
    normal: np.ndarray
    force: float


NO_CONTACT = Contact(False, np.full(3, np.nan), np.full(3, np.nan), 0.0)


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


class _Inputs(Mapping):
    """Effect inputs, each computed on first use within one sample."""

    def __init__(self, world: World) -> None:
        self._world = world
        self._cache: dict[str, Any] = {}

    def __getitem__(self, key: str) -> Any:
        if key not in self._cache:
            self._cache[key] = self._world._input(key)  # noqa: SLF001 - the world's helper
        return self._cache[key]

    def __iter__(self):
        return iter(self._cache)

    def __len__(self) -> int:
        return len(self._cache)


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
        if patch_texture is not None:
            find_texture(patch_texture)
            self._patches = tuple(type(p)(patch_texture, p.x_m, p.y_m) for p in scene.patches)
        for patch in self._patches:
            find_texture(patch.texture)
        self.effects: list[Effect] = []
        for name in scene.effects:
            options = dict(scene.effect_options.get(name, {}))
            if name == 'texture':
                options.setdefault('heading_rad', texture_heading_rad)
            if name == 'barometer':
                options.setdefault('drift_pa_per_s', drift_pa_per_s)
            self.effects.append(effect_class(name)(self.rng, noise_scale, **options))
        enabled = {e.name for e in self.effects}
        self.model = mujoco.MjModel.from_xml_string(build_mjcf(
            timestep_s=scene.timestep_s, compliant='compliance' in enabled,
            assets_xml=self._surface_assets(), worldbody_xml=self._surface_geoms(),
            sensors_xml=f'<accelerometer name="accel" site="{IMU_SITE}"/>'
                        f'<gyro name="gyro" site="{IMU_SITE}"/>'))
        if scene.surface.kind == 'uneven':
            self._fill_heightfield()
        if 'contact' not in enabled:
            self.model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
        self.data = mujoco.MjData(self.model)
        self._arm_qpos = [self.model.joint(n).qposadr[0] for n in JOINT_STATE_NAMES]
        self._press = (self.model.joint('sensor_press').qposadr[0]
                       if 'compliance' in enabled else None)
        self._sensor_geoms = {self.model.geom(SENSOR_GEOM).id,
                              self.model.geom(SENSOR_EDGE_GEOM).id}
        self._surface_geom = self.model.geom(SURFACE_GEOM).id
        self._edge_body = self.model.body('sensor_edge').id
        self._sensor_body = self.model.body('sensor_link').id
        self._site = self.model.site(IMU_SITE).id
        self.period_s = 1.0 / scene.sensor_rate_hz
        self._next_sample_s = 0.0
        self._force = np.zeros(6)
        self._edge_velocity = np.zeros(6)
        self._inputs: _Inputs | None = None
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

    # -- control ----------------------------------------------------------------------
    @property
    def time_s(self) -> float:
        """Simulated time (s)."""
        return float(self.data.time)

    def set_arm_targets(self, positions) -> None:
        """Position-servo goals of joint1..joint4 (rad) and the gripper (m)."""
        self.data.ctrl[:len(JOINT_STATE_NAMES)] = positions

    def place_arm(self, positions) -> None:
        """Put the arm at `positions` at rest (start of a run)."""
        self.data.qpos[self._arm_qpos] = positions
        self.data.qvel[:] = 0.0
        self.set_arm_targets(positions)
        mujoco.mj_forward(self.model, self.data)

    def joint_positions(self) -> np.ndarray:
        """Present joint1..joint4 (rad) and gripper (m)."""
        return self.data.qpos[self._arm_qpos].copy()

    def joint_velocities(self) -> np.ndarray:
        """Present joint velocities."""
        return self.data.qvel[[self.model.joint(n).dofadr[0] for n in JOINT_STATE_NAMES]]

    def next_sample(self) -> Sample:
        """Step to the next sensor instant and return what the sensor reads there."""
        while self.data.time + 0.5 * self.model.opt.timestep < self._next_sample_s:
            if self.controller is not None:
                self.set_arm_targets(self.controller(self.data.time))
            mujoco.mj_step(self.model, self.data)
        self._next_sample_s += self.period_s
        sensordata = self.data.sensordata
        reading = Reading(sensordata[0:3].copy(), sensordata[3:6].copy())
        self._inputs = _Inputs(self)
        for effect in self.effects:
            effect.apply(reading, self._inputs)
        truth = GroundTruth(self.time_s, self._inputs['contact'],
                            self.data.xquat[self._sensor_body].copy(),
                            self.data.xpos[self._edge_body].copy(),
                            self._texture_name_at(self.data.xpos[self._edge_body]))
        return Sample(self.time_s, reading.accel, reading.gyro, reading.mag, reading.pressure,
                      reading.temperature, truth)

    # -- inputs -----------------------------------------------------------------------
    def _texture_name_at(self, position) -> str:
        patch = next((p for p in self._patches if p.contains(position[0], position[1])), None)
        return '' if patch is None else patch.texture

    def _input(self, key: str) -> Any:
        if key == 'contact':
            return self.contact()
        if key == 'edge velocity':
            mujoco.mj_objectVelocity(self.model, self.data, mujoco.mjtObj.mjOBJ_BODY,
                                     self._edge_body, self._edge_velocity, 0)
            return self._edge_velocity[3:].copy()
        if key == 'texture':
            name = self._texture_name_at(self._inputs['contact'].point) \
                if self._inputs['contact'].touching else ''
            return find_texture(name) if name else None
        if key == 'sensor rotation':
            return self.data.site_xmat[self._site].reshape(3, 3).copy()
        if key == 'sensor position':
            return self.data.site_xpos[self._site].copy()
        if key == 'compression':
            if self._press is not None:
                return max(0.0, -float(self.data.qpos[self._press]))
            # Welded body: what the compliant one would compress under this force.
            return self._inputs['contact'].force / PRESS_STIFFNESS_N_M
        if key == 'time':
            return self.time_s
        if key == 'sample rate':
            return self.scene.sensor_rate_hz
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

