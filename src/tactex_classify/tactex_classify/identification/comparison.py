# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Active against another policy at equal contact time, paired, with a 95 % interval.

Every policy of a replay meets the same held-out sweeps in the same order for a
(repeat, fold, texture, seed), so two policies' episodes pair up. At each contact time t
an episode counts right when its leader after the movements finished by t is the true
texture (none before its first; its final leader after its last). The difference in
accuracy is the mean over the paired episodes; its interval is a percentile bootstrap
over the textures: a resample draws the textures with replacement and pools the paired
episodes of those drawn (a texture weighs by its pairs, the same for every texture in a
replay). Textures, not episodes: an episode's seeds reorder the same held-out sweeps,
and its folds and repeats reuse the same recordings. What the interval covers: how much
the difference rests on a few textures, given these recordings; not the draw of the
recordings themselves (repeats show that), nor other texture sets (the textures share
the models and compete as classes). It is pointwise: of many contact times, a few
intervals exclude zero by chance, so a run of them says more than one.
"""

from __future__ import annotations

import numpy as np

RESAMPLES = 2000
MAX_TIMES = 1000  # contact times compared at most
LEVEL = 0.95


def right_by(contact_s: list[float], leaders: list[int], texture: int,
             grid_s: np.ndarray) -> np.ndarray:
    """Per time of `grid_s`, whether the leader after the movements finished by then is right.

    A movement that ends within rounding (1e-9 relative) of a grid time counts as finished
    by it: contact times are sums of movements' seconds, the grid multiples of a step.
    """
    steps = np.searchsorted(np.asarray(contact_s, dtype=float), grid_s * (1 + 1e-9),
                            side='right')
    return np.array([False, *[leader == texture for leader in leaders]])[steps]


def contact_grid(episodes: list, step_s: float) -> np.ndarray:
    """Contact times every `step_s` up to the longest episode's.

    At most MAX_TIMES of them: a step that would give more widens to longest / MAX_TIMES.
    Empty without an episode that moved, or with a step or contact time that is not
    finite and > 0.
    """
    ends = np.array([e.contact_s[-1] for e in episodes if e.contact_s], dtype=float)
    longest = ends.max() if ends.size else 0.0
    if not (np.isfinite(step_s) and step_s > 0.0 and np.all(np.isfinite(ends))
            and longest > 0.0):
        return np.zeros(0)
    step_s = max(step_s, longest / MAX_TIMES)
    return step_s * np.arange(1, min(int(np.ceil(longest / step_s - 1e-9)), MAX_TIMES) + 1)


def paired_difference(episodes: list, policy: str, other: str, grid_s: np.ndarray,
                      seed: int = 0, resamples: int = RESAMPLES) -> dict:
    """`policy` minus `other`: the difference in accuracy by contact time, with its interval.

    Args:
        episodes: a replay's episodes (`offline.Episode`), both policies among them.
        policy: the policy whose accuracy the other's is taken from.
        other: the policy compared with it.
        grid_s: the contact times.
        seed: the bootstrap's seed.
        resamples: bootstrap resamples of the textures.

    Returns:
        {'contact_s', 'difference', 'low', 'high'} (lists over the grid, in accuracy
        shares), 'pairs' and 'textures' (how many of each were compared).
    """
    keyed = {policy: {}, other: {}}
    for episode in episodes:
        if episode.policy in keyed:
            key = (episode.repeat, episode.fold, episode.texture, episode.seed)
            keyed[episode.policy][key] = right_by(episode.contact_s, episode.leaders,
                                                  episode.texture, grid_s)
    pairs = sorted(set(keyed[policy]) & set(keyed[other]))
    by_texture: dict[int, list[np.ndarray]] = {}
    for key in pairs:
        by_texture.setdefault(key[2], []).append(
            keyed[policy][key].astype(float) - keyed[other][key])
    if not by_texture:
        return {'contact_s': list(map(float, grid_s)), 'pairs': 0, 'textures': 0,
                **{name: [float('nan')] * len(grid_s) for name in ('difference', 'low', 'high')}}
    means = np.array([np.mean(rows, axis=0) for rows in by_texture.values()])
    weights = np.array([len(rows) for rows in by_texture.values()], dtype=float)
    textures = len(means)  # a resample: how often each texture is drawn, textures draws
    drawn = np.random.default_rng(seed).multinomial(textures, np.full(textures, 1 / textures),
                                                    size=resamples) * weights
    resampled = drawn @ means / drawn.sum(axis=1, keepdims=True)
    tail = 100 * (1 - LEVEL) / 2
    return {'contact_s': list(map(float, grid_s)),
            'difference': (weights @ means / weights.sum()).tolist(),
            'low': np.percentile(resampled, tail, axis=0).tolist(),
            'high': np.percentile(resampled, 100 - tail, axis=0).tolist(),
            'pairs': len(pairs), 'textures': len(by_texture)}
