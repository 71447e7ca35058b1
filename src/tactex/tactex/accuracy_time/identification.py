# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Section 8: contact seconds against accuracy when each next movement is chosen.

`tactex_sim.collect` sweeps `size.textures` textures under the first
`size.identify_movements` movements of config/movements.yaml, `size.identify_sweeps`
times each; the offline replay of `tactex report identification` (`offline.replay`:
folds grouped by recording, nested calibration and tempering, held-out sweeps drawn
without replacement) then runs every policy to the live node's threshold. Kept: each
policy's row of identification.json, its accuracy against contact seconds (mean over
folds and seeds), the curve the section plots, and its trade-off: accuracy and mean
contact seconds at each threshold up to the live node's (`identification.tradeoff`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
import time

import numpy as np

from tactex.accuracy_time.sizes import Size

MODEL = 'extratrees'  # the fastest baseline: the section compares policies, not models
FOLDS = 2
CURVE_POINTS = 100


def identification(scratch: Path, size: Size, log: Callable[[str], None], *,
                   seed: int) -> dict:
    """Section 8: every policy replayed on held-out recordings of the movements."""
    from tactex.launching.spec import config_path
    from tactex_classify.data.dataset import convert
    from tactex_classify.identification.offline import replay, ReplaySettings, summary
    from tactex_classify.identification.report import accuracy_curves
    from tactex_classify.identification.selection import Budget, COMPARED
    from tactex_classify.training.deep_classifier import TrainingConfig
    from tactex_description.movements import load_movements
    from tactex_sim.collect import collect
    from tactex_sim.scene import load_scene, resolve_scene
    from tactex_sim.textures import TEXTURES
    every = load_movements(config_path('movements.yaml'))
    movements = replace(every, movements=every.movements[:size.identify_movements])
    bags = scratch / 'movement_bags'
    began = time.monotonic()
    collect(load_scene(resolve_scene('uneven_texture')), size.identify_sweeps, bags,
            textures=list(TEXTURES)[:size.textures], movements=movements,
            progress=lambda line: log(f'  collect {line}'))
    collect_s = time.monotonic() - began
    data = convert([bags], window=movements.window, hop=movements.window // 2,
                   progress=lambda line: None)
    # The default budget's threshold is the live node's and identify_node's (0.99).
    settings = ReplaySettings(policies=COMPARED, budget=Budget(), folds=FOLDS,
                              inner_folds=FOLDS, seeds=size.identify_seeds,
                              training=TrainingConfig(model=MODEL, seed=seed), seed=seed)
    began = time.monotonic()
    result = replay(data, movements, settings, progress=lambda line: log(f'  {line}'))
    table = summary(result, settings)
    longest = max((e.contact_s[-1] for e in result['episodes'] if e.contact_s), default=1.0)
    grid = np.linspace(0.0, longest, CURVE_POINTS)
    return {'policies': table['policies'], 'episodes': table['episodes'],
            'movements': list(movements.names), 'contact_s': table['contact_s'],
            'textures': size.textures, 'sweeps': size.identify_sweeps, 'model': MODEL,
            'folds': FOLDS, 'seeds': size.identify_seeds,
            'threshold': settings.budget.threshold,
            'grid_s': grid.tolist(),
            'curves': {policy: accuracy_curves(result['episodes'], policy, grid)[0].tolist()
                       for policy in settings.policies},
            'tradeoff': table['tradeoff']['curves'],
            'collect_s': collect_s, 'replay_s': time.monotonic() - began}


def contact_for(row: dict, grid_s: list[float], curve: list[float]) -> float | None:
    """The least contact seconds at which `curve` reaches `row`'s final accuracy (or None)."""
    reached = [s for s, a in zip(grid_s, curve, strict=True) if a >= row['accuracy'] - 1e-9]
    return reached[0] if reached else None
