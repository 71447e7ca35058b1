# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The identification report: identification.json, identification.md and its PNGs.

Plots: accuracy against contact seconds per policy (mean over repeats x folds x seeds,
shaded one standard deviation; dashed, the best plan of at most k movements in hindsight),
active minus each other policy at equal contact time (paired, with a pointwise 95 %
interval over the textures), each policy's accuracy against its mean contact seconds as
the decision threshold is lowered (`tradeoff`), movements to decision, the movements
`active` chose per true texture, arm and wall time beside contact time, the reliability
of each movement's calibrated sweep probabilities, and each movement's confusion matrix
(what shows whether any movement tells more than another).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from tactex_classify.evaluation.training_report import draw_confusion
from tactex_classify.identification.calibration import reliability
from tactex_classify.identification.comparison import GOAL_SHARE, GOAL_TOLERANCE, right_by
from tactex_classify.identification.offline import Episode, ReplaySettings, summary
from tactex_classify.identification.tradeoff import at_equal_accuracy, fixed_goal
from tactex_classify.training.convergence import WHAT_TO_CHANGE
from tactex_common import plotting

PLOTS = ('accuracy_vs_contact.png', 'active_against.png', 'tradeoff.png',
         'movements_to_decision.png',
         'active_choices.png', 'time.png', 'reliability.png', 'movement_confusions.png')
ONLY_WITH_ACTIVE = ('active_against.png', 'active_choices.png')
SHOWN_STEPS = (1, 2, 3, 5, 10, 20, 30)  # contact times of the paired table, in grid steps


def accuracy_curves(episodes: list[Episode], policy: str, grid_s: np.ndarray
                    ) -> tuple[np.ndarray, np.ndarray]:
    """Mean and sd over (repeat, fold, seed) of the share of textures right by time t.

    Before its first movement an episode has no leader (counted wrong); after its last,
    its final leader stands.
    """
    groups: dict[tuple[int, int], list[np.ndarray]] = {}
    for episode in episodes:
        if episode.policy != policy:
            continue
        groups.setdefault((episode.repeat, episode.fold, episode.seed), []).append(
            right_by(episode.contact_s, episode.leaders, episode.texture, grid_s))
    means = np.array([np.mean(rows, axis=0) for rows in groups.values()])
    return means.mean(axis=0), means.std(axis=0)


def write_report(folder: Path, result: dict, settings: ReplaySettings) -> dict:
    """Write identification.json, identification.md and the PNGs into `folder`."""
    folder.mkdir(parents=True, exist_ok=True)
    table = summary(result, settings)
    (folder / 'identification.json').write_text(json.dumps(table, indent=1) + '\n',
                                                encoding='utf-8')
    _plot_accuracy(folder / 'accuracy_vs_contact.png', result['episodes'],
                   settings.policies, table['best_plans'])
    _plot_tradeoff(folder / 'tradeoff.png', table['tradeoff']['curves'])
    _plot_movements(folder / 'movements_to_decision.png', result['episodes'],
                    settings.policies)
    if 'active' in settings.policies:
        _plot_against(folder / 'active_against.png', table['active_against'])
        _plot_choices(folder / 'active_choices.png', result)
    _plot_time(folder / 'time.png', table)
    _plot_reliability(folder / 'reliability.png', result)
    _plot_confusions(folder / 'movement_confusions.png', table)
    (folder / 'identification.md').write_text(markdown(table), encoding='utf-8')
    return table


def markdown(table: dict) -> str:
    """The report's text: the policies' table, each movement's model, the plots."""
    settings = table['settings']
    classes = len(table['classes'])
    lines = ['# Active identification, replayed on held-out recordings', '',
             f'{table["episodes"]} episodes per policy ({partitions(settings)}'
             f'{settings["folds"]} folds grouped by '
             f'recording x {settings["seeds"]} seeds x {classes} textures; one episode moves '
             f'accuracy by {100 / max(table["episodes"], 1):.2f} points). Per movement: '
             f'{model_text(settings)}, calibrated by temperature on out-of-fold sweeps '
             f'({settings["inner_folds"]} inner folds); tempering exponent '
             f'{", ".join(f"{t:.2f}" for t in table["tempering"])} and repeat discount '
             f'{", ".join(f"{c:g}" for c in table["repeat_discount"])} (per fold'
             f'{" of each partition" if settings.get("repeats", 1) > 1 else ""}). '
             'Threshold '
             f'{settings["threshold"]:g}; budget {settings["budget_movements"] or "no limit on"}'
             f' movements, {settings["budget_seconds"] or "no limit on"} contact seconds.', '',
             '| policy | accuracy | decided | median contact (s) | p90 contact (s) | median '
             'movements | median arm (s) | median wall (s) |', '|---|---|---|---|---|---|---|---|']
    for policy, row in table['policies'].items():
        lines.append(f'| {policy} | {100 * row["accuracy"]:.1f} % | {100 * row["decided"]:.0f} '
                     f'% | {row["median_contact_s"]:.1f} | {row["p90_contact_s"]:.1f} | '
                     f'{row["median_movements"]:.0f} | {row["median_arm_s"]:.1f} | '
                     f'{row["median_wall_s"]:.1f} |')
    lines += _plans_table(table)
    lines += against_table(table)
    lines += fixed_goal_lines(table)
    lines += tradeoff_lines(table)
    lines += ['', '| movement | contact (s) | arm (s) | held-out sweeps | sweep accuracy | '
              'calibration error |', '|---|---|---|---|---|---|']
    for name, contact, arm in zip(table['movement_names'], table['contact_s'], table['arm_s'],
                                  strict=True):
        row = table['movements'][name]
        mark = ' (not converged)' if row.get('unconverged') else ''
        lines.append(f'| {name}{mark} | {contact:.1f} | {arm:.1f} | {row["sweeps"]} | '
                     f'{100 * row["sweep_accuracy"]:.1f} % | {row["calibration_error"]:.3f} |')
    unconverged = {name: row['unconverged'] for name, row in table['movements'].items()
                   if row.get('unconverged')}
    if unconverged:
        advice = '; '.join(f'{why}: {what}' for why, what in WHAT_TO_CHANGE.items())
        lines += ['', f'Not converged ({advice}; a movement that tells the textures apart '
                  'nowhere stalls at chance whatever the epochs): '
                  + '; '.join(f'{name}: {", ".join(reasons)}'
                              for name, reasons in unconverged.items()) + '.']
    lines += ['', *[f'![{name}]({name})' for name in plots_of(table)], '']
    return '\n'.join(lines)


def partitions(settings: dict) -> str:
    """'R partitions into ' where the folds were dealt R > 1 times, else ''."""
    repeats = settings.get('repeats', 1)  # a report kept before repeats were
    return f'{repeats} partitions into ' if repeats > 1 else ''


def model_text(settings: dict) -> str:
    """The per-movement model, with how it trained if it is a deep one."""
    if 'profile' not in settings:  # a baseline, or a report kept before the recipe was
        return settings['model']
    patience = (f', early stopping after {settings["early_stopping"]} epochs without gain'
                if settings['early_stopping'] else '')
    start = (f', fine-tuned from {settings["pretrained"]}' if settings.get('pretrained')
             else '')
    return (f'{settings["model"]} ({settings["profile"]} profile, at most {settings["epochs"]} '
            f'epochs, {settings["scaling"]} scaling{patience}{start})')


def plots_of(table: dict) -> tuple[str, ...]:
    """The report's PNGs: active's own plots only where active was replayed."""
    return tuple(name for name in PLOTS
                 if name not in ONLY_WITH_ACTIVE or 'active' in table['policies'])


def _plans_table(table: dict) -> list[str]:
    """Each policy's accuracy after k movements beside the best plan of at most k in hindsight."""
    plans, policies = table.get('best_plans', []), list(table['policies'])
    if not plans:
        return []
    lines = ['', 'Accuracy after k movements (the leader after the k-th; an episode that '
             'stopped earlier keeps its last), beside the best plan of at most k movements '
             'fixed in advance, picked in hindsight on these same held-out sweeps: an '
             'optimistic bound on plans fixed in advance for every episode, such as fixed and '
             'round-robin while they run to k. A policy that stops on its threshold chooses '
             'how many sweeps from them, random draws a plan per episode (on few episodes it '
             'can pass by luck), and active chooses from each sweep: these can pass it. '
             'Picked among many plans, it is '
             'flattered by luck; "chosen elsewhere" scores each fold with the plan best on the '
             'other folds of its partition, what a choice learnt from more recordings could '
             'reach.', '',
             f'| k | {" | ".join(policies)} | best plan (hindsight) | chosen elsewhere | its '
             'movements | its contact (s) |', '|---' * (len(policies) + 5) + '|']
    after = [table['policies'][p]['accuracy_after_k'] for p in policies]
    for plan in plans:
        k = plan['movements']
        elsewhere = plan['chosen_elsewhere']
        lines.append(f'| {k} | ' + ' | '.join(
            f'{100 * row[k - 1]:.1f} %' if k <= len(row) else '' for row in after)
            + f' | {100 * plan["accuracy"]:.1f} % | '
            + ('' if elsewhere is None else f'{100 * elsewhere:.1f} %') + ' | '
            + ', '.join(f'{name} x{count}' for name, count in plan['plan'].items())
            + f' | {plan["contact_s"]:.1f} |')
    return lines


def against_table(table: dict) -> list[str]:
    """Active minus each other policy at a few contact times, with the 95 % intervals."""
    against = table.get('active_against') or {}
    if not against:
        return []
    grid = next(iter(against.values()))['contact_s']
    columns = [k - 1 for k in SHOWN_STEPS if k <= len(grid)]
    if not columns:
        return []
    textures = next(iter(against.values()))['textures']
    lines = ['', 'Active minus each other policy at equal contact time (points of accuracy, '
             'paired on the same held-out sweeps; in brackets the pointwise 95 % interval of '
             f'a bootstrap over the {textures} textures, given these recordings: an interval '
             'above zero favours active):',
             '', '| active minus | ' + ' | '.join(f'{grid[i]:g} s' for i in columns) + ' |',
             '|---' * (len(columns) + 1) + '|']
    for other, row in against.items():
        lines.append(f'| {other} | ' + ' | '.join(
            f'{100 * row["difference"][i]:+.1f} [{100 * row["low"][i]:+.1f}, '
            f'{100 * row["high"][i]:+.1f}]' for i in columns) + ' |')
    return lines


def fixed_goal_lines(table: dict) -> list[str]:
    """The goal against fixed: active at 60 % of fixed's median contact, with its interval."""
    goal = table.get('against_fixed') or {}
    if not goal:
        return []
    verdict = 'met' if goal['margin'] >= 0 else 'not met'
    return ['', f'Against `fixed` (the goal: its final accuracy, within '
            f'{100 * GOAL_TOLERANCE:g} point, in at most {100 * GOAL_SHARE:g} % of its median '
            f'contact): fixed ends at {100 * goal["fixed_accuracy"]:.1f} % after a median '
            f'{goal["fixed_median_contact_s"]:g} s; after {goal["goal_contact_s"]:g} s active '
            f'has {100 * goal["accuracy"]:.1f} %. Margin {100 * goal["margin"]:+.1f} points '
            f'({verdict}; 95 % interval [{100 * goal["low"]:+.1f}, {100 * goal["high"]:+.1f}] '
            f'over the {goal["textures"]} textures, paired on the same held-out sweeps).']


def tradeoff_lines(table: dict) -> list[str]:
    """Each policy's accuracy and seconds per threshold, and the seconds at equal accuracy."""
    curves = (table.get('tradeoff') or {}).get('curves') or {}
    if not curves:  # a report kept before the trade-off was
        return []
    policies = list(curves)
    by_threshold = {policy: {row['threshold']: row for row in curve}
                    for policy, curve in curves.items()}
    thresholds = sorted({row['threshold'] for curve in curves.values() for row in curve})
    lines = ['', 'What accuracy costs in contact time: every episode cut after its first step '
             'whose leading posterior exceeds a lower threshold (a policy chooses from the '
             'belief, never from the threshold, so that is the episode a replay at that '
             'threshold makes). Accuracy / mean contact seconds per identification:', '',
             f'| threshold | {" | ".join(policies)} |', '|---' * (len(policies) + 1) + '|']
    for threshold in thresholds:
        lines.append(f'| {threshold:g} | ' + ' | '.join(
            f'{100 * row["accuracy"]:.1f} % / {row["mean_contact_s"]:.1f} s'
            if (row := by_threshold[p].get(threshold)) else '' for p in policies) + ' |')
    goal = fixed_goal(curves, GOAL_TOLERANCE)
    if goal:
        lines += ['', "The goal against fixed read the same way: active's trade-off reaches "
                  f"fixed's final accuracy less {100 * GOAL_TOLERANCE:g} point "
                  f'({100 * goal["accuracy"]:.1f} %) ' + fixed_goal_text(goal) + '.']
    equal = at_equal_accuracy(curves)
    if equal:
        others = list(equal)
        lines += ['', 'At equal accuracy: the mean contact seconds active needs at each '
                  'threshold, beside what each other policy needs for the same accuracy on '
                  'its own trade-off (between its thresholds; "<=": its lowest threshold '
                  'already reaches it, an upper bound; "never": none of its thresholds '
                  'reaches it):', '',
                  f'| threshold | accuracy | active (s) | {" | ".join(others)} |',
                  '|---' * (len(others) + 3) + '|']
        for index, row in enumerate(equal[others[0]]):
            lines.append(f'| {row["threshold"]:g} | {100 * row["accuracy"]:.1f} % | '
                         f'{row["seconds"]:.1f} | ' + ' | '.join(
                             seconds_text(equal[o][index]['other_seconds'],
                                          equal[o][index]['other_at_most']) for o in others)
                         + ' |')
    saving = ((table.get('tradeoff') or {}).get('active_saving') or {}).get('random')
    if saving:
        lines += ['', "The seconds active saves against random at equal accuracy (random's "
                  "seconds less active's, above zero where active needs fewer), with a 95 % "
                  'interval of a bootstrap over the textures (both trade-offs rebuilt from '
                  "each draw; where random never reaches active's accuracy its longest mean "
                  'contact stands in, so the saving is a lower bound, ">="; "<=" an upper '
                  'bound; the shares of resamples on either bound beside):', '',
                  '| threshold | accuracy | active (s) | saved (s) [95 %] | resamples random '
                  'never reaches | resamples on its upper bound |', '|---|---|---|---|---|---|']
        lines += [f'| {row["threshold"]:g} | {100 * row["accuracy"]:.1f} % | '
                  f'{row["seconds"]:.1f} | {saving_text(row)} | '
                  f'{100 * row["never_share"]:.0f} % | {100 * row["at_most_share"]:.0f} % |'
                  for row in saving]
    return lines


def saving_text(row: dict) -> str:
    """'+7.5 [+2.1, +12.0]', '>= +5.3 [...]' (the other never gets there) or '<= ...'."""
    if row['saving_s'] is None:
        return ''
    bound = '>= ' if row['never'] else '<= ' if row['at_most'] else ''
    interval = (f' [{row["low"]:+.1f}, {row["high"]:+.1f}]' if row['low'] is not None
                else '')
    return f'{bound}{row["saving_s"]:+.1f}{interval}'


def seconds_text(seconds: float | None, at_most: bool) -> str:
    """'never', '<= 11.4' (an upper bound) or '11.4'."""
    return 'never' if seconds is None else f'{"<= " if at_most else ""}{seconds:.1f}'


def fixed_goal_text(goal: dict) -> str:
    """'after a mean 11.4 s of contact (55 % of fixed's mean, 46 % of fixed's median)' or why not.

    'after at most ...' where active's lowest threshold already reaches fixed's accuracy.
    """
    seconds = goal['active_mean_contact_s']
    if seconds is None:
        return 'at none of its thresholds'
    shares = ', '.join(f"{100 * seconds / goal[key]:.0f} % of fixed's {name}"
                       for key, name in (('fixed_mean_contact_s', 'mean'),
                                         ('fixed_median_contact_s', 'median')) if goal[key] > 0)
    return (f'after {"at most " if goal.get("at_most") else ""}a mean {seconds:.1f} s of '
            'contact' + (f' ({shares})' if shares else ''))


def _plot_tradeoff(path: Path, curves: dict) -> None:
    plt, figure, axis = plotting.figure()
    for index, (policy, curve) in enumerate(curves.items()):
        seconds = [row['mean_contact_s'] for row in curve]
        accuracy = [100 * row['accuracy'] for row in curve]
        axis.plot(seconds, accuracy, 'o-', ms=3, color=f'C{index}', label=policy)
        if policy == 'active':
            for row, x, y in zip(curve, seconds, accuracy, strict=True):
                axis.annotate(f'{row["threshold"]:g}', (x, y), textcoords='offset points',
                              xytext=(4, -10), fontsize=7, color=f'C{index}')
    axis.set_xlabel('mean contact seconds per identification')
    axis.set_ylabel('textures identified right (%)')
    plotting.legend_outside(axis)
    plotting.save(plt, figure, path, 'each point a decision threshold (labelled for active); '
                  'up and to the left is better')


def _plot_against(path: Path, against: dict) -> None:
    plt, figure, axis = plotting.figure()
    axis.axhline(0.0, color='gray', lw=0.8)
    for index, (other, row) in enumerate(against.items(), start=1):
        grid = np.asarray(row['contact_s'])
        axis.plot(grid, 100 * np.asarray(row['difference']), color=f'C{index}',
                  label=f'active - {other}')
        axis.fill_between(grid, 100 * np.asarray(row['low']), 100 * np.asarray(row['high']),
                          color=f'C{index}', alpha=0.15, lw=0)
    axis.set_xlabel('contact seconds')
    axis.set_ylabel('difference in accuracy (points)')
    plotting.legend_outside(axis)
    plotting.save(plt, figure, path, 'paired on the same held-out sweeps; band: pointwise '
                  '95 % bootstrap interval over the textures')


def _plot_accuracy(path: Path, episodes: list[Episode], policies: tuple[str, ...],
                   plans: list[dict]) -> None:
    longest = max((e.contact_s[-1] for e in episodes if e.contact_s), default=1.0)
    grid = np.linspace(0.0, longest, 200)
    plt, figure, axis = plotting.figure()
    for index, policy in enumerate(policies):
        mean, spread = accuracy_curves(episodes, policy, grid)
        axis.plot(grid, 100 * mean, color=f'C{index}', label=policy)
        axis.fill_between(grid, np.clip(100 * (mean - spread), 0, 100),
                          np.clip(100 * (mean + spread), 0, 100), color=f'C{index}',
                          alpha=0.15, lw=0)
    if plans:
        axis.plot([plan['contact_s'] for plan in plans],
                  [100 * plan['accuracy'] for plan in plans], 'k--o', ms=3, lw=1,
                  label='best plan of <= k, hindsight')
    axis.set_xlabel('contact seconds')
    axis.set_ylabel('textures identified right (%)')
    plotting.legend_outside(axis)
    plotting.save(plt, figure, path,
                  'held-out recordings; band: one sd over repeats x folds x seeds')


def _plot_movements(path: Path, episodes: list[Episode], policies: tuple[str, ...]) -> None:
    counts = [[len(e.movements) for e in episodes if e.policy == p] for p in policies]
    top = max((max(c, default=0) for c in counts), default=0)
    plt, figure, axis = plotting.figure()
    axis.hist(counts, bins=np.arange(0.5, top + 1.5), label=list(policies))
    axis.set_xlabel('movements to decision (or to the budget)')
    axis.set_ylabel('episodes')
    plotting.legend_outside(axis)
    plotting.save(plt, figure, path)


def _plot_choices(path: Path, result: dict) -> None:
    names, classes = result['movements'], result['classes']
    counts = np.zeros((len(classes), len(names)), dtype=int)
    for episode in result['episodes']:
        if episode.policy == 'active':
            for movement in episode.movements:
                counts[episode.texture, movement] += 1
    plt, figure, axis = plotting.figure(classes=max(len(classes), len(names)))
    draw_confusion(axis, counts, classes, names, 'movements active chose, per true texture')
    axis.set_xlabel('movement')
    axis.set_ylabel('true texture')
    plotting.save(plt, figure, path)


def _plot_time(path: Path, table: dict) -> None:
    policies = list(table['policies'])
    plt, figure, axis = plotting.figure()
    for offset, (key, label) in enumerate((('median_contact_s', 'contact'),
                                           ('median_arm_s', 'arm'), ('median_wall_s', 'wall'))):
        axis.bar(np.arange(len(policies)) + 0.27 * (offset - 1),
                 [table['policies'][p][key] for p in policies], width=0.27, label=label)
    axis.set_xticks(range(len(policies)), policies)
    axis.set_ylabel('median seconds per identification')
    plotting.legend_outside(axis)
    plotting.save(plt, figure, path, 'arm: whole sweeps (approach, press, slide, lift); wall: '
                  'arm + classification + choice')


def _plot_reliability(path: Path, result: dict) -> None:
    plt, figure, axis = plotting.figure()
    axis.plot([0, 1], [0, 1], color='gray', lw=0.8, ls='--')
    for index, (name, held) in enumerate(result['held_out'].items()):
        bins = reliability(np.array(held['vectors']), np.array(held['labels']))
        shown = bins.counts > 0
        axis.plot(bins.confidence[shown], bins.accuracy[shown], 'o-', ms=3, lw=1,
                  color=f'C{index % 10}', label=f'{name} (error {bins.error:.3f})')
    axis.set_xlabel('confidence of the top texture')
    axis.set_ylabel('share right')
    plotting.legend_outside(axis)
    plotting.save(plt, figure, path, 'held-out sweeps, calibrated per fold')


def _plot_confusions(path: Path, table: dict) -> None:
    names, classes = table['movement_names'], table['classes']
    columns = min(4, len(names))
    rows = -(-len(names) // columns)
    plt, figure, axes = plotting.figure(rows, columns, classes=len(classes), squeeze=False)
    for axis, name in zip(axes.flat, names, strict=False):
        row = table['movements'][name]
        draw_confusion(axis, np.array(row['confusion']), classes, classes,
                       f'{name}: {100 * row["sweep_accuracy"]:.0f} % of sweeps')
    for axis in list(axes.flat)[len(names):]:
        axis.set_visible(False)
    plotting.save(plt, figure, path, 'one held-out sweep each, argmax of its calibrated vector')
