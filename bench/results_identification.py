# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Result section of active identification: policies on held-out recordings, choice cost."""

from collections.abc import Callable
from functools import partial

from results_common import FIGURES, kept_json
from scipy.stats import binomtest

from tactex_classify.identification.report import (
    against_table,
    partitions,
    saving_text,
    seconds_text,
)
from tactex_classify.identification.tradeoff import (
    at_equal_accuracy,
    leans_on_upper_bounds,
    saves_clearly,
)

SETTING_NAMES = {'default': ('default', 'every sweep counting fully'),  # short, long
                 'with_repeat_discount': ('discount', 'with the repeat discount')}
SHOWN_THRESHOLDS = (0.7, 0.9, 0.95, 0.98, 0.99)  # of the trade-off against random
TRADEOFF = ("report's episodes cut after the first step whose leading posterior exceeds a "
            'lower threshold (a policy chooses from the belief, never from the threshold, so '
            "that is the replay at that threshold); per threshold, active's accuracy and mean "
            'contact seconds per identification, against the mean seconds random needs for '
            'the same accuracy on its own trade-off (between its thresholds; "never": random '
            'does not reach it;')


def identification() -> str:
    report = kept_json('identification/identification.json')
    run = kept_json('identification/run.json')
    choice = kept_json('identification_choice.json')
    settings = report['settings']
    rows = ['| policy | accuracy | decided | median contact (s) | p90 contact (s) | median '
            'movements | median arm (s) |', '|---|---|---|---|---|---|---|']
    for policy, row in report['policies'].items():
        rows.append(f'| {policy} | {100 * row["accuracy"]:.1f} % | {100 * row["decided"]:.0f} % '
                    f'| {row["median_contact_s"]:.1f} | {row["p90_contact_s"]:.1f} | '
                    f'{row["median_movements"]:.0f} | {row["median_arm_s"]:.1f} |')
    steps = [k for k in (1, 2, 3, 5, 10, 20) if k <= min(
        len(row['accuracy_after_k']) for row in report['policies'].values())]
    same = len(set(report['contact_s'])) == 1  # then k movements are k x that contact
    after = ['| policy | ' + ' | '.join(f'after {k}' + (f' ({k * report["contact_s"][0]:g} s)'
                                                        if same else '') for k in steps)
             + ' | first three movements |',
             '|---|' + '---|' * (len(steps) + 1)]
    for policy, row in report['policies'].items():
        chosen = sorted(((name, count) for name, count in row.get(
            'first_three_movements', {}).items() if count), key=lambda kv: -kv[1])
        total = sum(count for _, count in chosen) or 1
        after.append(f'| {policy} | ' + ' | '.join(
            f'{100 * row["accuracy_after_k"][k - 1]:.1f} %' for k in steps) + ' | '
            + ', '.join(f'{name} {100 * count / total:.0f} %' for name, count in chosen[:2])
            + ' |')
    after += _best_plans_row(report, steps)
    movements = ['| movement | sweep accuracy | calibration error |', '|---|---|---|']
    for name in report['movement_names']:
        row = report['movements'][name]
        movements.append(f'| {name} | {100 * row["sweep_accuracy"]:.1f} % | '
                         f'{row["calibration_error"]:.3f} |')
    minutes, earlier = _minutes_run(run['steps'])
    chance = 100 / len(report['classes'])
    return (
        f'Measured (`python bench/bench_identification_report.py`, {minutes:.0f} min'
        + (' for convert and report, the sweeps recorded earlier by the same collect with '
           '`--bags`' if earlier else '') + ': '
        f'{len(report["classes"])} textures x {len(report["movement_names"])} movements x '
        f'{run["sweeps_per_texture_and_movement"]} simulated sweeps on scene seed '
        f'{run["scene_seed"]}, which no test uses; {partitions(settings)}'
        f'{settings["folds"]} folds grouped by '
        f'recording, {settings["seeds"]} seeds, {report["episodes"]} episodes per policy; '
        f'{settings["model"]} per movement; threshold {settings["threshold"]:g}; chance '
        f'{chance:.1f} %; `bench/results/identification/`, with '
        f'[the plots]({FIGURES}/identification/identification.md)):\n\n'
        + '\n'.join(rows) + '\n\nAccuracy after k movements ('
        + (f'every movement here holds {report["contact_s"][0]:g} s of contact; ' if same else '')
        + 'an episode that stopped earlier keeps its last leader), and the two movements each '
        'policy took most often among its first three'
        + ('; under them, the best plan of at most k movements fixed in advance, picked in '
           'hindsight on the same held-out sweeps (optimistic for plans fixed in advance for '
           'every episode, such as fixed and round-robin while they run to k; a policy that '
           'stops on its threshold, or random, which draws a plan per episode, can pass it; '
           'flattered by the luck of picking among many plans; this run took plans of exactly '
           'k, the same best figures here as they rise with k), and the plan picked on the '
           "other folds' held-out sweeps, scored on each fold's (the luck taken out)"
           if report.get('best_plans') else '') + ':\n\n' + '\n'.join(after)
        + (_against_goals(report) if same else '')
        + ''.join('\n' + line for line in against_table(report))
        + _without_discount(report, steps)
        + _dev_equal_accuracy(report)
        + '\n\nEach movement on its own, one held-out sweep '
        '(`movement_confusions.png` has the confusion matrices):\n\n' + '\n'.join(movements)
        + _choice_time(choice) + '\n')


def _choice_time(choice: dict) -> str:
    """How long choosing the next movement takes, from bench_identification.py's kept rows."""
    widest = max(row['sweeps_per_cell'] for row in choice['rows'])
    rows = {(row['sweeps_per_cell'], row['belief'], row['setting'], row['policy']): row
            for row in choice['rows']}
    within = {(setting, policy): rows[widest, 'identifications', setting, policy]['choice_ms']
              for setting in ('default', 'discount') for policy in ('active', 'active-sampled')}
    worst = max(row['choice_ms'][2] for row in choice['rows']
                if row['belief'] == 'identifications')
    ratios = {setting: [rows[widest, 'uniform', setting, 'active'][key][0]
                        / rows[widest, 'uniform', setting, 'active']['choice_ms'][0]
                        for key in ('row_by_row_ms', 'per_movement_ms')]
              for setting in ('default', 'discount')}
    return (
        f'\n\nChoosing the next movement (`python bench/bench_identification.py`, '
        f'{choice["textures"]} textures x {choice["movements"]} movements, the target '
        f'{choice["target_ms"]:g} ms; {choice["cores"]} cores at a load of '
        f'{choice["load_average"]:.1f}): over every choice of whole identifications with '
        f'{widest} held-out sweeps per texture and movement, median and p99 '
        f'{_ms(within["default", "active"])} for active and '
        f'{_ms(within["default", "active-sampled"])} for active-sampled with every sweep '
        f'counting fully, {_ms(within["discount", "active"])} and '
        f'{_ms(within["discount", "active-sampled"])} with a repeat discount of '
        f'{choice["repeat_discount"]:g} (the table makes a movement\'s discounted products '
        'the first time its number of repeats is asked, and keeps them); the slowest single '
        f'choice of any identification took {worst:.2f} ms. With {widest}, the uniform '
        f'belief\'s gain took {ratios["default"][0]:.0f}x (discount: '
        f'{ratios["discount"][0]:.0f}x) longer (median) in one exponential pass over every '
        f'held-out sweep and {ratios["default"][1]:.0f}x ({ratios["discount"][1]:.0f}x) '
        'computed movement by movement.')


def _ms(times: list[float]) -> str:
    """A kept row's median and p99."""
    return f'{times[0]:.2f} / {times[1]:.2f} ms'


def _against_goals(report: dict) -> str:
    """The issue's two comparisons, from the after-k curves (every movement as long)."""
    seconds, policies = report['contact_s'][0], report['policies']
    if not {'active', 'fixed', 'random'} <= set(policies):
        return ''
    fixed, active = policies['fixed'], policies['active']['accuracy_after_k']
    goal = 0.6 * fixed['median_contact_s']
    reached = _first_reaching(active, fixed['accuracy'] - 0.01)
    within = int(goal // seconds + 1e-9)
    if within < 1:
        return ''
    plans = {plan['movements']: plan for plan in report.get('best_plans', [])}
    bound = (f'; the best plan of {within} in hindsight {100 * plans[within]["accuracy"]:.1f} %, '
             f'chosen elsewhere {100 * plans[within]["chosen_elsewhere"]:.1f} %'
             if within in plans and plans[within]['chosen_elsewhere'] is not None else '')
    random = policies['random']['accuracy_after_k']
    later = [k for k, right in enumerate(random, 1)
             if (_first_reaching(active, right - 1e-12) or k + 1) > k]
    return (
        f'\n\nAgainst `fixed` (goal: its final accuracy, within 1 point, in at most 60 % of its '
        f'median contact): fixed ends at {100 * fixed["accuracy"]:.1f} % after a median '
        f'{fixed["median_contact_s"]:g} s; active '
        + (f'first reaches {100 * fixed["accuracy"] - 1:.1f} % after {reached} movements '
           f'({reached * seconds:g} s, '
           f'{100 * reached * seconds / fixed["median_contact_s"]:.0f} % of fixed\'s)'
           if reached else f'never reaches {100 * fixed["accuracy"] - 1:.1f} %') + '. '
        f'Within 60 % ({goal:g} s, {within} movement{"" if within == 1 else "s"}) active has '
        f'{100 * active[within - 1]:.1f} %{bound}. Against `random` (goal: fewer contact '
        'seconds at equal accuracy): of the accuracies random reaches after 1 to '
        f'{len(random)} movements, active reaches '
        + ('every one as early or earlier' if not later else
           f'all but {len(later)} as early or earlier (later after '
           f'{", ".join(map(str, later[:8]))}{"..." if len(later) > 8 else ""} movements of '
           'random)') + '.')


def identification_seeds() -> str:
    """The two goals on fresh scene seeds, each apart and pooled (bench_identification_seeds)."""
    kept = kept_json('identification_seeds/seeds.json')
    settings = kept_json(f'identification_seeds/{kept["scene_seeds"][0]}.json')['settings']
    minutes, earlier = _minutes_run(kept['steps'])
    seeds = len(kept['scene_seeds'])
    pooled, discounted = kept['pooled'], kept['with_repeat_discount']
    return (
        'Measured (`python bench/bench_identification_seeds.py`'
        + (', the reports made earlier by the same commands and read with `--reports`'
           if earlier else f', {minutes:.0f} min') + '): the same collect, convert '
        f'and report as above ({kept["sweeps_per_texture_and_movement"]} sweeps per texture '
        f'and movement, {partitions(settings)}{settings["folds"]} folds, '
        f'{settings["seeds"]} seeds, {settings["model"]} per movement) on {seeds} fresh '
        'scene seeds, none used by a test or looked at while active was built. The '
        "margin is active's accuracy after 60 % of fixed's median contact, less fixed's "
        f'final accuracy, plus {100 * kept["goal_tolerance"]:g} point: at or above zero the '
        'goal against fixed is met. Its interval is a bootstrap over the textures (pooled: '
        "over every seed's textures, each against its own seed's fixed); "
        f"[the plot]({FIGURES}/identification_seeds/seeds.png), and each seed's report "
        'beside it. By default, every sweep counting fully:\n\n'
        + _seed_rows(kept, kept['scene_seeds'])
        + "\n\nThe same folds and sweeps with a fitted discount of a movement's repeats "
        '(`--repeat-discount`):\n\n'
        + _seed_rows(discounted, kept['scene_seeds'])
        + f'\n\nThe goal against fixed is met on {pooled["met"]} of {seeds} fresh seeds; '
        f'pooled, the margin is {_points(pooled)} points'
        + _verdict(pooled, ': on these seeds the policies cannot be told apart on this goal')
        + f'. With the discount it is met on {discounted["pooled"]["met"]} of {seeds}, '
        f'pooled {_points(discounted["pooled"])}{_verdict(discounted["pooled"])}.'
        + _equal_accuracy(kept, discounted, kept['scene_seeds'])
        + _on_tradeoff(kept, discounted, kept['scene_seeds'])
        + _declared_tests([kept[key] for key in kept.get('declared', ())]))


def _declared_tests(tests: list[dict]) -> str:
    """Every declared test in the order declared, each set of seeds with its untested reading."""
    text = ''
    for index, test in enumerate(tests):
        if test.get('pending'):
            text += _pending(test)
            continue
        declared_on_seeds = {other['policy'] for other in tests
                             if other['scene_seeds'] == test['scene_seeds']}
        text += (_confirmatory(test, first=index == 0, shown=tests[:index])
                 + _read_after(test, declared_on_seeds))
    return text


def _pending(declared: dict) -> str:
    """A declared test whose seeds' reports are not in yet: what was declared, no figures."""
    seeds = declared['scene_seeds']
    return (f'\n\n**The declared tests of {declared["policy"]} on scene seeds {seeds[0]} to '
            f'{seeds[-1]}.** Declared (`DECLARED` in bench/bench_identification_seeds.py) before '
            f'any of the {len(seeds)} scenes was collected: {declared["chosen"]}; '
            f'{SETTING_NAMES[declared["setting"]][1]}. Its reports are not in yet.')


def _confirmatory(declared: dict, first: bool, shown: list[dict]) -> str:
    """One policy's declared tests, one per goal, on further fresh seeds, both settings.

    `first`: the first declared (it follows the exploration; a later one follows it).
    `shown`: the declared tests rendered before it; where one of them had the same seeds,
    their reports are pointed to, not tabulated again.
    """
    seeds, chosen = declared['scene_seeds'], declared['setting']
    chooser = declared['policy']
    same_seeds = next((test for test in shown if test['scene_seeds'] == seeds), None)
    policies = (chooser,) if same_seeds else (chooser, 'random', 'fixed')
    seed_rows, test_rows = [], []
    for setting in (chosen, *(name for name in SETTING_NAMES if name != chosen)):
        short = SETTING_NAMES[setting][0]
        for seed in seeds:
            folder = '' if setting == 'default' else f'{setting}/'
            report = kept_json(f'identification_seeds/{folder}{seed}.json')['policies']
            seed_rows.append(f'| {seed}, {short} | ' + ' | '.join(
                f'{100 * report[p]["accuracy"]:.1f} %, {report[p]["median_contact_s"]:g} s'
                for p in policies) + ' |')
        saving, goal = declared[setting]['against_random'], declared[setting]['against_fixed']
        tested = setting == chosen
        test_rows.append(
            f'| {short} ({"declared" if tested else "not tested"}) | {saving_text(saving)} | '
            f'{100 * saving["never_share"]:.0f} % | {_passed(saving, tested)} | '
            f'{_goal_text(goal)} | {goal["budget_s"]:g} s | {_passed(goal, tested)} |')
    passed = declared[chosen]
    verdict = {(True, True): 'both tests pass', (False, False): 'neither test passes',
               (True, False): 'the test against random passes, the one against fixed fails',
               (False, True): 'the test against fixed passes, the one against random fails'}[
        passed['against_random']['passed'], passed['against_fixed']['passed']]
    minutes, earlier = _minutes_run(declared['steps'])
    return (
        ('\n\n**The declared tests.** The seeds above explored. Before any report of scene '
         if first else f'\n\n**The declared tests of {chooser} on scene seeds {seeds[0]} to '
         f'{seeds[-1]}.** Before any report of scene ')
        + f'seeds {", ".join(map(str, seeds[:-1]))} and {seeds[-1]} was read, one test per goal '
        f'of {chooser} was declared on them (`DECLARED` in bench/bench_identification_seeds.py), '
        f'{declared["chosen"]}: {SETTING_NAMES[chosen][1]}, over the '
        f"{len(seeds)} seeds' {passed['units']} textures pooled, with 95 % intervals from "
        f'{declared["resamples"]} draws of them. Against random: the seconds {chooser} saves '
        'at equal accuracy, averaged over '
        f'{_thresholds_text([f"{t:g}" for t in declared["thresholds"]])} (one interval for '
        'the stretch, not one per threshold), passing where the interval lies above zero and '
        f"not on upper bounds. Against fixed: the mean contact {chooser}'s trade-off needs for "
        f"fixed's pooled final accuracy less {100 * declared['goal_tolerance']:g} point, "
        "passing where the interval's high end is within "
        f"{100 * declared['goal_share']:g} % of fixed's median contact (the smallest of the "
        "seeds'). The other setting is shown beside, not tested. "
        + (f"The seeds' reports are those of {same_seeds['policy']}'s tests above (random's "
           f"and fixed's figures there); {chooser}'s" if same_seeds else
           'Each seed, the same commands as above'
           + (' (the reports made earlier and read with `--reports`)' if earlier
              else f' ({minutes:.0f} min)')) + ':\n\n'
        '| scene seed, setting | ' + ' | '.join(f'{p}: accuracy, median contact'
                                                for p in policies) + ' |\n'
        + '|---' * (len(policies) + 1) + '|\n' + '\n'.join(seed_rows)
        + '\n\n| setting | seconds saved against random [95 %] | draws where random never '
        f"reaches {chooser}'s accuracy at some threshold (a lower bound) | passed | fixed's "
        "final accuracy after (s; share of fixed's mean) | "
        f"{100 * declared['goal_share']:g} % of fixed's median | passed |\n"
        + '|---' * 7 + '|\n' + '\n'.join(test_rows)
        + f'\n\n{SETTING_NAMES[chosen][1].capitalize()}, the declared setting, {verdict}.')


def identification_power() -> str:
    """How often a declared test of each size passes, drawn from the kept seeds."""
    kept = kept_json('identification_power/power.json')
    rows = []
    first = next(iter(next(iter(kept['settings'].values())).values()))
    sizes = [cell['scene_seeds'] for cell in first['power']]  # every row's, by the bench
    for setting, policies in kept['settings'].items():
        for policy, row in policies.items():
            cells = [f'{100 * cell["both"]:.0f} % ({100 * cell["against_random"]:.0f}, '
                     f'{100 * cell["against_fixed"]:.0f})' for cell in row['power']]
            rows.append(f'| {policy}, {SETTING_NAMES[setting][0]} | {len(row["pilot_seeds"])} | '
                        + ' | '.join(cells) + ' |')
    return (
        'Measured (`python bench/bench_identification_power.py`): each of '
        f'{kept["draws"]} simulated declared tests per size draws its scene seeds in two '
        "stages from every kept seed's report that replayed the policy (a population as large "
        "as the pilot, then the test's seeds from it, each with its textures) and runs both "
        "goals' tests on them as a declared test does "
        f'({_thresholds_text([f"{t:g}" for t in kept["thresholds"]])}, '
        f'{kept["resamples"]} resamples each); the share that passes both, and in brackets '
        "each alone (against random, against fixed); [the plot]"
        f'({FIGURES}/identification_power/power.png):\n\n'
        '| policy, setting | kept seeds drawn from | '
        + ' | '.join(f'{size} seeds' for size in sizes) + ' |\n'
        + '|---' * (len(sizes) + 2) + '|\n' + '\n'.join(rows))


def _read_after(declared: dict, declared_on_seeds: set[str]) -> str:
    """What a declared test's seeds say of the policies no test on them declared, untested.

    Kept with the first test declared on those seeds only; '' for the others.
    """
    rows = [f'| {policy}, {SETTING_NAMES[setting][0]} | '
            f'{saving_text(tests["against_random"])} | {_goal_text(tests["against_fixed"])} |'
            for setting, policies in declared.get('read_after', {}).items()
            for policy, tests in policies.items() if policy not in declared_on_seeds]
    if not rows:
        return ''
    return ('\n\nRead after the fact on the same seeds, not tested: the same two readings of '
            'the other policies the reports replayed.\n\n'
            "| policy, setting | seconds saved against random [95 %] | fixed's final accuracy "
            "after (s; share of fixed's mean) |\n|---|---|---|\n" + '\n'.join(rows))


def _minutes_run(steps: list[dict]) -> tuple[float, bool]:
    """The kept steps' minutes, and whether some ran earlier (no seconds kept)."""
    return (sum(step['seconds'] or 0.0 for step in steps) / 60,
            any(step['seconds'] is None for step in steps))


def _passed(test: dict, tested: bool) -> str:
    """'yes' or 'no' for a declared test, '-' for one shown beside it untested."""
    return ('yes' if test['passed'] else 'no') if tested else '-'


def _on_tradeoff(plain: dict, discounted: dict, scene_seeds: list[int]) -> str:
    """Both goals on the trade-offs with intervals, per seed and pooled; '' if not kept."""
    if 'on_tradeoff' not in plain or 'on_tradeoff' not in discounted:
        return ''
    names = [*map(str, scene_seeds), 'pooled']
    lines, above, pooled_goals = [], {}, {}
    budgets = {goal['goal_contact_s'] for goals in (plain, discounted)
               for goal in goals['against_fixed'].values()}
    budget = budgets.pop() if len(budgets) == 1 else None  # 60 % of fixed's median contact
    thresholds = sorted({entry['threshold'] for goals in (plain, discounted)
                         for row in goals['on_tradeoff'].values() for entry in row['saving']})
    for label, goals in (('default', plain), ('discount', discounted)):
        for name in names:
            row = goals['on_tradeoff'][name]
            saving = {entry['threshold']: entry for entry in row['saving']}
            cells = [_saving_cell(saving[t]) if t in saving else '' for t in thresholds]
            lines.append(f'| {name}, {label} | ' + ' | '.join(cells) + ' | '
                         + _goal_text(row['fixed_goal']) + ' |')
        pooled = goals['on_tradeoff']['pooled']
        above[label] = [f'{entry["threshold"]:g}' for entry in pooled['saving']
                        if saves_clearly(entry)]
        pooled_goals[label] = pooled['fixed_goal']
    within = [label for label, goal in pooled_goals.items() if budget is not None
              and goal.get('seconds_high') is not None and goal['seconds_high'] <= budget]
    return (
        "\n\nBoth goals read on the trade-offs, with intervals: the textures resampled with "
        "replacement (pooled: every seed's), both trade-offs rebuilt from each draw. Against "
        "random, the mean contact seconds active saves at each threshold (random's seconds "
        "for active's accuracy less active's; \">=\": random never reaches it and its longest "
        'mean contact stands in, a lower bound; "<=": an upper bound; "*": more than 2.5 % '
        'of the draws on an upper bound, which lifts the low end); against fixed, the mean '
        "contact active's trade-off needs for fixed's final accuracy less 1 point, and its "
        "share of fixed's mean contact (pooled: one trade-off per policy over every seed's "
        "textures, fixed's pooled final accuracy the target); in brackets the 95 % intervals "
        f'([the plot]({FIGURES}/identification_seeds/saving.png)):\n\n'
        '| scene seed, setting | ' + ' | '.join(f'saved at {t:g} (s)' for t in thresholds)
        + " | fixed's final accuracy after (s; share of fixed's mean) |\n"
        + '|---' * (len(thresholds) + 2) + '|\n' + '\n'.join(lines)
        + '\n\nPooled, the interval of the seconds saved lies above zero, and not on upper '
        'bounds, at '
        + _by_setting({label: _thresholds_text(shown) for label, shown in above.items()})
        + "; active's trade-off reaches fixed's final accuracy after "
        + _by_setting({label: _goal_text(goal) for label, goal in pooled_goals.items()})
        + (f", against the goal's {budget:g} s (60 % of fixed's median contact, its cap of "
           'ten sweeps in every report, not resampled): the interval under it '
           + _by_setting({label: '' for label in within}) if within else '') + '.')


def _saving_cell(row: dict) -> str:
    """`saving_text`, starred where over 2.5 % of the draws stand on an upper bound."""
    return saving_text(row) + ('*' if leans_on_upper_bounds(row) else '')


def _thresholds_text(shown: list[str]) -> str:
    """'no threshold', 'threshold 0.7' or 'thresholds 0.7, 0.95 and 0.98'."""
    if len(shown) < 2:
        return f'threshold {shown[0]}' if shown else 'no threshold'
    return f'thresholds {", ".join(shown[:-1])} and {shown[-1]}'


def _by_setting(texts: dict[str, str]) -> str:
    """'TEXT by default and TEXT with the discount', per setting label."""
    return ' and '.join(f'{text} {"with the discount" if label == "discount" else "by default"}'
                        .strip() for label, text in texts.items())


def _goal_text(goal: dict) -> str:
    """'10.4 s [8.8, 13.8]; 51 % [47, 65]', '<= ...' (an upper bound) or 'never'."""
    if not goal or goal['seconds'] is None:
        return 'never'
    if goal['share'] is None:
        return f'{goal["seconds"]:.1f} s'
    return (f'{"<= " if goal["at_most"] else ""}{goal["seconds"]:.1f} s '
            f'{_bracket(goal["seconds_low"], goal["seconds_high"], 1, 1)}; '
            f'{100 * goal["share"]:.0f} % {_bracket(goal["low"], goal["high"], 100, 0)}')


def _bracket(low: float | None, high: float | None, scale: float, digits: int) -> str:
    """'[8.8, 13.8]' scaled, 'never' for an end that is not finite."""
    return '[' + ', '.join('never' if end is None else f'{scale * end:.{digits}f}'
                           for end in (low, high)) + ']'


def _equal_accuracy(plain: dict, discounted: dict, scene_seeds: list[int]) -> str:
    """Against random at equal accuracy, per seed and threshold, both ways; '' if not kept."""
    rows = {(f'{seed}, {label}', label): goals['against_random'][str(seed)].get(
                'at_equal_accuracy', [])
            for label, goals in (('default', plain), ('discount', discounted))
            for seed in scene_seeds}
    if not all(rows.values()):
        return ''
    return (
        '\n\nWhat accuracy costs in time, against `random` at equal accuracy: each '
        f'{TRADEOFF} [the plot]({FIGURES}/identification_seeds/tradeoff.png)). '
        + _equal_accuracy_table('scene seed, setting', rows)
        + "\n\nThe goal against fixed read the same way (active stopped by a lower "
        "threshold): the mean contact active's trade-off needs for fixed's final accuracy "
        "less 1 point, as a share of fixed's mean and of its median contact (<=: an upper "
        "bound, active's lowest threshold already reaches it): "
        + '; '.join(f'{label}, ' + ', '.join(_fixed_share(goals['fixed_on_tradeoff'][str(seed)])
                                            for seed in scene_seeds)
                    for label, goals in (('by default', plain), ('with the discount',
                                                                 discounted))) + '.')


def _equal_accuracy_table(heading: str, rows: dict[tuple[str, str], list[dict]]) -> str:
    """'Of the pairs shown, active needs fewer ...' and the table, one row per (name, setting).

    `rows`: per (row name, setting), `tradeoff.at_equal_accuracy` rows against random. A
    pair counts for active only where random's seconds are measured, not an upper bound;
    where random never reaches active's accuracy it is counted apart.
    """
    lines, fewer, never = [], {}, {}
    for (name, setting), equal_rows in rows.items():
        equal = {row['threshold']: row for row in equal_rows}
        cells = []
        for threshold in SHOWN_THRESHOLDS:
            row = equal.get(threshold)
            if row is None:
                cells.append('')
                continue
            other, at_most = row['other_seconds'], row.get('other_at_most', False)
            cells.append(f'{100 * row["accuracy"]:.1f} %: {row["seconds"]:.1f} s vs '
                         + seconds_text(other, at_most) + ('' if other is None else ' s'))
            fewer.setdefault(setting, []).append(
                other is not None and not at_most and row['seconds'] < other)
            never[setting] = never.get(setting, 0) + (other is None)
        lines.append(f'| {name} | ' + ' | '.join(cells) + ' |')
    return ('Of the (row, threshold) pairs shown, active needs fewer seconds than random in '
            + ' and '.join(f'{sum(won)} of {len(won)} {setting}'
                           + (f" (random never reaching active's accuracy in {never[setting]} "
                              'more)' if never[setting] else '')
                           for setting, won in fewer.items()
                           ).replace('discount', 'with the discount') + ':\n\n'
            f'| {heading} | ' + ' | '.join(f'threshold {t:g}' for t in SHOWN_THRESHOLDS)
            + ' |\n' + '|---' * (len(SHOWN_THRESHOLDS) + 1) + '|\n' + '\n'.join(lines))


def _dev_equal_accuracy(report: dict) -> str:
    """The development report against random at equal accuracy, both ways; '' if not kept."""
    discounted = kept_json('identification/with_repeat_discount/identification.json')
    rows = {(label, label): at_equal_accuracy(table.get('tradeoff', {}).get('curves', {})).get(
                'random', []) for label, table in (('default', report),
                                                    ('discount', discounted))}
    if not all(rows.values()):
        return ''
    savings = {label: table.get('tradeoff', {}).get('active_saving', {}).get('random')
               for label, table in (('default', report), ('discount', discounted))}
    return ('\n\nAgainst `random` at equal accuracy, both ways: the '
            f'{TRADEOFF} `tradeoff.png` among the plots). '
            + _equal_accuracy_table('setting', rows)
            + ('\n\nWith 95 % intervals over the 12 textures (the last table of '
               '`identification.md`), the seconds active saves lie above zero, and not on '
               "random's upper bounds, at " + _by_setting(
                   {label: _thresholds_text([f'{row["threshold"]:g}' for row in saving
                                             if saves_clearly(row)])
                    for label, saving in savings.items()}) + '.'
               if all(savings.values()) else ''))


def _fixed_share(row: dict) -> str:
    """'9.3 s (47 %, 37 %)': active's seconds, their shares of fixed's mean and median."""
    seconds = row['active_mean_contact_s']
    if seconds is None:
        return 'never'
    return (f'{seconds_text(seconds, row.get("at_most", False))} s '
            f'({100 * seconds / row["fixed_mean_contact_s"]:.0f} %, '
            f'{100 * seconds / row["fixed_median_contact_s"]:.0f} %)')


def _seed_rows(goals: dict, scene_seeds: list[int]) -> str:
    """Per seed: fixed, active at 60 % of its contact, the margin, and random beside; pooled."""
    first = goals['against_random'][str(scene_seeds[0])]['policies']
    compared = [p for p in ('active', 'random', 'active-realized') if p in first]
    rows = ['| scene seed | fixed: final, median contact | active at 60 % of it | margin '
            f'[95 % interval] | {" / ".join(compared)}: accuracy, median contact | active vs '
            'random (contact times above / below zero) |', '|---|---|---|---|---|---|']
    for seed in map(str, scene_seeds):
        goal, random = goals['against_fixed'][seed], goals['against_random'][seed]
        finals = [random['policies'][policy] for policy in compared]
        rows.append(
            f'| {seed} | {100 * goal["fixed_accuracy"]:.1f} %, '
            f'{goal["fixed_median_contact_s"]:g} s | {100 * goal["accuracy"]:.1f} % after '
            f'{goal["goal_contact_s"]:g} s | {_points(goal)} | '
            + ' / '.join(f'{100 * row["accuracy"]:.1f}' for row in finals) + ' %, '
            + ' / '.join(f'{row["median_contact_s"]:g}' for row in finals) + ' s | '
            f'{random["times_above"]} / {random["times_below"]} of {random["times"]} |')
    pooled = goals['pooled']
    rows.append(f'| pooled ({pooled["units"]} seed x texture units) |  |  | {_points(pooled)} '
                '|  |  |')
    return '\n'.join(rows)


def _verdict(pooled: dict, undecided: str = '') -> str:
    """Where the pooled margin's interval lies, as a clause; `undecided` follows a span of zero."""
    return (', above zero throughout its interval' if pooled['low'] > 0 else
            ', below zero throughout its interval' if pooled['high'] < 0 else
            ', its interval spanning zero' + undecided)


def _points(goal: dict) -> str:
    """A margin and its interval, in points."""
    return (f'{100 * goal["margin"]:+.1f} [{100 * goal["low"]:+.1f}, '
            f'{100 * goal["high"]:+.1f}]')


def _first_reaching(curve: list[float], level: float) -> int | None:
    """The first k (from 1) whose accuracy after k movements reaches `level`, or None."""
    return next((k for k, right in enumerate(curve, 1) if right >= level), None)


def _best_plans_row(report: dict, steps: list[int]) -> list[str]:
    """The best plan of k movements, in hindsight and chosen on the other folds, as rows."""
    plans = {plan['movements']: plan for plan in report.get('best_plans', [])}
    if not plans:
        return []
    longest = max(k for k in steps if k in plans)
    rows = []
    for label, key in (('best plan, hindsight', 'accuracy'),
                       ('best plan, chosen elsewhere', 'chosen_elsewhere')):
        cells = [f'{100 * plans[k][key]:.1f} %' if k in plans and plans[k][key] is not None
                 else '' for k in steps]
        last = (f'at {longest}: ' + ', '.join(f'{name} x{count}' for name, count in
                                               plans[longest]['plan'].items())
                if key == 'accuracy' else 'per fold, the plan best on the other folds')
        rows.append(f'| {label} | ' + ' | '.join(cells) + f' | {last} |')
    return rows


def _without_discount(report: dict, steps: list[int]) -> str:
    """The same replay with the repeat discount fitted, beside the default one (none)."""
    discounted = kept_json('identification/with_repeat_discount/identification.json')
    rows = ['| policy | repeat discount | accuracy | ' + ' | '.join(f'after {k}' for k in steps)
            + ' |', '|---|---|---|' + '---|' * len(steps)]
    for policy in [p for p in report['policies'] if p in discounted['policies']]:
        for name, table in (('none', report), ('fitted', discounted)):
            row = table['policies'][policy]
            rows.append(f'| {policy} | {name} | {100 * row["accuracy"]:.1f} % | ' + ' | '.join(
                f'{100 * row["accuracy_after_k"][min(k, len(row["accuracy_after_k"])) - 1]:.1f} %'
                for k in steps) + ' |')
    return ('\n\nThe same folds, seeds and held-out sweeps with a fitted discount of a '
            "movement's repeats (`--repeat-discount`; c per fold "
            f'{", ".join(f"{c:g}" for c in discounted["repeat_discount"])}, the exponent '
            f'{", ".join(f"{t:.2f}" for t in discounted["tempering"])} with it and '
            f'{", ".join(f"{t:.2f}" for t in report["tempering"])} without):\n\n'
            + '\n'.join(rows))


# The live runs kept with a generated section (bench_identify_live.py's LIVE_RUNS less
# identify_live_init, of which none is kept), each rendered by _live_section.
LIVE_SECTIONS = ('identify_live', 'identify_live_sweeps', 'identify_live_sweeps_init',
                 'identify_live_sweeps_init_sweeps', 'identify_live_sweeps_init_sweeps_realized',
                 'identify_live_sweeps_rounds')


def live_sections() -> dict[str, Callable[[], str]]:
    """Each kept live run's section: its name, and what renders it."""
    return {name: partial(_live_section, f'{name}.json') for name in LIVE_SECTIONS}


def _bench_options(kept: dict, goals_per_texture: float, name: str) -> str:
    """The bench's options that reproduce a kept live run (the checkpoint as PRETRAINED).

    Its training, its goals per texture if not one, its model with the model's training
    options if not the default MiniRocket, and `--keep` where `name` is not the default.
    """
    training = (f'--training sweeps --sweeps {kept["sweeps_per_texture_and_movement"]} '
                if kept.get('training') == 'sweeps' else '')
    episodes = f'--episodes {goals_per_texture:g} ' if goals_per_texture != 1 else ''
    options = kept.get('training_options', [])
    if '--init' in options:
        options = [*options]
        options[options.index('--init') + 1] = 'PRETRAINED'
    model = (' '.join(['--model', kept['model'], *options]) + ' '
             if kept['model'] != 'minirocket' or options else '')
    from bench_identify_live import default_kept_file
    default = default_kept_file(kept.get('training', 'collect'), bool(kept.get('pretrained')))
    keep = f'--keep {name} ' if name != default else ''
    discount = '--repeat-discount ' if kept.get('repeat_discount_fitted') else ''
    policy = f'--policy {kept["policy"]} ' if kept.get('policy', 'active') != 'active' else ''
    return f'{training}{episodes}{model}{discount}{policy}{keep}--work DIR'


def _fine_tuned_from(kept: dict) -> str:
    """', by fine-tuning (its options) a checkpoint pretrained on ...', or '' if not."""
    pretrained = kept.get('pretrained')
    if not pretrained:
        return ''
    options = kept['training_options']
    named = dict(zip(options[::2], options[1::2], strict=True))
    recipe = [f'{option.lstrip("-")} {named[option]}' for option in ('--profile', '--epochs')
              if option in named]
    recipe.append(f'scaling {named["--scaling"]}' if '--scaling' in named else
                  f"the checkpoint's {pretrained['scaling']} scaling")
    source = kept_json('identification_init.json')['source']
    origin = (pretrained['recipe'] if 'recipe' in pretrained else
              f"the learning curves' set ({source['recordings']} recordings of "
              f"{source['classes']} textures, the set bench_identification_init.py pretrains "
              'on)' if pretrained['trained_on'] == source['digest'] else
              f'the set of digest {pretrained["trained_on"][:16]}' if pretrained['trained_on']
              else 'a set the checkpoint does not name')
    return (f', by fine-tuning ({", ".join(recipe)}) a {pretrained["model"]} pretrained on '
            f'{origin}')


def _live_interval(episodes: list[dict], offline: float) -> str:
    """The live leader's share right with its 95 % Wilson interval, against the offline one."""
    right = sum(episode['leader'] == episode['truth'] for episode in episodes)
    interval = binomtest(right, len(episodes)).proportion_ci(method='wilson')
    holds = interval.low <= offline <= interval.high
    return (f'Live, the leader at the end was right in {right} of {len(episodes)} goals (95 % '
            f'Wilson interval {100 * interval.low:.1f}-{100 * interval.high:.1f} %), which '
            f'{"holds" if holds else "excludes"} the offline figure'
            f'{": these goals alone cannot tell the two apart" if holds else ""}. ')


def _live_section(name: str) -> str:
    kept = kept_json(name)
    live, offline, probe = kept['live'], kept['offline'], kept['probe']
    policy = kept.get('policy', 'active')  # the policy run live, and replayed offline
    textures = sorted({episode['truth'] for episode in kept['episodes']})
    goals_per_texture = live['episodes'] / max(len(textures), 1)
    movements = kept.get('movements', ['8'] * 8)
    minutes = kept['live_seconds'] / 60
    sweeps = kept['sweeps_per_texture_and_movement']
    trained_on = (f'{len(textures)} textures x {len(movements)} movements x {sweeps} sweeps '
                  'recorded through the sweep action on their parts of the probed pathway, '
                  f'the way identify_node sweeps ({", ".join(movements)}: those the pathway '
                  'holds)' if kept.get('training') == 'sweeps' else
                  f'{len(textures)} textures x {len(movements)} movements x {sweeps} '
                  f'`sim collect` sweeps (scene seed {kept["scene_seed"]}, which no test uses)')
    trained_on += _fine_tuned_from(kept)
    rows = ['| | accuracy | decided | median movements | median contact (s) | p90 contact (s) |',
            '|---|---|---|---|---|---|',
            f'| live, identify_node | {100 * live["accuracy"]:.1f} % '
            f'(leader {100 * live["leader_accuracy"]:.1f} %) | {100 * live["decided"]:.0f} % | '
            f'{live["median_movements"]:.0f} | {live["median_contact_s"]:.1f} | '
            f'{live["p90_contact_s"]:.1f} |',
            f'| offline replay, {policy} | {100 * offline["accuracy"]:.1f} % | | '
            f'{offline["median_movements"]:.0f} | {offline["median_contact_s"]:.1f} | '
            f'{offline["p90_contact_s"]:.1f} |']
    chosen: dict[str, int] = {}
    for episode in kept['episodes']:
        for movement in episode['movements']:
            chosen[movement] = chosen.get(movement, 0) + 1
    update = kept.get('bundle', {})
    fitted = (f' (tempering {update["tempering"]:.2f}, repeat discount '
              f'{update["repeat_discount"]:g})' if update else '')
    return (
        'Measured live (`python bench/bench_identify_live.py '
        f'{_bench_options(kept, goals_per_texture, name)}`, {minutes:.0f} min '
        f'of live identification): a bundle of {kept["model"]} per movement{fitted} trained '
        f'on {trained_on}; the system launched in simulation, {probe["points"]} probes asked '
        f'along {1e3 * kept["span_m"]:.0f} mm of which {probe["contacts"]} gave a contact '
        f'(the pathway), then {live["episodes"]} Identify goals ({policy}, threshold 0.99, at '
        f'most {kept["budget_movements"]} movements), '
        f'{"one" if goals_per_texture == 1 else f"{goals_per_texture:g}"} per texture; '
        f'{live["failed"]} '
        'failed. Beside it, `tactex report identification` on the same dataset with the '
        f'same model and policy ({kept["offline_episodes"]} held-out episodes, '
        f'{kept.get("offline_folds", 2)} folds):\n\n'
        + '\n'.join(rows)
        + f'\n\nOffline, {policy} was {100 * kept["offline_accuracy_after_budget"]:.1f} % right '
        f'after {kept["budget_movements"]} movements, the live budget. '
        + _live_interval(kept['episodes'], kept['offline_accuracy_after_budget']) +
        f'A live goal took a median {live["median_wall_s"]:.0f} s of wall time (the arm '
        'travels between sweeps). Movements the live goals ran: '
        + ', '.join(f'{movement} {count}' for movement, count in
                    sorted(chosen.items(), key=lambda kv: -kv[1])) + '.'
        + _offline_ranking(kept, policy) + _checkpoint_alone(kept)
        + (f' {kept["note"]}' if kept.get('note') else '') + '\n')


def _checkpoint_alone(kept: dict) -> str:
    """How right the pretrained checkpoint alone, not fine-tuned, was on these sweeps."""
    alone = kept.get('pretrained', {}).get('alone_sweep_accuracy')
    if not alone:
        return ''
    return (f' The pretrained {kept["pretrained"]["model"]} alone, not fine-tuned, named a '
            'sweep right for ' + ', '.join(
                f'{name} {100 * share:.1f} %' for name, share in
                sorted(alone.items(), key=lambda kv: -kv[1])) + '.')


def _offline_ranking(kept: dict, policy: str) -> str:
    """What the replay of `policy` chose first and how right each movement was alone."""
    first, right = kept.get('offline_first_three'), kept.get('offline_sweep_accuracy')
    if not first or not right:  # kept before the bench recorded them
        return ''
    return (f" Offline, {policy}'s first three movements were "
            + ', '.join(f'{name} {count}' for name, count in
                        sorted(first.items(), key=lambda kv: -kv[1]))
            + f' (of {sum(first.values())}); a single held-out sweep was right for '
            + ', '.join(f'{name} {100 * share:.1f} %' for name, share in
                        sorted(right.items(), key=lambda kv: -kv[1])) + '.')


def identification_init() -> str:
    """Per-movement models fine-tuned from a pretrained one, beside scratch and MiniRocket."""
    kept = kept_json('identification_init.json')
    reports = kept['reports']
    first = next(iter(reports.values()))
    seconds = first['contact_s'][0]
    steps = [k for k in (1, 2, 3, 5) if all(
        len(r['policies'][p]['accuracy_after_k']) >= k for r in reports.values()
        for p in ('active', 'random', 'fixed'))]
    rows = ['| per-movement model | policy | accuracy | decided | median contact (s) | p90 '
            'contact (s) | median movements | ' + ' | '.join(
                f'after {k} ({k * seconds:g} s)' for k in steps) + ' |',
            '|---|---|---|---|---|---|---|' + '---|' * len(steps)]
    for name, report in reports.items():
        for policy in ('active', 'random', 'fixed'):
            row = report['policies'][policy]
            rows.append(f'| {name} | {policy} | {100 * row["accuracy"]:.1f} % | '
                        f'{100 * row["decided"]:.0f} % | {row["median_contact_s"]:.1f} | '
                        f'{row["p90_contact_s"]:.1f} | {row["median_movements"]:.0f} | '
                        + ' | '.join(f'{100 * row["accuracy_after_k"][k - 1]:.1f} %'
                                     for k in steps) + ' |')
    sweeps = ['| movement | ' + ' | '.join(reports) + ' |', '|---|' + '---|' * len(reports)]
    for movement in first['movement_names']:
        cells = []
        for report in reports.values():
            row = report['movements'][movement]
            short = len(row.get('unconverged', []))
            cells.append(f'{100 * row["sweep_accuracy"]:.1f} %'
                         + (f' ({short} not converged)' if short else ''))
        sweeps.append(f'| {movement} | ' + ' | '.join(cells) + ' |')
    timed = [step['seconds'] for step in kept['steps'] if step['seconds'] is not None]
    earlier = [step['command'].split()[0] for step in kept['steps'] if step['seconds'] is None]
    tuned = reports['cnn_3 fine-tuned']
    folds, inner = tuned['settings']['folds'], tuned['settings']['inner_folds']
    trainings = folds * (inner + 1) * len(first['movement_names'])
    unconverged = [why for row in tuned['movements'].values() for why in row['unconverged']]
    reasons = sorted({why.rsplit(': ', 1)[-1] for why in unconverged})
    sweeps_set, source, pre = kept['movement_sweeps'], kept['source'], kept['pretraining']
    per_cell = sweeps_set['recordings'] // (sweeps_set['classes'] * len(first['movement_names']))
    curves_set = kept_json('learning_curves/learning_curves.json')['dataset']
    scratch = ' '.join(kept['settings']['cnn_3 from scratch'][2:])
    return (
        f'Measured (`python bench/bench_identification_init.py`, {sum(timed) / 60:.0f} min '
        'for the three reports'
        + (f'; made earlier by the same steps and given with {", ".join(earlier)}'
           if earlier else '') + f'): the {sweeps_set["classes"]} textures x '
        f'{len(first["movement_names"])} movements x {per_cell} sweeps above, on '
        + ('the first of its partitions into folds, with its seeds and held-out sweeps '
           if kept_json('identification/identification.json')['settings'].get('repeats', 1)
           > 1 else 'the same folds, seeds and held-out sweeps ')
        + f'({first["episodes"]} episodes per policy); per '
        f'movement minirocket, cnn_3 from scratch (`{scratch}`), and cnn_3 fine-tuned '
        f'(`--init`, `--profile modern`, at most {kept["fine_tuning_epochs"]} epochs) from a '
        f'{pre["model"]} pretrained on {source["recordings"]} recordings of '
        f'{source["classes"]} textures ({source["windows"]} windows'
        + ("; the learning curves' set, `tactex sim collect --scene uneven_texture --sweeps "
           "85` on the scene's own seed, none of these sweeps"
           if source['windows_sha256'] == curves_set else '')
        + f'), `{pre["profile"]}` profile, {pre["scaling"]} scaling, at most {pre["epochs"]} '
        f'epochs, stopping after {pre["early_stopping"]} without gain:\n\n'
        + '\n'.join(rows) + '\n\nEach movement on its own, one held-out sweep (in brackets, '
        f'how many of its trainings, of {folds} folds x ({inner} inner folds + the final '
        'model), did not converge):\n\n' + '\n'.join(sweeps)
        + f"\n\n{len(unconverged)} of the fine-tuned setting's {trainings} trainings did not "
        'converge' + (f' ({", ".join(reasons)})' if reasons else '') + '.'
        + _against_goals(tuned) + '\n')


def texture_signal() -> str:
    """How far each texture's own vibration rises above the IMU noise, by path and movement."""
    kept = kept_json('texture_signal.json')
    noise = kept['noise_rms']
    paths = list(kept['paths'])
    action = 'sweep action'
    # Per path, the movements it measured (a refused one kept only its reason).
    measured = {path: {name: row for name, row in kept['paths'][path].items()
                       if 'textures' in row} for path in paths}
    refused = {path: [name for name in kept['paths'][path] if name not in measured[path]]
               for path in paths}
    textures = list(next(iter(measured[action].values()))['textures'])

    def best(path: str, texture: str, channel: str) -> tuple[float, str]:
        rows = measured[path]
        name = max(rows, key=lambda m: rows[m]['textures'][texture][f'{channel}_rms'])
        return rows[name]['textures'][texture][f'{channel}_rms'] / noise[channel], name

    def spread(path: str, key: str) -> tuple[float, float]:
        values = [row[key] for row in measured[path].values()]
        return min(values), max(values)

    lines = ['| texture | ' + ' | '.join(f'{path}: accel | {path}: gyro' for path in paths)
             + ' |', '|---|' + '---|---|' * len(paths)]
    for texture in textures:
        cells = []
        for path in paths:
            for channel in ('accel', 'gyro'):
                ratio, name = best(path, texture, channel)
                cells.append(f'{ratio:.2g} ({name})')
        lines.append(f'| {texture} | ' + ' | '.join(cells) + ' |')
    above = [t for t in textures
             if max(best(action, t, c)[0] for c in ('accel', 'gyro')) > 2.0]
    live = kept_json('identify_live_sweeps_init_sweeps_realized.json')
    decided = sorted({e['truth'] for e in live['episodes'] if e['answer'] == e['truth']})
    return (
        f'Measured (`python bench/bench_texture_signal.py`, {kept["seconds"]:.0f} s): one sweep '
        f'of every texture under every movement of the {kept["scene"]} scene in MuJoCo with '
        "the IMU noise off, along the sweep action's path (planned from a probe-like pathway, "
        "played through the driver's controller) and sim collect's scripted one; a "
        "texture's own signal is the reading over it minus the reading over no texture, "
        "over the contact segment. Its rms (norm over the three axes) against the scene's "
        f'IMU noise ({noise["accel"]:.3f} m/s^2 and {noise["gyro"]:.4f} rad/s over three '
        'axes), the largest over the movements, and at which:\n\n' + '\n'.join(lines)
        + '\n\n' + ' '.join(
            '{}: mean contact force {:.3f}-{:.3f} N, barometer {:.0f}-{:.0f} Pa, over no '
            'texture a high-frequency gyro of {:.4f}-{:.4f} rad/s, {:.4f}-{:.4f} after the '
            'first 0.25 s of contact'.format(
                path, *spread(path, 'force_n'), *spread(path, 'pressure_pa'),
                *spread(path, 'bare_gyro_hf_rms'), *spread(path, 'bare_gyro_hf_rms_after_start'))
            + (f'; {", ".join(refused[path])} refused (the arm cannot follow it)'
               if refused[path] else '') + '.' for path in paths)
        + f' Through the sweep action, above twice the noise at some movement: '
        f'{", ".join(above)}. The live goals of the run above decided, always right, on: '
        f'{", ".join(decided)}.\n')
