# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""How likely a declared identification test of a given size is to pass, from the kept seeds.

Before a test is declared, its size is chosen: too few seeds and a real saving of a few
seconds cannot clear zero. This reads the kept reports of bench_identification_seeds.py
(bench/results/identification_seeds/, both settings) as a pilot: for each policy, every
kept seed whose report replayed it. Each of `--draws` simulated tests draws its scene seeds
in two stages, so that the pilot's own uncertainty enters: a population as large as the
pilot, drawn from the pilot's seeds with replacement (what the pilot might have been), then
the test's seeds from that population with replacement, each with its twelve textures. On
them it runs both goals' tests exactly as a declared test (`bench_identification_seeds`'s
`goal_tests` and `fixed_budget`, the first declaration's thresholds, tolerance, share).
The share of draws that pass estimates each test's power, and both together. The pilot's
seeds were read, and a policy may have been picked for how they fell: its power here is as
optimistic as that pick; it sizes a test, it does not stand in for one.

Written to bench/results/identification_power/: power.json and power.png.
"""

import argparse
import json
from pathlib import Path
import sys

from bench_identification_seeds import (
    COMPARED,
    CONFIRMATORY,
    declared_sums,
    DISCOUNTED,
    fixed_budget,
    goal_tests,
)
from bench_identification_seeds import RESULTS as SEEDS
import numpy as np

from tactex_classify.identification.selection import POLICIES
from tactex_common import plotting

RESULTS = Path(__file__).parent / 'results' / 'identification_power'
SETTINGS = {'default': SEEDS, DISCOUNTED: SEEDS / DISCOUNTED}  # seeds.json's keys


def pilot(policy: str, folder: Path) -> dict[int, dict]:
    """Every kept seed's report in `folder` that replayed `policy`, by scene seed."""
    reports = {int(path.stem): json.loads(path.read_text(encoding='utf-8'))
               for path in sorted(folder.glob('*.json')) if path.stem.isdigit()}
    return {seed: report for seed, report in reports.items() if policy in report['policies']}


def power(reports: dict[int, dict], declared: dict, scene_seeds: int, draws: int,
          resamples: int) -> dict:
    """The share of `draws` simulated tests of `scene_seeds` seeds passing each goal, and both."""
    pilot_seeds = list(reports)
    generator = np.random.default_rng(0)
    passed = []
    for draw in range(draws):
        population = generator.choice(pilot_seeds, size=len(pilot_seeds))
        drawn = [reports[seed] for seed in generator.choice(population, size=scene_seeds)]
        tests = goal_tests(declared_sums(drawn, declared['policy']), declared,
                           fixed_budget(drawn, declared), resamples=resamples,
                           bootstrap_seed=draw)
        passed.append((bool(tests) and tests['against_random']['passed'],
                       bool(tests) and tests['against_fixed']['passed']))
    random_goal, fixed_goal = np.asarray(passed, dtype=bool).T
    return {'scene_seeds': scene_seeds, 'against_random': float(random_goal.mean()),
            'against_fixed': float(fixed_goal.mean()),
            'both': float((random_goal & fixed_goal).mean())}


def plot(path: Path, table: dict) -> None:
    """Power against the test's size, one panel per setting, one colour per policy."""
    plt, figure, axes = plotting.figure(1, len(table), squeeze=False, sharey=True)
    for axis, (setting, policies) in zip(axes[0], table.items(), strict=True):
        for index, (policy, row) in enumerate(policies.items()):
            sizes = [cell['scene_seeds'] for cell in row['power']]
            for goal, style in (('both', '-'), ('against_random', ':'), ('against_fixed', '--')):
                axis.plot(sizes, [cell[goal] for cell in row['power']], style, marker='o',
                          ms=3, color=f'C{index}', label=f'{policy}, {goal.replace("_", " ")}')
        axis.axhline(0.8, color='grey', lw=0.6)
        axis.set(title=setting, xlabel='scene seeds in the test (12 textures each)',
                 ylim=(0, 1.02))
    axes[0][0].set_ylabel('share of simulated tests that pass')
    plotting.legend_outside(axes[0][-1])
    plotting.save(plt, figure, path, 'seeds drawn in two stages from the kept seeds of each '
                  'policy; grey: 0.8')


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('--policies', default='active,active-rounds,active-sampled',
                        help='comma-separated policies to size a test of')
    parser.add_argument('--scene-seeds', default='6,12,18,24',
                        help='comma-separated test sizes, in scene seeds')
    parser.add_argument('--draws', type=int, default=400, help='simulated tests per size')
    parser.add_argument('--resamples', type=int, default=400,
                        help="each simulated test's bootstrap resamples")
    args = parser.parse_args()
    try:
        sizes = [int(size) for size in args.scene_seeds.split(',')]
    except ValueError:
        parser.error(f'--scene-seeds: {args.scene_seeds!r} is not comma-separated whole numbers')
    if min(sizes) < 1 or args.draws < 1 or args.resamples < 1:
        parser.error('--scene-seeds, --draws and --resamples: give numbers of at least 1')
    policies = args.policies.split(',')
    sizable = [policy for policy in POLICIES if policy not in COMPARED]
    unknown = [policy for policy in policies if policy not in sizable]
    if unknown:
        parser.error(f'--policies: {unknown} are not policies a test compares with random and '
                     f'fixed; choose from {sizable}')
    kept = {setting: {policy: pilot(policy, folder) for policy in policies}
            for setting, folder in SETTINGS.items()}
    unkept = sorted({policy for reports in kept.values() for policy, seeds in reports.items()
                     if not seeds})
    if unkept:
        parser.error(f'--policies: no kept seed in {SEEDS} replayed {unkept}')
    table: dict[str, dict] = {}
    for setting, reports in kept.items():
        for policy, by_seed in reports.items():
            declared = {**CONFIRMATORY, 'policy': policy}
            table.setdefault(setting, {})[policy] = {
                'pilot_seeds': list(by_seed),
                'power': [power(by_seed, declared, size, args.draws, args.resamples)
                          for size in sizes]}
            print(setting, policy, json.dumps(table[setting][policy]['power']), flush=True)
    RESULTS.mkdir(parents=True, exist_ok=True)
    written = {'draws': args.draws, 'resamples': args.resamples,
               'thresholds': CONFIRMATORY['thresholds'], 'settings': table}
    (RESULTS / 'power.json').write_text(json.dumps(written, indent=1) + '\n', encoding='utf-8')
    plot(RESULTS / 'power.png', table)
    return 0


if __name__ == '__main__':
    sys.exit(main())
