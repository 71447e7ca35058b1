# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""How likely a declared identification test of a given size is to pass, from the kept seeds.

Before a test is declared, its size is chosen: too few seeds and a real saving of a few
seconds cannot clear zero. This reads the kept reports of bench_identification_seeds.py
(bench/results/identification_seeds/, both settings) as a pilot: for each policy, the
(seed, texture) units of every kept seed whose report replayed it, pooled. Each of
`--draws` simulated tests draws `--textures` units from the pilot with replacement, as a
fresh test's seeds would bring new textures, and runs both goals' tests on them exactly as
`bench_identification_seeds.goal_tests` does for a declared test (its thresholds,
tolerance and share; fixed's budget from the pilot's seeds). The share of draws that pass
estimates each test's power, and both together. The pilot's seeds were read, so a
policy's power here is as optimistic as its pilot is lucky: it sizes a test, it does not
stand in for one.

Written to bench/results/identification_power/: power.json and power.png.
"""

import argparse
import json
from pathlib import Path
import sys

from bench_identification_seeds import CONFIRMATORY, DISCOUNTED, goal_tests
from bench_identification_seeds import RESULTS as SEEDS
import numpy as np

from tactex_classify.identification.tradeoff import pooled_sums
from tactex_common import plotting

RESULTS = Path(__file__).parent / 'results' / 'identification_power'
SETTINGS = {'default': '', 'discount': DISCOUNTED}


def pilot(policy: str, folder: Path) -> tuple[dict, float, list[int]]:
    """The policy's, random's and fixed's pooled sums over every kept seed that replayed it.

    Returns:
        (sums per policy, the test against fixed's budget in seconds, the seeds).
    """
    reports = {int(path.stem): json.loads(path.read_text(encoding='utf-8'))
               for path in sorted(folder.glob('*.json')) if path.stem.isdigit()}
    seeds = [seed for seed, report in reports.items() if policy in report['policies']]
    sums = {name: pooled_sums([reports[seed]['tradeoff']['textures'][name] for seed in seeds])
            for name in (policy, 'random', 'fixed')}
    budget = CONFIRMATORY['goal_share'] * min(
        reports[seed]['policies']['fixed']['median_contact_s'] for seed in seeds)
    return sums, budget, seeds


def units(sums: dict, chosen: np.ndarray) -> dict:
    """`sums` (one policy's `pooled_sums`) cut to the units `chosen`, in that order."""
    count = len(sums['episodes'])
    return {'thresholds': sums['thresholds'],
            'episodes': np.asarray(sums['episodes'])[chosen].tolist(),
            **{key: np.asarray(sums[key], dtype=float).reshape(-1, count)[:, chosen].tolist()
               for key in ('right', 'contact_s')}}


def power(sums: dict, budget: float, declared: dict, textures: int, draws: int,
          resamples: int) -> dict:
    """The share of `draws` simulated tests of `textures` units that pass each goal, and both."""
    shared = np.flatnonzero(np.all([np.asarray(s['episodes']) > 0 for s in sums.values()],
                                   axis=0))
    generator = np.random.default_rng(0)
    passed = []
    for draw in range(draws):
        chosen = generator.choice(shared, size=textures)
        tests = goal_tests({name: units(s, chosen) for name, s in sums.items()}, declared,
                           budget, resamples=resamples, bootstrap_seed=draw)
        passed.append((tests['against_random']['passed'], tests['against_fixed']['passed']))
    random_goal, fixed_goal = np.asarray(passed, dtype=bool).T
    return {'textures': textures, 'against_random': float(random_goal.mean()),
            'against_fixed': float(fixed_goal.mean()),
            'both': float((random_goal & fixed_goal).mean())}


def plot(path: Path, table: dict) -> None:
    """Power against the test's size, one panel per setting, one colour per policy."""
    plt, figure, axes = plotting.figure(1, len(table), squeeze=False, sharey=True)
    for axis, (setting, policies) in zip(axes[0], table.items(), strict=True):
        for index, (policy, row) in enumerate(policies.items()):
            sizes = [cell['textures'] for cell in row['power']]
            for goal, style in (('both', '-'), ('against_random', ':'), ('against_fixed', '--')):
                axis.plot(sizes, [cell[goal] for cell in row['power']], style, marker='o',
                          ms=3, color=f'C{index}', label=f'{policy}, {goal.replace("_", " ")}')
        axis.axhline(0.8, color='grey', lw=0.6)
        axis.set(title=setting, xlabel='textures in the test (12 per scene seed)', ylim=(0, 1.02))
    axes[0][0].set_ylabel('share of simulated tests that pass')
    plotting.legend_outside(axes[0][-1])
    plotting.save(plt, figure, path, 'drawn from the kept seeds of each policy; grey: 0.8')


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('--policies', default='active,active-rounds,active-sampled',
                        help='comma-separated policies to size a test of')
    parser.add_argument('--textures', default='72,144,216,288',
                        help='comma-separated test sizes, in (seed, texture) units')
    parser.add_argument('--draws', type=int, default=200, help='simulated tests per size')
    parser.add_argument('--resamples', type=int, default=400,
                        help="each simulated test's bootstrap resamples")
    args = parser.parse_args()
    try:
        sizes = [int(size) for size in args.textures.split(',')]
    except ValueError:
        parser.error(f'--textures: {args.textures!r} is not comma-separated whole numbers')
    if min(sizes) < 1 or args.draws < 1 or args.resamples < 1:
        parser.error('--textures, --draws and --resamples: give numbers of at least 1')
    table: dict[str, dict] = {}
    for setting, folder in SETTINGS.items():
        for policy in args.policies.split(','):
            sums, budget, seeds = pilot(policy, SEEDS / folder)
            if not seeds:
                parser.error(f'--policies: no kept seed replayed {policy!r}')
            declared = {**CONFIRMATORY, 'policy': policy}
            table.setdefault(setting, {})[policy] = {
                'pilot_seeds': seeds, 'budget_s': budget,
                'power': [power(sums, budget, declared, size, args.draws, args.resamples)
                          for size in sizes]}
            print(setting, policy, json.dumps(table[setting][policy]['power']), flush=True)
    RESULTS.mkdir(parents=True, exist_ok=True)
    kept = {'draws': args.draws, 'resamples': args.resamples,
            'thresholds': CONFIRMATORY['thresholds'], 'settings': table}
    (RESULTS / 'power.json').write_text(json.dumps(kept, indent=1) + '\n', encoding='utf-8')
    plot(RESULTS / 'power.png', table)
    return 0


if __name__ == '__main__':
    sys.exit(main())
