# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""How the sensor edge meets a surface: its contact footprint and how the body answers it.

Derived from the compliant joints of `OPEN_MANIPULATOR_X` and two properties of the cast
polyurethane skin under the rim that the description does not otherwise hold (stated
below as assumptions). The simulator's texture effect takes its defaults from here.

- Footprint. The rim (radius 15 mm, the `sensor_edge` origin) has a rounded fillet
  (`EDGE_TIP_RADIUS_M` of the MJCF, 2 mm). Pressed `SKIN_INDENTATION_M` into a flat
  surface, a curved body of radius R touches over a chord of 2 sqrt(2 R d): the fillet
  gives the length along the sliding direction, the rim the width across it. Under
  more force the footprint grows as force^(1/3) (Hertz; K. L. Johnson, Contact
  Mechanics, 1985, ch. 4).
- Rocking. A rise h of the edge is shared between the body's press travel and its pitch
  about the compliant pivot, in proportion to their compliances at the edge
  (1/k_press and L^2/k_pitch, L the pivot-to-edge distance): the body pitches by
  share * h / L.
- Resonances. The body (the `sensor_link` mass and pitch inertia about the pivot) sits
  between its mount springs and the skin: normal resonance sqrt((k_skin + k_press) / m),
  rocking resonance sqrt((k_skin L^2 + k_pitch) / I).
"""

from __future__ import annotations

import math

from tactex_common import frames
from tactex_description.geometry import OPEN_MANIPULATOR_X
from tactex_description.mjcf import EDGE_TIP_RADIUS_M

# Assumptions about the skin (not in the description): how far the sweep's contact
# force (about 1 N) indents it at the rim, its normal stiffness there (it puts the
# normal resonance at 85 Hz, where the earlier calibration had it) and its damping.
SKIN_INDENTATION_M = 1.5e-4
SKIN_STIFFNESS_N_M = 3700.0
SKIN_DAMPING_RATIO = 0.12
REFERENCE_FORCE_N = 1.0


def _vector_to_edge() -> tuple[float, float, float]:
    press = OPEN_MANIPULATOR_X.joint('sensor_press').origin_xyz
    edge = OPEN_MANIPULATOR_X.joint('sensor_edge_fixed').origin_xyz
    return tuple(a + b for a, b in zip(press, edge, strict=True))


RIM_RADIUS_M = OPEN_MANIPULATOR_X.joint('sensor_edge_fixed').origin_xyz[0]
PIVOT_TO_EDGE_M = math.hypot(*_vector_to_edge())


def footprint_m(force_n: float = REFERENCE_FORCE_N) -> tuple[float, float]:
    """(length along the sliding direction, width across it) of the edge's contact (m).

    At `REFERENCE_FORCE_N` the chords of the indented fillet and rim; under another
    force scaled by (force / reference)^(1/3), the force held within [0.01, 100] N.
    """
    scale = (min(max(force_n, 0.01), 100.0) / REFERENCE_FORCE_N) ** (1.0 / 3.0)
    return (2.0 * math.sqrt(2.0 * EDGE_TIP_RADIUS_M * SKIN_INDENTATION_M) * scale,
            2.0 * math.sqrt(2.0 * RIM_RADIUS_M * SKIN_INDENTATION_M) * scale)


def rocking_per_metre() -> float:
    """Pitch of the body (rad) per metre the edge rises."""
    pitch = OPEN_MANIPULATOR_X.joint('sensor_pitch').stiffness
    press = OPEN_MANIPULATOR_X.joint('sensor_press').stiffness
    pitch_compliance = PIVOT_TO_EDGE_M ** 2 / pitch
    share = pitch_compliance / (pitch_compliance + 1.0 / press)
    return share / PIVOT_TO_EDGE_M


def body_mass_kg() -> float:
    """Mass of the sensor body (what moves on the compliant joints, past the press)."""
    return _body()[0]


def _body() -> tuple[float, float]:
    """Mass (kg) of the sensor body and its pitch inertia about the pivot (kg m^2)."""
    inertial = OPEN_MANIPULATOR_X.inertials[frames.SENSOR]
    offset = OPEN_MANIPULATOR_X.joint('sensor_press').origin_xyz[2] + inertial.com_xyz[2]
    return inertial.mass_kg, inertial.inertia_diag[1] + inertial.mass_kg * offset ** 2


def normal_resonance_hz() -> float:
    """The body's resonance along the contact normal, on its mount and the skin."""
    mass, _ = _body()
    press = OPEN_MANIPULATOR_X.joint('sensor_press').stiffness
    return math.sqrt((SKIN_STIFFNESS_N_M + press) / mass) / (2.0 * math.pi)


def rocking_resonance_hz() -> float:
    """The body's pitch resonance, on its mount and the skin under the edge."""
    _, inertia = _body()
    pitch = OPEN_MANIPULATOR_X.joint('sensor_pitch').stiffness
    return math.sqrt((SKIN_STIFFNESS_N_M * PIVOT_TO_EDGE_M ** 2 + pitch) / inertia) / (
        2.0 * math.pi)
