# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The identification goals on fresh scene seeds, each apart and pooled.

One scene seed decides little: on twenty sweeps per texture and movement the goal
against the single best movement repeated rests on a point or two, within the interval
of a bootstrap over twelve textures. For each of `--scene-seeds` (fresh: no test uses
them and none was looked at while the policies were built), this runs the same collect,
convert and `tactex report identification` as bench_identification_report.py (every
policy, active-realized too) and keeps each seed's identification.json. It then pools
the goal against fixed over the seeds: every seed's textures are other scenes, so a
(seed, texture) is one more unit of the bootstrap (`comparison.texture_bootstrap`), each
unit's margin measured against its own seed's fixed. Written to
bench/results/identification_seeds/: seeds.json (rendered into the docs), seeds.png
(each seed's margin with its interval, and the pooled one) and each seed's
identification.json (its per-movement confusions among them).
`--reports DIR` reuses DIR/SEED/identification.json written earlier by the same report.
"""

import argparse
import json
from pathlib import Path
import shutil
import sys
import tempfile

from bench_textures import TACTEX, timed  # one way to run and time a tactex step
import numpy as np

from tactex_classify.identification.comparison import GOAL_TOLERANCE, texture_bootstrap
from tactex_classify.identification.selection import POLICIES
from tactex_common import plotting

RESULTS = Path(__file__).parent / 'results' / 'identification_seeds'
MOVEMENTS = Path(__file__).parents[1] / 'config' / 'movements.yaml'
FRESH = (2037, 2039, 2041)


def random_goal(report: dict) -> dict:
    """Against random: every policy's accuracy and median contact, where active leads or lags."""
    against = report['active_against']['random']
    low, high = np.array(against['low']), np.array(against['high'])
    return {'policies': {policy: {'accuracy': row['accuracy'],
                                  'median_contact_s': row['median_contact_s']}
                         for policy, row in report['policies'].items()},
            'times': len(low), 'times_above': int(np.sum(low > 0)),
            'times_below': int(np.sum(high < 0))}


def pooled(reports: dict[int, dict]) -> dict:
    """The goal against fixed over every (seed, texture), each against its own seed's fixed."""
    margins = np.concatenate([r['against_fixed']['texture_margins'] for r in reports.values()])
    pairs = np.concatenate([r['against_fixed']['texture_pairs'] for r in reports.values()])
    margin, low, high = (float(v[0]) for v in texture_bootstrap(margins[:, None],
                                                                 pairs.astype(float)))
    return {'margin': margin, 'low': low, 'high': high, 'units': len(margins),
            'met': sum(r['against_fixed']['margin'] >= 0 for r in reports.values())}


def plot(path: Path, reports: dict[int, dict], together: dict) -> None:
    """Each seed's margin against fixed with its 95 % interval, and the pooled one."""
    plt, figure, axis = plotting.figure()
    rows = [(str(seed), r['against_fixed']) for seed, r in reports.items()]
    rows.append(('pooled', together))
    for index, (name, row) in enumerate(rows):
        axis.errorbar([index], [100 * row['margin']],
                      yerr=[[100 * (row['margin'] - row['low'])],
                            [100 * (row['high'] - row['margin'])]],
                      fmt='o', color='C1' if name == 'pooled' else 'C0', capsize=4)
    axis.axhline(0.0, color='gray', lw=0.8)
    axis.set_xticks(range(len(rows)), [name for name, _ in rows])
    axis.set_xlabel('scene seed')
    axis.set_ylabel('margin of the goal against fixed (points)')
    axis.set_xlim(-0.5, len(rows) - 0.5)
    plotting.save(plt, figure, path, "active at 60 % of fixed's median contact, less fixed's "
                  'final, plus 1 point; 95 % interval over textures')


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('--scene-seeds', default=','.join(map(str, FRESH)),
                        help='comma-separated scene seeds that no test uses')
    parser.add_argument('--sweeps', type=int, default=20)
    parser.add_argument('--folds', type=int, default=2)
    parser.add_argument('--seeds', type=int, default=10)
    parser.add_argument('--repeats', type=int, default=5)
    parser.add_argument('--inner-folds', type=int, default=3)
    parser.add_argument('--model', default='minirocket')
    parser.add_argument('--reports', type=Path,
                        help='DIR/SEED/identification.json from earlier runs of the same report')
    args = parser.parse_args()
    scene_seeds = [int(seed) for seed in args.scene_seeds.split(',')]
    steps: list[dict] = []
    reports: dict[int, dict] = {}
    with tempfile.TemporaryDirectory() as scratch:
        for seed in scene_seeds:
            folder = Path(scratch) / str(seed)
            report = [TACTEX, 'report', 'identification', str(folder / 'data.npz'),
                      '--movements', str(MOVEMENTS), '--folds', str(args.folds),
                      '--inner-folds', str(args.inner_folds), '--seeds', str(args.seeds),
                      '--repeats', str(args.repeats), '--model', args.model,
                      '--policies', ','.join(POLICIES)]
            collect = [TACTEX, 'sim', 'collect', '--movements', str(MOVEMENTS), '--sweeps',
                       str(args.sweeps), '--seed', str(seed), '--out', str(folder / 'bags')]
            convert = [TACTEX, 'convert', str(folder / 'bags'), '--out',
                       str(folder / 'data.npz'), '--window', '128']
            for command in (collect, convert, [*report, '--out', str(folder / 'report')]):
                if args.reports:
                    steps.append({'command': ' '.join(['tactex', *command[1:]]).replace(
                        scratch, 'SCRATCH'), 'seconds': None, 'note': 'run earlier (--reports)'})
                else:
                    timed(command, steps)
            made = (args.reports / str(seed) if args.reports else folder / 'report') \
                / 'identification.json'
            reports[seed] = json.loads(made.read_text(encoding='utf-8'))
        shutil.rmtree(RESULTS, ignore_errors=True)
        RESULTS.mkdir(parents=True)
        for seed, report in reports.items():
            (RESULTS / f'{seed}.json').write_text(json.dumps(report, indent=1) + '\n',
                                                  encoding='utf-8')
    together = pooled(reports)
    table = {'scene_seeds': scene_seeds, 'sweeps_per_texture_and_movement': args.sweeps,
             'goal_tolerance': GOAL_TOLERANCE, 'steps': steps,
             'against_fixed': {seed: {k: v for k, v in r['against_fixed'].items()
                                      if not k.startswith('texture_')}
                               for seed, r in reports.items()},
             'pooled': together,
             'against_random': {seed: random_goal(r) for seed, r in reports.items()}}
    (RESULTS / 'seeds.json').write_text(json.dumps(table, indent=1) + '\n', encoding='utf-8')
    plot(RESULTS / 'seeds.png', reports, together)
    print(json.dumps({'pooled': together, 'against_fixed': table['against_fixed']}, indent=1))
    return 0


if __name__ == '__main__':
    sys.exit(main())
