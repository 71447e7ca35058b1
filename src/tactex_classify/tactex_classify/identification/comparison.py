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

`against_fixed` measures the issue's goal against the single best movement repeated: the
policy's accuracy after GOAL_SHARE of fixed's median contact seconds, against fixed's
final accuracy less the goal's GOAL_TOLERANCE, paired and bootstrapped the same way. Its
per-texture margins let runs on other scene seeds pool as more textures.
"""

from __future__ import annotations

import numpy as np

RESAMPLES = 2000
MAX_TIMES = 1000  # contact times compared at most
LEVEL = 0.95
GOAL_SHARE = 0.6  # of fixed's median contact seconds
GOAL_TOLERANCE = 0.01  # below fixed's final accuracy


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


def paired_episodes(episodes: list, policy: str, other: str) -> list[tuple]:
    """(`policy`'s, `other`'s) episodes of each (repeat, fold, texture, seed) both replayed."""
    keyed: dict[str, dict] = {policy: {}, other: {}}
    for episode in episodes:
        if episode.policy in keyed:
            keyed[episode.policy][(episode.repeat, episode.fold, episode.texture,
                                   episode.seed)] = episode
    return [(keyed[policy][key], keyed[other][key])
            for key in sorted(set(keyed[policy]) & set(keyed[other]))]


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
    pairs = paired_episodes(episodes, policy, other)
    by_texture: dict[int, list[np.ndarray]] = {}
    for ours, theirs in pairs:
        by_texture.setdefault(ours.texture, []).append(
            right_by(ours.contact_s, ours.leaders, ours.texture, grid_s).astype(float)
            - right_by(theirs.contact_s, theirs.leaders, theirs.texture, grid_s))
    if not by_texture:
        return {'contact_s': list(map(float, grid_s)), 'pairs': 0, 'textures': 0,
                **{name: [float('nan')] * len(grid_s) for name in ('difference', 'low', 'high')}}
    means = np.array([np.mean(rows, axis=0) for rows in by_texture.values()])
    weights = np.array([len(rows) for rows in by_texture.values()], dtype=float)
    difference, low, high = texture_bootstrap(means, weights, seed, resamples)
    return {'contact_s': list(map(float, grid_s)), 'difference': difference.tolist(),
            'low': low.tolist(), 'high': high.tolist(), 'pairs': len(pairs),
            'textures': len(by_texture)}


def resample_counts(units: int, seed: int = 0, resamples: int = RESAMPLES) -> np.ndarray:
    """How often each unit is drawn (resamples x units), a resample drawing `units` times."""
    return np.random.default_rng(seed).multinomial(units, np.full(units, 1 / units),
                                                   size=resamples)


def texture_bootstrap(means: np.ndarray, weights: np.ndarray, seed: int = 0,
                      resamples: int = RESAMPLES) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The weighted mean over textures and its percentile interval, textures resampled.

    `means`: per texture (rows), its mean paired difference at each time (columns);
    `weights`: its pairs. A resample draws as many textures as there are, with replacement.
    """
    drawn = resample_counts(len(means), seed, resamples) * weights
    resampled = drawn @ means / drawn.sum(axis=1, keepdims=True)
    tail = 100 * (1 - LEVEL) / 2
    return (weights @ means / weights.sum(), np.percentile(resampled, tail, axis=0),
            np.percentile(resampled, 100 - tail, axis=0))


def against_fixed(episodes: list, policy: str = 'active', seed: int = 0,
                  resamples: int = RESAMPLES) -> dict:
    """`policy` after GOAL_SHARE of fixed's median contact, against fixed's final accuracy.

    Paired as `paired_difference`: per (repeat, fold, texture, seed), whether `policy`'s
    leader after the movements finished by the goal's time is right, less whether fixed's
    final leader is. The margin adds GOAL_TOLERANCE: at or above zero, the goal is met.

    Returns:
        {'goal_contact_s', 'fixed_median_contact_s', 'fixed_accuracy', 'accuracy' (the
        policy's at the goal's time), 'margin', 'low', 'high' (its 95 % interval over the
        textures), 'pairs', 'textures', 'texture_margins', 'texture_pairs' (per texture
        replayed, in texture order)}; {} without paired episodes or with a fixed contact
        time that is not finite.
    """
    pairs = paired_episodes(episodes, policy, 'fixed')
    ends = [fixed.contact_s[-1] if fixed.contact_s else 0.0 for _, fixed in pairs]
    if not pairs or not np.all(np.isfinite(ends)):
        return {}
    median = float(np.median(ends))
    goal = GOAL_SHARE * median
    by_texture: dict[int, list[tuple[float, float]]] = {}
    for ours, fixed in pairs:
        right = float(right_by(ours.contact_s, ours.leaders, ours.texture, np.array([goal]))[0])
        by_texture.setdefault(ours.texture, []).append((right, float(fixed.right)))
    textures = sorted(by_texture)
    rights = np.array([np.mean(by_texture[t], axis=0) for t in textures])
    weights = np.array([len(by_texture[t]) for t in textures], dtype=float)
    margins = rights[:, 0] - rights[:, 1] + GOAL_TOLERANCE
    margin, low, high = (float(value[0]) for value in texture_bootstrap(
        margins[:, None], weights, seed, resamples))
    accuracy, fixed_accuracy = weights @ rights / weights.sum()
    return {'goal_contact_s': goal, 'fixed_median_contact_s': median,
            'fixed_accuracy': float(fixed_accuracy), 'accuracy': float(accuracy),
            'margin': margin, 'low': low, 'high': high,
            'pairs': len(pairs), 'textures': len(textures),
            'texture_margins': margins.tolist(), 'texture_pairs': weights.astype(int).tolist()}
