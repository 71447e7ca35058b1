# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What accuracy costs in contact time: each policy's accuracy and seconds at lower thresholds.

A policy chooses its movements from the belief and the budget, never from the threshold
(`selection.Identification.next_movement`), and stops once the leading posterior
exceeds it. So an episode replayed with threshold T, cut after its first step whose
leading posterior exceeds a lower threshold t (or left whole when none does), is exactly
the episode a replay with t would have made on the same sweeps. One replay gives every
policy's speed-accuracy trade-off for each t <= T: its accuracy and mean contact seconds
per identification.

At equal accuracy: the mean contact seconds another policy needs to reach each of
`policy`'s accuracies, read off its trade-off between the thresholds that bracket that
accuracy first (linear in seconds), or None where none of its thresholds reaches it. And
the goal against fixed read the same way (`fixed_goal`): the seconds active's trade-off
needs for fixed's final accuracy, less the goal's tolerance.

With an interval (`saving_interval`): the same comparison on per-texture sums
(`texture_sums`), the textures resampled with replacement as in
`comparison.texture_bootstrap` (both policies' curves from the same draw), so the seconds
saved at equal accuracy carry a 95 % percentile interval, per threshold or averaged over
several (`mean_saving_interval`: one test for a stretch of the trade-off). Runs on other
scene seeds pool as more textures (`pooled_sums`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from tactex_classify.identification.comparison import LEVEL, resample_counts, RESAMPLES

THRESHOLDS = (0.5, 0.7, 0.8, 0.9, 0.95, 0.98, 0.99)


def stop_step(top_posterior: Sequence[float], threshold: float) -> int:
    """The step (0-based) after which an episode with `threshold` stops, -1 without steps."""
    over = np.flatnonzero(np.asarray(top_posterior, dtype=float) > threshold)
    return int(over[0]) if over.size else len(top_posterior) - 1


def tradeoff(episodes: list, policy: str, thresholds: Sequence[float]) -> list[dict]:
    """Per threshold, `policy`'s episodes cut there: accuracy, contact seconds, decided share.

    Args:
        episodes: a replay's episodes (`offline.Episode`, with `top_posterior`).
        policy: whose episodes.
        thresholds: each at most the replay's (a higher one would need longer episodes).

    Returns:
        [{'threshold', 'accuracy', 'mean_contact_s', 'median_contact_s', 'decided'}, ...];
        [] without an episode of `policy`.
    """
    own = [e for e in episodes if e.policy == policy]
    if not own:
        return []
    rows = []
    for threshold in thresholds:
        right, contact, decided = np.array([cut(episode, threshold) for episode in own]).T
        rows.append({'threshold': float(threshold), 'accuracy': float(np.mean(right)),
                     'mean_contact_s': float(np.mean(contact)),
                     'median_contact_s': float(np.median(contact)),
                     'decided': float(np.mean(decided))})
    return rows


def cut(episode, threshold: float) -> tuple[bool, float, bool]:
    """(right, contact seconds, decided) of `episode` cut where `threshold` stops it."""
    step = stop_step(episode.top_posterior, threshold)
    if step < 0:
        return False, 0.0, False
    return (episode.leaders[step] == episode.texture, episode.contact_s[step],
            episode.top_posterior[step] > threshold)


def texture_sums(episodes: list, policy: str, thresholds: Sequence[float],
                 textures: int) -> dict:
    """Per threshold and texture, `policy`'s episodes cut there: how many right, how long.

    Returns:
        {'thresholds', 'episodes' (per texture), 'right' and 'contact_s' (per threshold, per
        texture: episodes right, and their contact seconds summed)}; textures 0 to
        `textures` - 1, a texture without episodes counting zero.
    """
    own = [e for e in episodes if e.policy == policy]
    count = np.zeros(textures)
    right, contact = np.zeros((len(thresholds), textures)), np.zeros((len(thresholds), textures))
    for episode in own:
        count[episode.texture] += 1
        for row, threshold in enumerate(thresholds):
            was_right, seconds, _ = cut(episode, threshold)
            right[row, episode.texture] += was_right
            contact[row, episode.texture] += seconds
    return {'thresholds': [float(t) for t in thresholds], 'episodes': count.tolist(),
            'right': right.tolist(), 'contact_s': contact.tolist()}


def pooled_sums(runs: list[dict]) -> dict:
    """Several runs' `texture_sums` of one policy, at the same thresholds, as one of more textures.

    Raises:
        ValueError: the runs' thresholds differ.
    """
    if len({tuple(run['thresholds']) for run in runs}) > 1:
        raise ValueError('the runs were cut at different thresholds')
    if not runs:
        return {'thresholds': [], 'episodes': [], 'right': [], 'contact_s': []}
    shapes = [(len(run['thresholds']), len(run['episodes'])) for run in runs]
    return {'thresholds': runs[0]['thresholds'],
            'episodes': [n for run in runs for n in run['episodes']],
            **{key: np.hstack([np.asarray(run[key], dtype=float).reshape(shape)
                               for run, shape in zip(runs, shapes, strict=True)]).tolist()
               for key in ('right', 'contact_s')}}


def saving_interval(sums: dict, other_sums: dict, seed: int = 0,
                    resamples: int = RESAMPLES) -> list[dict]:
    """Per threshold of `sums`: the mean contact seconds it saves against the other, 95 % interval.

    `sums` and `other_sums` (`texture_sums`, the same textures in the same order): the
    policy's trade-off and the other's. The saving is the other's seconds at the policy's
    accuracy (`seconds_for`) less the policy's own: above zero where the policy needs
    fewer. Each resample draws the textures with replacement and rebuilds both curves from
    the same draw; only textures both policies have episodes of are drawn. Where the other
    never reaches the policy's accuracy, its longest mean contact stands in (the saving is
    then a lower bound: such draws make the interval's low end conservative, its high end
    not), and where its first threshold already reaches it, its seconds there (an upper
    bound: such draws make the low end optimistic); the shares of resamples where each
    happened say how much of the interval rests on bounds (`saves_clearly`).

    Returns:
        [{'threshold', 'accuracy', 'seconds' (the policy's mean contact), 'saving_s' (None
        if not a number), 'never' (the other never reaches that accuracy: the saving is a
        lower bound), 'at_most' (an upper bound), 'low', 'high' (None without a finite
        resample), 'never_share', 'at_most_share'}, ...]; [] without episodes or when the
        two cover different textures.
    """
    both = _shared_textures(sums, other_sums)
    if both is None:
        return []
    sums, other_sums = both
    count = np.asarray(sums['episodes'], dtype=float)
    accuracy, seconds, saving, never, at_most = _savings(sums, other_sums,
                                                         np.ones((1, len(count))))
    _, _, spread, spread_never, spread_at_most = _savings(
        sums, other_sums, resample_counts(len(count), seed, resamples))
    rows = []
    for index, threshold in enumerate(sums['thresholds']):
        low, high = _finite_interval(spread[:, index])
        rows.append({'threshold': float(threshold), 'accuracy': float(accuracy[0, index]),
                     'seconds': float(seconds[0, index]),
                     'saving_s': float(saving[0, index]) if np.isfinite(saving[0, index])
                     else None, 'never': bool(never[0, index]),
                     'at_most': bool(at_most[0, index]), 'low': low, 'high': high,
                     'never_share': float(np.mean(spread_never[:, index])),
                     'at_most_share': float(np.mean(spread_at_most[:, index]))})
    return rows


def mean_saving_interval(sums: dict, other_sums: dict, thresholds: Sequence[float],
                         seed: int = 0, resamples: int = RESAMPLES) -> dict:
    """The seconds `sums` saves against the other averaged over `thresholds`, 95 % interval.

    One number for a stretch of the trade-off, so that one interval answers whether a
    policy saves time at equal accuracy, where `saving_interval` gives one per threshold
    (and with each more, one more chance to clear zero by luck). Each resample averages
    the savings `saving_interval` reads from the same draw of textures, the other's bounds
    standing in alike; a draw stands on an upper bound (or on a never-reached accuracy)
    when any of its thresholds does. `thresholds` are some of those the sums were cut at.

    Returns:
        {'thresholds', 'saving_s', 'low', 'high' (each None where not finite), 'never',
        'at_most' (at the point, at any threshold), 'never_share', 'at_most_share'}, as
        `saves_clearly` reads them; {} without thresholds or textures both have episodes of.

    Raises:
        ValueError: a threshold the sums were not cut at, or one named twice.
    """
    missing = [t for t in thresholds if t not in sums['thresholds']]
    if missing:
        raise ValueError(f'the sums were not cut at {missing}; they were cut at '
                         f'{sums["thresholds"]}')
    if len(set(thresholds)) < len(thresholds):
        raise ValueError(f'thresholds {list(thresholds)} name one twice: it would count twice')
    both = _shared_textures(sums, other_sums)
    if both is None or not len(thresholds):
        return {}
    sums, other_sums = both
    columns = [sums['thresholds'].index(t) for t in thresholds]
    count = len(sums['episodes'])
    averaged = []  # per weights row: the mean saving, and whether any threshold is a bound
    for weights in (np.ones((1, count)), resample_counts(count, seed, resamples)):
        _, _, saving, never, at_most = _savings(sums, other_sums, weights)
        averaged.append((saving[:, columns].mean(axis=1), never[:, columns].any(axis=1),
                         at_most[:, columns].any(axis=1)))
    (point, point_never, point_at_most), (spread, spread_never, spread_at_most) = averaged
    low, high = _finite_interval(spread)
    return {'thresholds': [sums['thresholds'][c] for c in columns], 'saving_s': _number(point[0]),
            'low': low, 'high': high, 'never': bool(point_never[0]),
            'at_most': bool(point_at_most[0]), 'never_share': float(spread_never.mean()),
            'at_most_share': float(spread_at_most.mean())}


def _finite_interval(draws: np.ndarray) -> tuple[float | None, float | None]:
    """The 95 % percentile interval of the finite draws; (None, None) without one."""
    finite = draws[np.isfinite(draws)]
    if not finite.size:
        return None, None
    tail = 100 * (1 - LEVEL) / 2
    return tuple(np.percentile(finite, (tail, 100 - tail)).tolist())


def saves_clearly(row: dict) -> bool:
    """A `saving_interval` row's interval lies above zero, and not on upper bounds."""
    return (row['low'] is not None and row['low'] > 0
            and not leans_on_upper_bounds(row) and not row['at_most'])


def leans_on_upper_bounds(row: dict) -> bool:
    """More of a `saving_interval` row's draws stand on an upper bound than its tail share.

    Draws where the other's seconds are only an upper bound lift the interval's low end;
    past the interval's own tail share (2.5 %) they decide where the low end lies.
    """
    return row['at_most_share'] > (1 - LEVEL) / 2


def _shared_textures(sums: dict, other_sums: dict) -> tuple[dict, dict] | None:
    """Both `texture_sums` cut to the textures both have episodes of; None if none or unlike."""
    count, other_count = (np.asarray(s['episodes'], dtype=float) for s in (sums, other_sums))
    if count.shape != other_count.shape or not (sums['thresholds'] and other_sums['thresholds']):
        return None
    keep = (count > 0) & (other_count > 0)
    if not keep.any():
        return None
    return tuple({'thresholds': s['thresholds'], 'episodes': np.asarray(s['episodes'])[keep],
                  **{key: np.asarray(s[key], dtype=float).reshape(
                      len(s['thresholds']), len(keep))[:, keep] for key in ('right', 'contact_s')}}
                 for s in (sums, other_sums))


def fixed_goal_interval(sums: dict, fixed_sums: dict, tolerance: float, seed: int = 0,
                        resamples: int = RESAMPLES) -> dict:
    """`fixed_goal` in seconds and as a share of fixed's mean contact, with 95 % intervals.

    The mean contact `sums`' trade-off needs for fixed's final accuracy (its last
    threshold) less `tolerance`, and that over fixed's mean contact there; each resample
    draws the textures with replacement (those both have episodes of) and rebuilds both
    from the same draw. Where the trade-off never reaches that accuracy both stand at
    infinity (the goal missed), and where its lowest threshold already does, at that
    threshold's (an upper bound).

    Returns:
        {'seconds', 'seconds_low', 'seconds_high', 'share', 'low', 'high' (None: not
        finite, as where never reached), 'never' (at the point), 'at_most', 'never_share',
        'at_most_share'}; {} without episodes or thresholds, or when the two cover
        different textures.
    """
    both = _shared_textures(sums, fixed_sums)
    if both is None:
        return {}
    sums, fixed_sums = both
    count = np.asarray(sums['episodes'], dtype=float)
    reached = []  # per weights row: (seconds, share, never, at most)
    for weights in (np.ones((1, len(count))), resample_counts(len(count), seed, resamples)):
        accuracy, seconds = _curve(sums, weights)
        fixed_accuracy, fixed_seconds = _curve(fixed_sums, weights)
        rows = []
        for draw in range(len(weights)):
            needed, at_most = seconds_for(
                [{'accuracy': a, 'mean_contact_s': c}
                 for a, c in zip(accuracy[draw], seconds[draw], strict=True)],
                fixed_accuracy[draw, -1] - tolerance)
            needed = np.inf if needed is None else needed
            with np.errstate(invalid='ignore', divide='ignore'):
                rows.append((needed, needed / fixed_seconds[draw, -1], needed == np.inf,
                             at_most))
        reached.append(np.array(rows, dtype=float))
    point, spread = reached
    tail = 100 * (1 - LEVEL) / 2
    with np.errstate(invalid='ignore'):  # between two infinite values: None below
        (seconds_low, low), (seconds_high, high) = np.percentile(
            spread[:, :2], (tail, 100 - tail), axis=0)
    return {'seconds': _number(point[0, 0]), 'seconds_low': _number(seconds_low),
            'seconds_high': _number(seconds_high), 'share': _number(point[0, 1]),
            'low': _number(low), 'high': _number(high), 'never': bool(point[0, 2]),
            'at_most': bool(point[0, 3]), 'never_share': float(spread[:, 2].mean()),
            'at_most_share': float(spread[:, 3].mean())}


def _number(value: float) -> float | None:
    """`value` as a float, None where it is not finite (JSON has no infinity)."""
    return float(value) if np.isfinite(value) else None


def _savings(sums: dict, other_sums: dict, weights: np.ndarray) -> tuple[np.ndarray, ...]:
    """Per row of `weights` (how often each texture counts) and threshold of `sums`.

    (accuracy, seconds, saving, never, at_most), each weights rows x thresholds: the
    policy's accuracy and mean contact, the other's seconds there less the policy's (its
    longest where it never gets there), and whether it never does, or only at most.
    """
    accuracy, seconds = _curve(sums, weights)
    other_accuracy, other_seconds = _curve(other_sums, weights)
    saving = np.full(accuracy.shape, np.nan)
    never, at_most = np.zeros(accuracy.shape, bool), np.zeros(accuracy.shape, bool)
    for draw in range(len(weights)):
        curve = [{'accuracy': a, 'mean_contact_s': c}
                 for a, c in zip(other_accuracy[draw], other_seconds[draw], strict=True)]
        for index, reached in enumerate(accuracy[draw]):
            needed, at_most[draw, index] = seconds_for(curve, reached)
            never[draw, index] = needed is None
            if needed is None:
                needed = curve[-1]['mean_contact_s'] if curve else np.nan
            saving[draw, index] = needed - seconds[draw, index]
    return accuracy, seconds, saving, never, at_most


def _curve(sums: dict, weights: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(accuracy, mean contact seconds), weights rows x thresholds, textures weighted."""
    episodes = weights @ np.asarray(sums['episodes'], dtype=float)
    with np.errstate(invalid='ignore', divide='ignore'):
        return tuple(weights @ np.asarray(sums[key], dtype=float).reshape(
            len(sums['thresholds']), len(sums['episodes'])).T / episodes[:, None]
            for key in ('right', 'contact_s'))


def seconds_for(curve: list[dict], accuracy: float) -> tuple[float | None, bool]:
    """(the mean contact seconds `curve` needs to reach `accuracy`, whether only at most).

    Interpolated between the thresholds that first bracket `accuracy` (see top). When the
    curve's first threshold already reaches it, its seconds are only an upper bound (a lower
    threshold might stop sooner): at most. (None, False) where no threshold reaches it, or
    for an accuracy that is not a number.
    """
    if not np.isfinite(accuracy):
        return None, False
    previous = None
    for row in curve:
        if row['accuracy'] >= accuracy:
            if previous is None:
                return row['mean_contact_s'], True
            share = (accuracy - previous['accuracy']) / (row['accuracy'] - previous['accuracy'])
            return previous['mean_contact_s'] + share * (row['mean_contact_s']
                                                         - previous['mean_contact_s']), False
        previous = row
    return None, False


def at_equal_accuracy(curves: dict[str, list[dict]], policy: str = 'active') -> dict:
    """Per other policy: at each of `policy`'s thresholds, the seconds it needs beside the other's.

    Returns:
        {other: [{'threshold', 'accuracy', 'seconds' (policy's mean contact), 'other_seconds'
        (None: the other reaches that accuracy at none of its thresholds), 'other_at_most'
        (its seconds only an upper bound)}, ...]}; {} without `policy`'s curve.
    """
    own = curves.get(policy) or []
    return {other: [dict(zip(('threshold', 'accuracy', 'seconds', 'other_seconds',
                              'other_at_most'),
                             (row['threshold'], row['accuracy'], row['mean_contact_s'],
                              *seconds_for(curve, row['accuracy'])), strict=True))
                    for row in own]
            for other, curve in curves.items() if other != policy and own}


def fixed_goal(curves: dict[str, list[dict]], tolerance: float) -> dict:
    """The mean contact active's trade-off needs for fixed's final accuracy less `tolerance`.

    Fixed's final accuracy and contact are its trade-off's last row (the replay's own
    threshold, whole episodes).

    Returns:
        {'accuracy', 'active_mean_contact_s' (None: never reached), 'at_most' (active's
        seconds only an upper bound), 'fixed_median_contact_s', 'fixed_mean_contact_s'};
        {} without active's or fixed's curve.
    """
    if not (curves.get('active') and curves.get('fixed')):
        return {}
    final = curves['fixed'][-1]
    seconds, at_most = seconds_for(curves['active'], final['accuracy'] - tolerance)
    return {'accuracy': final['accuracy'] - tolerance, 'active_mean_contact_s': seconds,
            'at_most': at_most, 'fixed_median_contact_s': final['median_contact_s'],
            'fixed_mean_contact_s': final['mean_contact_s']}
