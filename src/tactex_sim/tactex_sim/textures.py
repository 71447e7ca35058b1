# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The 12 textures of the original as parametric surface models, and their profiles.

Each texture is a height field over the patch: ridges (period, height, direction), a
woven or meshed pattern (two periods, height), random roughness (rms, correlation
length) and friction, plus how soft it is (a soft fabric passes on less vibration).
Sliding at speed v over a spatial period p gives a temporal frequency v / p. Textures
that feel alike really are alike here: the two cotton weaves differ by a fraction of a
millimetre in period, mesh cotton and mesh leather in period, friction and softness.
"""

from __future__ import annotations

from dataclasses import dataclass
import math

import numpy as np

from tactex_sim.errors import UnknownNameError


@dataclass(frozen=True)
class Texture:
    """Surface model of one texture (lengths in m)."""

    name: str
    ridge_period: float = 0.0
    ridge_height: float = 0.0
    ridge_angle: float = 0.0  # direction of the ridge crests, rad, in the patch frame
    weave_period: tuple[float, float] = (0.0, 0.0)
    weave_height: float = 0.0
    roughness_rms: float = 0.0
    roughness_length: float = 0.0005
    friction: float = 0.5
    softness: float = 1.0  # 1: hard; lower: the material damps what it transmits

    def waves(self) -> list[tuple[float, np.ndarray, float]]:
        """The periodic part of the height: (amplitude m, wavevector rad/m, phase rad) terms.

        Height = sum of amplitude * cos(k . uv + phase) over the terms. Rounded ridges are
        a sine with its second harmonic; a weave sin(a u) sin(b v) is two plane waves.
        """
        terms = []
        if self.ridge_period > 0:
            k = 2 * math.pi / self.ridge_period * np.array(
                [math.cos(self.ridge_angle), math.sin(self.ridge_angle)])
            terms += [(0.8 * self.ridge_height, k, -math.pi / 2),
                      (0.2 * self.ridge_height, 2 * k, -math.pi / 2)]
        if self.weave_height > 0:
            a, b = (2 * math.pi / p for p in self.weave_period)
            terms += [(0.5 * self.weave_height, np.array([a, -b]), 0.0),
                      (-0.5 * self.weave_height, np.array([a, b]), 0.0)]
        return terms

    def profile(self, start_uv: tuple[float, float], heading_rad: float, length_m: float,
                step_m: float, rng: np.random.Generator) -> np.ndarray:
        """Heights (m) along a straight path in the patch frame, `step_m` apart.

        Args:
            start_uv: path start in the patch frame (m).
            heading_rad: path direction in the patch frame.
            length_m: path length.
            step_m: sample spacing along the path.
            rng: source of this path's roughness.
        """
        s = np.arange(0.0, length_m + step_m, step_m)
        u = start_uv[0] + s * math.cos(heading_rad)
        v = start_uv[1] + s * math.sin(heading_rad)
        height = np.zeros_like(s)
        for amplitude, k, phase in self.waves():
            height += amplitude * np.cos(k[0] * u + k[1] * v + phase)
        if self.roughness_rms > 0:
            height += _rough(s.size, step_m, self.roughness_rms, self.roughness_length, rng)
        return height


def _rough(count: int, step_m: float, rms: float, length_m: float,
           rng: np.random.Generator) -> np.ndarray:
    """Gaussian-correlated random heights with the given rms and correlation length."""
    white = rng.standard_normal(count)
    frequencies = np.fft.rfftfreq(count, step_m)
    shaped = np.fft.irfft(np.fft.rfft(white) * np.exp(-(math.pi * frequencies * length_m) ** 2),
                          count)
    std = float(np.std(shaped))
    return shaped * (rms / std) if std > 0 else shaped


TEXTURES: dict[str, Texture] = {t.name: t for t in (
    Texture('brocade fabric', weave_period=(0.0016, 0.0011), weave_height=60e-6,
            ridge_period=0.0048, ridge_height=25e-6, ridge_angle=0.6,
            roughness_rms=14e-6, roughness_length=0.0003, friction=0.6, softness=0.7),
    Texture('open weave cotton', weave_period=(0.0012, 0.0012), weave_height=75e-6,
            roughness_rms=11e-6, roughness_length=0.0003, friction=0.55, softness=0.6),
    Texture('tight weave cotton', weave_period=(0.0010, 0.0010), weave_height=62e-6,
            roughness_rms=11e-6, roughness_length=0.0003, friction=0.55, softness=0.6),
    Texture('mesh cotton', weave_period=(0.0021, 0.0021), weave_height=95e-6,
            roughness_rms=12e-6, roughness_length=0.0004, friction=0.5, softness=0.62),
    Texture('honeycomb fabric', weave_period=(0.0030, 0.0026), weave_height=110e-6,
            ridge_period=0.0015, ridge_height=30e-6, ridge_angle=1.05,
            roughness_rms=10e-6, friction=0.5, softness=0.65),
    Texture('embossed plastic', weave_period=(0.0025, 0.0025), weave_height=140e-6,
            roughness_rms=5e-6, roughness_length=0.0002, friction=0.35, softness=1.0),
    Texture('wood', ridge_period=0.0008, ridge_height=18e-6, ridge_angle=0.0,
            roughness_rms=25e-6, roughness_length=0.0015, friction=0.4, softness=1.0),
    Texture('silicone mesh', weave_period=(0.0040, 0.0040), weave_height=280e-6,
            roughness_rms=8e-6, friction=0.9, softness=0.5),
    Texture('reptile-patterned leather', weave_period=(0.0050, 0.0038), weave_height=120e-6,
            roughness_rms=20e-6, roughness_length=0.0006, friction=0.6, softness=0.8),
    Texture('ridged polymer', ridge_period=0.0018, ridge_height=190e-6, ridge_angle=0.0,
            roughness_rms=5e-6, friction=0.35, softness=1.0),
    Texture('mesh leather', weave_period=(0.0023, 0.0022), weave_height=100e-6,
            roughness_rms=15e-6, roughness_length=0.0004, friction=0.58, softness=0.72),
    Texture('carpet wool', weave_period=(0.0030, 0.0030), weave_height=70e-6,
            roughness_rms=140e-6, roughness_length=0.0010, friction=0.7, softness=0.4),
)}


def texture(name: str) -> Texture:
    """The texture called `name`.

    Raises:
        UnknownNameError: not one of the 12; the message lists them.
    """
    try:
        return TEXTURES[name]
    except KeyError:
        raise UnknownNameError(f'unknown texture {name!r}; known: '
                               f'{", ".join(TEXTURES)}') from None
