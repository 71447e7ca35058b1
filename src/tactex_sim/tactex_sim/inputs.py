# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What the world gives an effect at each sensor sample: one typed, frozen record.

An effect declares the fields it reads (`Effect.reads`, checked against `INPUT_NAMES`
when the effect's class is defined) and gets an `Inputs` with those fields filled, the
others None.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from tactex_sim.textures import Texture


@dataclass(frozen=True)
class Contact:
    """Contact of the sensor with the surface (normal points out of the surface)."""

    touching: bool
    point: np.ndarray
    normal: np.ndarray
    force: float


NO_CONTACT = Contact(False, np.full(3, np.nan), np.full(3, np.nan), 0.0)


@dataclass(frozen=True)
class Inputs:
    """The world's state at one sensor sample, as effects read it (SI units, world frame).

    Attributes:
        contact: the sensor's deepest contact with the surface.
        edge_velocity: linear velocity of the sensor's edge (m/s).
        texture: the texture under the contact point (None off the patches or without
            contact).
        sensor_rotation: world <- sensor rotation matrix of the IMU site.
        sensor_position: position of the IMU site (m).
        compression_m: how far the compliant body is pressed in (m).
        time_s: the sample's time.
        sample_rate_hz: the sensor's sample rate.
        sensor_filters_hz: the chips' (accelerometer, gyro) low-pass cut-offs; (inf,
            inf) without the `sensor` effect.
    """

    contact: Contact | None = None
    edge_velocity: np.ndarray | None = None
    texture: Texture | None = None
    sensor_rotation: np.ndarray | None = None
    sensor_position: np.ndarray | None = None
    compression_m: float | None = None
    time_s: float | None = None
    sample_rate_hz: float | None = None
    sensor_filters_hz: tuple[float, float] | None = None


INPUT_NAMES = frozenset(field.name for field in fields(Inputs))
