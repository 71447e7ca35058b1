# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Section 4: sliding speed against contact fraction and classification accuracy.

At each speed the uneven-texture scene's sweeps slide for the same contact time (so
every speed gets the same seconds of signal, faster ones over a longer stretch); the
recordings are converted and cross-validated (grouped by recording, ExtraTrees, the
fastest model to train). Contact fraction: the share of the planned sliding samples in
which the simulator's ground truth has the sensor sliding in contact over the texture
(what the converter keeps).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
import time

import numpy as np

from tactex.accuracy_time.sizes import Size

MODEL = 'extratrees'


def sweep_speed(scratch: Path, size: Size, log: Callable[[str], None], *, seed: int) -> dict:
    """Per speed: contact fraction, window and whole-sweep accuracy, collection time.

    A speed whose sweeps cannot be simulated (out of reach) gets a row with `failed`.
    """
    from tactex_classify.data.dataset import convert
    from tactex_classify.evaluation.cross_validation import cross_validate, threshold_decisions
    from tactex_classify.models.baselines import StatsExtraTrees
    from tactex_sim.collect import collect
    from tactex_sim.errors import SimError
    from tactex_sim.scene import load_scene, resolve_scene
    from tactex_sim.textures import TEXTURES
    base = load_scene(resolve_scene('uneven_texture'))
    textures = list(TEXTURES)[:size.textures]
    rows = []
    for speed in size.speeds_mm_s:
        scene = replace(base, sweep=replace(base.sweep, speed_m_s=speed * 1e-3,
                                            contact_s=size.speed_contact_s))
        bags = scratch / f'speed_{speed:g}'
        began = time.monotonic()
        try:
            collect(scene, size.speed_sweeps, bags, textures=textures,
                    progress=lambda line: None)
        except SimError as err:  # e.g. the stretch runs out of the arm's reach
            rows.append({'speed_mm_s': speed, 'failed': str(err)})
            log(f'  {speed:g} mm/s: not measured: {err}')
            continue
        collect_s = time.monotonic() - began
        data = convert([bags], window=size.speed_window, hop=size.speed_window // 2,
                       progress=lambda line: None)
        rate = data.info['sampling_rate_hz']
        planned = size.speed_contact_s * rate
        fractions = [min(1.0, r['kept'] / planned) for r in data.info['recordings']]
        folds = min(size.folds, size.speed_sweeps)
        result = cross_validate(data, lambda: StatsExtraTrees(seed=seed), 'grouped',
                                folds=folds, seed=seed)
        whole = threshold_decisions(data, result.proba, 1.0, rate)
        rows.append({'speed_mm_s': speed, 'contact_fraction': float(np.mean(fractions)),
                     'contact_fraction_min': float(np.min(fractions)),
                     'window_accuracy': float(np.mean(result.proba.argmax(axis=1) == data.y)),
                     'sweep_accuracy': whole['accuracy'], 'windows': len(data.y),
                     'distance_mm': speed * size.speed_contact_s, 'collect_s': collect_s,
                     'folds': folds, 'failed': ''})
        log(f'  {speed:g} mm/s: contact {100 * rows[-1]["contact_fraction"]:.1f} %, window '
            f'accuracy {100 * rows[-1]["window_accuracy"]:.1f} %, whole sweep '
            f'{100 * whole["accuracy"]:.1f} %')
    return {'rows': rows, 'model': MODEL, 'contact_s': size.speed_contact_s,
            'window': size.speed_window, 'sweeps': size.speed_sweeps,
            'textures': size.textures}
