# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Simulation effects: small units a scene switches on by name, each computed only then.

An effect declares the inputs it reads (fields of `tactex_sim.inputs.Inputs`, checked
when its class is defined) and the channels or model parts it writes. At each sample the
world computes the inputs that enabled effects declare and gives each effect an `Inputs`
with only its own filled (a test holds every effect's uses to its declarations); it
builds the collisions only if an enabled effect writes
`contact` and the compliant joints only if one writes `sensor pose`; the channels no
enabled effect writes stay NaN (a test holds every effect to its `writes`). Hooks:
`after_compile(model, data)` once, and `apply(reading, inputs)` at every sensor sample.
Options come from the scene's `[effect.NAME]` table and are checked by name and by value
against each effect's `defaults` table of `Option`s (default and accepted range). Enabled
effects run in registry order (`EFFECTS`), whatever order the scene lists them in.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
import math
from typing import Any, ClassVar

import mujoco
import numpy as np

from tactex_common import chips
from tactex_common.constants import EARTH_FIELD_T, SEA_LEVEL_PRESSURE_PA
from tactex_common.numbers import is_finite_number
from tactex_description import edge
from tactex_sim import vibration
from tactex_sim.errors import SceneError, UnknownNameError
from tactex_sim.inputs import INPUT_NAMES, Inputs
from tactex_sim.textures import Texture


class Reading:
    """One sensor sample being built, in the sensor frame and SI units.

    accel (m/s^2), gyro (rad/s), mag (T), pressure (Pa), temperature (degC); channels
    that no effect simulates stay NaN.
    """

    __slots__ = ('accel', 'gyro', 'mag', 'pressure', 'temperature')

    def __init__(self, accel: np.ndarray, gyro: np.ndarray) -> None:
        self.accel = accel
        self.gyro = gyro
        self.mag = np.full(3, np.nan)
        self.pressure = math.nan
        self.temperature = math.nan


@dataclass(frozen=True)
class Option:
    """One effect option: its default and the values it accepts.

    Numbers must be finite and within [low, high], or one of `choices` when it names
    some (a chip's selectable ranges); a divisor's `low` is a physical minimum above 0 (a
    subnormal divisor overflows); a vector option (a tuple default) takes as many finite
    numbers, each in the range.
    """

    default: float | tuple[float, ...]
    low: float = -math.inf
    high: float = math.inf
    choices: tuple[float, ...] = ()

    def check(self, effect: str, name: str, value: Any) -> float | tuple[float, ...]:
        """The value as float(s).

        Raises:
            SceneError: wrong type, length, not finite or out of range; names the option.
        """
        where = f'effect {effect!r}: option {name}'
        vector = isinstance(self.default, tuple)
        items = value if vector and isinstance(value, (list, tuple)) else [value]
        if vector and (not isinstance(value, (list, tuple)) or len(value) != len(self.default)):
            raise SceneError(f'{where} must be a list of {len(self.default)} numbers, got '
                             f'{value!r}')
        for item in items:
            if not is_finite_number(item):
                raise SceneError(f'{where} must be a finite number, got {value!r}')
            if not self.low <= item <= self.high or (self.choices
                                                     and item not in self.choices):
                raise SceneError(f'{where} must be in {self.describe()}, got {value!r}')
        return tuple(float(v) for v in items) if vector else float(value)

    def describe(self) -> str:
        """The accepted values, as an interval or a set."""
        if self.choices:
            return '{' + ', '.join(f'{c:g}' for c in self.choices) + '}'
        return f'[{self.low:g}, {self.high:g}]'


class Effect:
    """Base of all effects: options, declared inputs and outputs, no-op hooks."""

    name: ClassVar[str] = ''
    reads: ClassVar[frozenset[str]] = frozenset()  # fields of tactex_sim.inputs.Inputs
    writes: ClassVar[frozenset[str]] = frozenset()
    defaults: ClassVar[Mapping[str, Option]] = {}

    def __init_subclass__(cls, **kwargs: Any) -> None:
        """Refuse, when the class is defined, an input the world does not provide."""
        super().__init_subclass__(**kwargs)
        unknown = sorted(cls.reads - INPUT_NAMES)
        if unknown:
            raise TypeError(f'effect {cls.name!r} reads {unknown}, which the world does not '
                            f'provide; it provides {sorted(INPUT_NAMES)}')

    def __init__(self, rng: np.random.Generator, noise_scale: float = 1.0,
                 **options: Any) -> None:
        unknown = sorted(set(options) - set(self.defaults))
        if unknown:
            raise SceneError(f'effect {self.name!r}: unknown option(s) {unknown}; known: '
                             f'{sorted(self.defaults)}')
        if not (math.isfinite(noise_scale) and noise_scale >= 0.0):
            raise SceneError(f'effect {self.name!r}: noise_scale must be finite and >= 0, '
                             f'got {noise_scale!r}')
        self.options = {name: option.check(self.name, name, options.get(name, option.default))
                        for name, option in self.defaults.items()}
        self.rng = rng
        self.noise_scale = noise_scale

    def after_compile(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Called once the model exists."""

    def apply(self, reading: Reading, inputs: Inputs) -> None:
        """Called at every sensor sample."""


class Contact(Effect):
    """Rigid contact between the sensor and the surface (off: they pass through)."""

    name = 'contact'
    writes = frozenset({'contact'})


class Compliance(Effect):
    """The compliant sensor body: 3 revolute + 1 prismatic joints with stiffness, damping.

    Without it the sensor is welded to its mount (the model is built that way).
    """

    name = 'compliance'
    writes = frozenset({'sensor pose'})


# Slower than this the edge creeps rather than slides: no texture signal.
SLIDING_SPEED_M_S = 1e-4
# The texture model holds up to this sliding speed; faster (a diverging or flung arm)
# vibrates as at this speed, so the channels stay finite.
MAX_SLIDING_SPEED_M_S = 2.0
# The footprint follows the contact force within these bounds (N); beyond, as at them.
FOOTPRINT_FORCE_RANGE_N = (0.01, 100.0)


class TextureVibration(Effect):
    """Vibration and rocking of the body as its edge slides over the texture.

    The edge rides the texture's height as its footprint feels it (tactex_sim.vibration:
    periodic waves through the footprint's sinc, roughness through a moving mean), and
    the body answers through its own dynamics (tactex_description.edge):
    - normal acceleration: the second time derivative of that height, v^2 times its
      curvature along the path, through the normal resonance (`resonance_hz`,
      `damping_ratio`);
    - rocking: a rise of the edge pitches the body about n x d by `rocking_per_m` rad per
      metre (the share of the rise its pitch compliance takes, over the pivot-to-edge
      distance), so the gyro reads that times v times the footprint-averaged slope,
      through the rocking resonance (`rocking_resonance_hz`, `rocking_damping_ratio`);
    - tangential acceleration: friction follows the normal force (Amontons), so the
      normal acceleration times the friction coefficient, plus stick-slip on sticky
      materials (a sawtooth every `slip_length_m` of travel, `stick_slip_accel` at the
      reference force, growing with force and friction).
    Every factor is dimensionless or converts between the units it says; nothing carries
    an acceleration gain onto an angular rate. The footprint grows with force as
    force^(1/3) (Hertz). With the `sensor` effect, each wave is also attenuated by the
    chip's digital low-pass at its frequency. A soft material (`softness` < 1) passes on
    less. No contact or no sliding: no signal.

    Not modelled: the phase of the resonances (magnitudes only), lateral (across-path)
    rocking, force-dependence of the roughness's footprint (taken at the reference force),
    friction-induced rocking, and material damping beyond `softness`. Checked for order
    of magnitude against rigid-tool recordings (Romano and Kuchenbecker 2012) and
    fingertip-sensor recordings (Fishel and Loeb 2012), which grow with speed and force
    as this does; a compliant cast body passes on less than a rigid tool. `tactex sim
    stats` compares the result with a real module's recordings channel by channel.
    """

    name = 'texture'
    reads = frozenset({'contact', 'edge_velocity', 'texture', 'sensor_rotation', 'sample_rate_hz',
                       'sensor_filters_hz'})
    writes = frozenset({'accel', 'gyro'})
    defaults = {'resonance_hz': Option(edge.normal_resonance_hz(), 1.0, 1e4),
                'damping_ratio': Option(edge.SKIN_DAMPING_RATIO, 0.01, 10.0),
                'rocking_resonance_hz': Option(edge.rocking_resonance_hz(), 1.0, 1e4),
                'rocking_damping_ratio': Option(edge.SKIN_DAMPING_RATIO, 0.01, 10.0),
                'rocking_per_m': Option(edge.rocking_per_metre(), 0.0, 1e3),
                'contact_length_m': Option(edge.footprint_m()[0], 1e-6, 0.1),
                'contact_width_m': Option(edge.footprint_m()[1], 1e-6, 0.1),
                'reference_force_n': Option(edge.REFERENCE_FORCE_N, 1e-3, 1e3),
                'heading_rad': Option(0.0),
                'slip_length_m': Option(0.0004, 1e-6, 1.0),
                'stick_slip_accel': Option(1.5, 0.0, 1e3)}

    def __init__(self, rng, noise_scale=1.0, **options) -> None:
        super().__init__(rng, noise_scale, **options)
        self.heading_rad = float(self.options['heading_rad'])
        self._travelled = 0.0
        self._roughness: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        self._wave_terms: dict[str, list[tuple[float, float, float, float]]] = {}
        self._mass_kg = edge.body_mass_kg()

    def _waves(self, surface: Texture) -> list[tuple[float, float, float, float]]:
        """The texture's height waves as floats: (amplitude m, k_u, k_v rad/m, phase rad)."""
        if surface.name not in self._wave_terms:
            self._wave_terms[surface.name] = [(float(a), float(k[0]), float(k[1]), float(p))
                                              for a, k, p in surface.waves()]
        return self._wave_terms[surface.name]

    def _footprint_roughness(self, surface: Texture) -> tuple[np.ndarray, np.ndarray]:
        """(slope, curvature) of a 1 m random profile as the footprint feels it (cached)."""
        if surface.name not in self._roughness:
            step = vibration.ROUGHNESS_STEP_M
            rough_only = Texture(surface.name, roughness_rms=surface.roughness_rms,
                                 roughness_length=surface.roughness_length)
            heights = rough_only.profile((0.0, 0.0), 0.0, 1.0, step, self.rng)
            self._roughness[surface.name] = vibration.footprint_roughness(
                heights, step, self.options['contact_length_m'],
                self.options['contact_width_m'], surface.roughness_length)
        return self._roughness[surface.name]

    def apply(self, reading: Reading, inputs: Inputs) -> None:
        """Add the texture's vibration and rocking while the edge slides on a patch."""
        contact = inputs.contact
        surface = inputs.texture if contact.touching else None
        if surface is None:
            return
        velocity = inputs.edge_velocity
        largest = float(np.max(np.abs(velocity)))
        if largest > MAX_SLIDING_SPEED_M_S:  # flung: keep the direction, cap the speed
            velocity = velocity * (MAX_SLIDING_SPEED_M_S / largest)
        normal = contact.normal
        tangential = velocity - np.dot(velocity, normal) * normal
        speed = float(np.linalg.norm(tangential))
        if speed < SLIDING_SPEED_M_S:
            return
        direction = tangential / speed
        speed = min(speed, MAX_SLIDING_SPEED_M_S)
        self._travelled += speed / inputs.sample_rate_hz
        options = self.options
        force = min(max(contact.force, FOOTPRINT_FORCE_RANGE_N[0]), FOOTPRINT_FORCE_RANGE_N[1])
        relative_force = force / options['reference_force_n']
        grow = relative_force ** (1.0 / 3.0)
        length, width = options['contact_length_m'] * grow, options['contact_width_m'] * grow
        accel_cutoff, gyro_cutoff = inputs.sensor_filters_hz
        cos_h, sin_h = math.cos(self.heading_rad), math.sin(self.heading_rad)
        x, y = float(contact.point[0]), float(contact.point[1])
        u, v = cos_h * x + sin_h * y, -sin_h * x + cos_h * y
        dx, dy = float(direction[0]), float(direction[1])
        du, dv = cos_h * dx + sin_h * dy, -sin_h * dx + cos_h * dy
        curvature_term = slope_term = 0.0  # through the normal and rocking dynamics
        for amplitude, ku, kv, phase in self._waves(surface):
            k_along, k_across = ku * du + kv * dv, kv * du - ku * dv
            felt = amplitude * vibration.footprint_gain(k_along, k_across, length, width)
            frequency = speed * abs(k_along) / (2 * math.pi)
            angle = ku * u + kv * v + phase
            curvature_term -= (felt * k_along * k_along * math.cos(angle)
                               * vibration.transmissibility(frequency, options['resonance_hz'],
                                                            options['damping_ratio'])
                               * chips.first_order_gain(frequency, accel_cutoff))
            slope_term -= (felt * k_along * math.sin(angle)
                           * vibration.transmissibility(frequency,
                                                        options['rocking_resonance_hz'],
                                                        options['rocking_damping_ratio'])
                           * chips.first_order_gain(frequency, gyro_cutoff))
        rough_slope, rough_curvature = self._footprint_roughness(surface)
        index = int(self._travelled / vibration.ROUGHNESS_STEP_M) % rough_slope.size
        curvature_term += float(rough_curvature[index])
        slope_term += float(rough_slope[index])
        # The edge follows the texture only while its contact force can pull it down.
        reach = contact.force / self._mass_kg
        normal_accel = min(max(surface.softness * speed * speed * curvature_term, -reach), reach)
        rocking = surface.softness * options['rocking_per_m'] * speed * slope_term
        stickiness = max(0.0, surface.friction - 0.45) * min(1.5, speed / 0.015)
        slip_phase = (self._travelled / options['slip_length_m']) % 1.0
        tangential_accel = surface.friction * normal_accel + surface.softness * min(
            2.0, relative_force) * options['stick_slip_accel'] * stickiness * (slip_phase - 0.5)
        rotation = inputs.sensor_rotation  # world <- sensor
        reading.accel += rotation.T @ (normal_accel * normal + tangential_accel * direction)
        reading.gyro += rotation.T @ (rocking * _cross(normal, direction))


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The cross product of two 3-vectors (np.cross costs far more per sample)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]])


class ImuNoise(Effect):
    """White noise and a constant bias (drawn per world) on accel and gyro.

    The gyro's noise by default is the LSM9DS0's rate noise density behind its 100 Hz
    cut-off (tactex_common.chips); the datasheet gives no accelerometer noise density,
    so `accel_sd` (2 mg) is an assumption.
    """

    name = 'imu_noise'
    writes = frozenset({'accel', 'gyro'})
    defaults = {'accel_sd': Option(0.02, 0.0, 100.0),
                'gyro_sd': Option(chips.GYRO_NOISE_SD_RAD_S, 0.0, 10.0),
                'accel_bias_sd': Option(0.05, 0.0, 100.0),
                'gyro_bias_sd': Option(0.005, 0.0, 10.0)}

    def __init__(self, rng, noise_scale=1.0, **options) -> None:
        super().__init__(rng, noise_scale, **options)
        self.accel_bias = rng.normal(0.0, self.options['accel_bias_sd'], 3)
        self.gyro_bias = rng.normal(0.0, self.options['gyro_bias_sd'], 3)

    def apply(self, reading: Reading, inputs: Inputs) -> None:
        """Add bias and noise."""
        reading.accel += self.accel_bias + self.rng.normal(
            0.0, self.options['accel_sd'] * self.noise_scale, 3)
        reading.gyro += self.gyro_bias + self.rng.normal(
            0.0, self.options['gyro_sd'] * self.noise_scale, 3)


# Farther than this on some axis, a magnet's dipole is computed as at this distance
# (1e-16 T or less per A m^2).
FAR_FROM_MAGNET_M = 1e3


class Magnetometer(Effect):
    """Earth's field plus a nearby magnet's dipole field, in the sensor frame, with noise.

    Closer to the magnet's centre than `magnet_radius_m` (inside the magnet, where the
    dipole law does not hold), the field is that at the radius, so it stays finite;
    farther than FAR_FROM_MAGNET_M, that at FAR_FROM_MAGNET_M in the same direction.
    """

    name = 'magnetometer'
    reads = frozenset({'sensor_rotation', 'sensor_position'})
    writes = frozenset({'mag'})
    defaults = {'earth_field_t': Option(EARTH_FIELD_T, -1e-2, 1e-2),
                'magnet_position_m': Option((0.35, 0.25, 0.05), -100.0, 100.0),
                'magnet_moment_am2': Option((0.0, 0.0, 0.5), -1e4, 1e4),
                'magnet_radius_m': Option(0.005, 1e-4, 1.0),
                'noise_sd_t': Option(2.0e-7, 0.0, 1e-2)}

    def apply(self, reading: Reading, inputs: Inputs) -> None:
        """Field at the sensor, rotated into its frame."""
        offset = inputs.sensor_position - np.asarray(self.options['magnet_position_m'])
        largest = float(np.max(np.abs(offset)))
        if largest > FAR_FROM_MAGNET_M:  # same direction, no overflow
            offset = offset * (FAR_FROM_MAGNET_M / largest)
        norm = float(np.linalg.norm(offset))
        moment = np.asarray(self.options['magnet_moment_am2'], dtype=float)
        unit = offset / norm if norm > 0.0 else np.array([0.0, 0.0, 1.0])
        distance = max(norm, self.options['magnet_radius_m'])
        dipole = 1e-7 * (3.0 * np.dot(moment, unit) * unit - moment) / distance ** 3
        field = np.asarray(self.options['earth_field_t'], dtype=float) + dipole
        reading.mag = inputs.sensor_rotation.T @ field + self.rng.normal(
            0.0, self.options['noise_sd_t'] * self.noise_scale, 3)


class Barometer(Effect):
    """Pressure from the compression of the compliant body, slow thermal drift, noise."""

    name = 'barometer'
    reads = frozenset({'compression_m', 'time_s'})
    writes = frozenset({'pressure', 'temperature'})
    defaults = {'sea_level_pa': Option(SEA_LEVEL_PRESSURE_PA, 1.0, 1e7),
                'pa_per_m_compression': Option(1.5e6, 0.0, 1e9),
                'noise_sd_pa': Option(2.0, 0.0, 1e5),
                'drift_pa_per_s': Option(0.0, -1e4, 1e4),
                'temperature_c': Option(24.0, -273.15, 1000.0)}

    def apply(self, reading: Reading, inputs: Inputs) -> None:
        """Compression raises the pressure inside the cast body."""
        t = inputs.time_s
        reading.pressure = (self.options['sea_level_pa']
                            + self.options['pa_per_m_compression'] * inputs.compression_m
                            + self.options['drift_pa_per_s'] * t
                            + self.rng.normal(0.0, self.options['noise_sd_pa']
                                              * self.noise_scale))
        reading.temperature = self.options['temperature_c'] + 0.002 * t


class SensorChips(Effect):
    """What the LSM9DS0 and the MPL115A2 make of the physical signal (tactex_common.chips).

    Accelerometer, gyro and magnetometer: the configured full scale, each axis a whole
    16-bit count and held at the rails as the chip saturates; the magnetometer updates at
    its 100 Hz output data rate (a faster stream repeats its last value). The gyro's
    100 Hz digital low-pass and the accelerometer's 194 Hz anti-alias filter act on the
    texture's vibration (the `texture` effect reads them as `sensor filters`); the
    380/400 Hz output data rates of those two are faster than any stream rate and not
    modelled. Barometer: the reading belongs to the start of its 1.6 ms conversion
    (interpolated back from this sample), carries `pressure_noise_pa` of white noise (the
    datasheet states a 0.15 kPa resolution, about two 10-bit codes, and no noise figure:
    one code by default) and is a 10-bit code over 50-115 kPa, held at those ends.
    Channels no other effect simulates stay NaN. A scene gets it only by declaring `sensor`.
    """

    name = 'sensor'
    reads = frozenset({'time_s'})
    writes = frozenset({'accel', 'gyro', 'mag', 'pressure'})
    defaults = {'accel_range_g': Option(float(chips.ACCEL_RANGE_G),
                                        choices=tuple(map(float, chips.ACCEL_RANGES))),
                'gyro_range_dps': Option(float(chips.GYRO_RANGE_DPS),
                                         choices=tuple(map(float, chips.GYRO_RANGES))),
                'mag_range_gauss': Option(float(chips.MAG_RANGE_GAUSS),
                                          choices=tuple(map(float, chips.MAG_RANGES))),
                'pressure_noise_pa': Option(chips.PRESSURE_LSB_PA, 0.0, 1e4)}

    def __init__(self, rng, noise_scale=1.0, **options) -> None:
        super().__init__(rng, noise_scale, **options)
        self.accel = chips.accel_range(self.options['accel_range_g'])
        self.gyro = chips.gyro_range(self.options['gyro_range_dps'])
        self.mag = chips.mag_range(self.options['mag_range_gauss'])
        self._mag_tick = -1
        self._mag_held = np.full(3, np.nan)
        self._last_pressure: tuple[float, float] | None = None

    @property
    def filters_hz(self) -> tuple[float, float]:
        """Cut-offs (accelerometer, gyro) of the chip's filters."""
        return chips.ACCEL_BANDWIDTH_HZ, chips.GYRO_CUTOFF_HZ

    def apply(self, reading: Reading, inputs: Inputs) -> None:
        """Saturate and quantise each channel as the chips report it."""
        t = inputs.time_s
        reading.accel = chips.quantise(reading.accel, self.accel.lsb_si)
        reading.gyro = chips.quantise(reading.gyro, self.gyro.lsb_si)
        tick = math.floor(t * chips.MAG_ODR_HZ + 1e-9)
        if tick != self._mag_tick:
            self._mag_tick = tick
            self._mag_held = chips.quantise(reading.mag, self.mag.lsb_si)
        reading.mag = self._mag_held.copy()
        pressure = reading.pressure
        if math.isnan(pressure):
            return
        reported = pressure
        if self._last_pressure is not None and t > self._last_pressure[0]:
            before_t, before = self._last_pressure
            back = min(1.0, chips.PRESSURE_CONVERSION_S / (t - before_t))
            reported = pressure - back * (pressure - before)
        self._last_pressure = (t, pressure)
        noisy = reported + self.rng.normal(0.0, self.options['pressure_noise_pa']
                                           * self.noise_scale)
        reading.pressure = float(chips.quantise_pressure(noisy))


EFFECTS: dict[str, type[Effect]] = {cls.name: cls for cls in (
    Contact, Compliance, TextureVibration, ImuNoise, Magnetometer, Barometer, SensorChips)}


def effect_class(name: str) -> type[Effect]:
    """The effect registered as `name`.

    Raises:
        UnknownNameError: unknown name; the message lists the registered effects.
    """
    try:
        return EFFECTS[name]
    except KeyError:
        raise UnknownNameError(f'unknown effect {name!r}; known effects: '
                               f'{", ".join(EFFECTS)}') from None

