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
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

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
        right, contact, decided = [], [], []
        for episode in own:
            step = stop_step(episode.top_posterior, threshold)
            right.append(step >= 0 and episode.leaders[step] == episode.texture)
            contact.append(episode.contact_s[step] if step >= 0 else 0.0)
            decided.append(step >= 0 and episode.top_posterior[step] > threshold)
        rows.append({'threshold': float(threshold), 'accuracy': float(np.mean(right)),
                     'mean_contact_s': float(np.mean(contact)),
                     'median_contact_s': float(np.median(contact)),
                     'decided': float(np.mean(decided))})
    return rows


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
