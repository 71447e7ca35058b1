# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""When the face lay flat on the surface, and which tilt to touch with next if it did not.

The compliance bias, and how it is removed. The body turns its face towards the surface
only while the misalignment is within its capture range: the hinges (0.3 N m/rad) give
way to the contact's moment, so at a force F a face misaligned by d turns all the way
while d < F r / k (about 4 degrees at 1.5 N on the 15 mm rim). Beyond that only the rim
bears, and friction locks it: the force runs from the rim towards the hinges, inside the
friction cone, and the face turns by a degree or two whatever the misalignment. Such a
normal is biased towards the tool's own axis by most of the misalignment.

Rather than modelling that bias (it depends on friction, which nobody knows), the
explorer removes it: each touch is measured at two forces, and the face counts as flat
only when it turned by less than `tolerance` and pressing twice as hard did not turn it
further. Otherwise the tool touches again at a new tilt, a root search on turn(tilt) =
0. Within the capture range turn = (surface tilt - tool tilt), a slope of -1, so the
first step assumes the face lay flat and turns the tool by the measured turn. If the
next touch turns the face about as much again (a slope above -`FLAT_SLOPE`), only the
rim bore: the turn then only tells the side, and the tool steps `RIM_STEP_RAD` that way,
twice as far each time the rim bears again. Once two touches turned opposite ways the
root is bracketed and the next tilt is interpolated between them. The turn's sign stays
right well past the capture range (a 19 degree misalignment still turns the face the
right way by 0.4-1.8 degrees in the simulator), which is all the search needs.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
import math

import numpy as np

from tactex_probe.normals import NormalEstimate

# A step on a bearing rim, where the turn only tells the side.
RIM_STEP_RAD = math.radians(8.0)
# turn(tilt) falls at least this steeply where the face lies flat (-1 ideally).
FLAT_SLOPE = 0.5
# The largest tilt change between two touches.
MAX_TILT_STEP_RAD = math.radians(20.0)


@dataclass(frozen=True)
class TouchResult:
    """One touch: the tool's tilt and the estimates at the light and at the full force."""

    tilt: float
    light: NormalEstimate
    full: NormalEstimate

    @property
    def turn_rad(self) -> float:
        """The face's turn at the full force (signed like a tilt)."""
        return self.full.turn_rad

    def flat(self, tolerance_rad: float) -> bool:
        """True when the face lay flat: it barely turned, and no further when pressed harder."""
        return (abs(self.full.turn_rad) <= tolerance_rad
                and abs(self.full.turn_rad - self.light.turn_rad) <= tolerance_rad)



def next_tilt(touches: Sequence[TouchResult]) -> float:
    """The tilt to touch with next so that the face does not turn (see the module docstring).

    Raises:
        ValueError: no touch yet.
    """
    if not touches:
        raise ValueError('next_tilt needs at least one touch')
    last = touches[-1]
    side = math.copysign(1.0, last.turn_rad)
    opposite = [t for t in touches[:-1] if math.copysign(1.0, t.turn_rad) != side]
    if opposite:
        other = min(opposite, key=lambda t: abs(t.tilt - last.tilt))
        span = other.turn_rad - last.turn_rad
        fraction = last.turn_rad / span if abs(span) > 1e-12 else 0.5
        step = -fraction * (other.tilt - last.tilt)
    elif len(touches) >= 2 and abs(last.tilt - touches[-2].tilt) > 1e-9:
        previous = touches[-2]
        slope = (last.turn_rad - previous.turn_rad) / (last.tilt - previous.tilt)
        if slope < -FLAT_SLOPE:
            step = -last.turn_rad / max(slope, -2.0)
        else:  # a rim again: twice the last step, at least RIM_STEP_RAD
            step = side * max(RIM_STEP_RAD, 2.0 * abs(last.tilt - previous.tilt))
    else:
        step = last.turn_rad
    return last.tilt + float(np.clip(step, -MAX_TILT_STEP_RAD, MAX_TILT_STEP_RAD))


def best(touches: Sequence[TouchResult], tolerance_rad: float) -> TouchResult:
    """The touch to report: the last flat one, else the one whose face turned least."""
    flat = [t for t in touches if t.flat(tolerance_rad)]
    if flat:
        return flat[-1]
    return min(touches, key=lambda t: abs(t.turn_rad))
