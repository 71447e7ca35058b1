# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Whether a training converged, judged from its per-epoch training losses alone.

One rule for a fresh training (`DeepClassifier`), a kept grid's cells (`grid_report`) and
`tactex train`'s notes: 'stalled at chance' or 'still falling' (`unconverged_because`).
"""

from collections.abc import Sequence
import math

import numpy as np

# A training loss never this fraction below ln(classes) stayed at chance (stalled_at_chance).
CHANCE_MARGIN = 0.05
# What to change for each `unconverged_because` reason (early stopping ends neither).
WHAT_TO_CHANGE = {'still falling': 'raise --epochs',
                  'stalled at chance': 'raise --epochs, or try another --model'}


def still_falling(losses: Sequence[float], span: int = 5, drop: float = 0.02) -> bool:
    """Whether a training loss was still falling at its end: not converged.

    True when the mean of the last `span` epochs lies more than `drop` (a fraction) below
    the mean of the `span` before; a history too short to tell, or with a loss that is not
    finite among those epochs, counts as falling.
    """
    last = np.asarray(losses[-2 * span:], dtype=float)
    if last.size < 2 * span or not np.all(np.isfinite(last)):
        return True
    before, after = (float(np.sum(part / span)) for part in (last[:span], last[span:]))
    return after < (1.0 - drop) * before  # sums of parts: no overflow near the float limit


def stalled_at_chance(losses: Sequence[float], classes: int,
                      margin: float = CHANCE_MARGIN) -> bool:
    """Whether a training never left chance: not converged, however it ended.

    The loss of the uniform prediction is ln(classes) against any target, label smoothing
    and mixup included; a training whose loss never fell `margin` (a fraction) below it
    learned nothing before it ended (early stopping waits while this holds; grids kept
    before that rule hold trainings it ended on their first plateau). A
    training without one finite loss learned nothing either; no epoch or one class: False.
    """
    losses = np.asarray(losses, dtype=float)
    if not losses.size or classes < 2:
        return False
    finite = losses[np.isfinite(losses)]
    return not finite.size or float(finite.min()) >= (1.0 - margin) * math.log(classes)


def ran_out_still_falling(losses: Sequence[float], epochs: int) -> bool:
    """Whether a training ran all its `epochs` with its loss `still_falling` at the end.

    One that early stopping ended before its last epoch had stopped improving.
    """
    return len(losses) >= epochs and still_falling(losses)


def unconverged_because(losses: Sequence[float], classes: int, epochs: int) -> str | None:
    """Why a training with these per-epoch `losses` did not converge, or None if it did.

    'stalled at chance' (`stalled_at_chance`), or 'still falling' (`ran_out_still_falling`).
    """
    if stalled_at_chance(losses, classes):
        return 'stalled at chance'
    if ran_out_still_falling(losses, epochs):
        return 'still falling'
    return None
