# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Active identification against fixed, random and round-robin movements, held out.

Runs `tactex sim collect --movements config/movements.yaml` (12 textures x 8 movements x
`--sweeps` sweeps, on a scene seed no test uses), `tactex convert` at the movement
file's window, then `tactex report identification` (grouped folds dealt `--repeats`
times, nested evidence, every policy on the same held-out sweeps, active-realized beside
the comparison's four, active paired against each), and keeps the report in
bench/results/identification/ with run.json (the commands, their seconds, the dataset).
The same report is then run again with `--repeat-discount` (a fitted discount of a
movement's repeats) on the same folds and sweeps, and its identification.json kept in
with_repeat_discount/, for the paired comparison.
`--bags DIR` reuses sweeps an earlier run of the same collect command recorded.
"""

import argparse
import json
from pathlib import Path
import shutil
import sys
import tempfile

from bench_textures import TACTEX, timed  # one way to run and time a tactex step

from tactex_classify.identification.selection import POLICIES

RESULTS = Path(__file__).parent / 'results' / 'identification'
MOVEMENTS = Path(__file__).parents[1] / 'config' / 'movements.yaml'


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('--sweeps', type=int, default=20)
    parser.add_argument('--seed', type=int, default=2035, help='scene seed (no test uses it)')
    parser.add_argument('--folds', type=int, default=2)
    parser.add_argument('--seeds', type=int, default=10)
    parser.add_argument('--repeats', type=int, default=5,
                        help='partitions into folds, each replayed (repeated cross-validation)')
    parser.add_argument('--inner-folds', type=int, default=3,
                        help='calibration folds inside each outer fold (2 below 6 sweeps)')
    parser.add_argument('--model', default='minirocket')
    parser.add_argument('--bags', type=Path, help='sweeps recorded earlier by the same collect')
    args = parser.parse_args()
    steps: list[dict] = []
    collect = [TACTEX, 'sim', 'collect', '--movements', str(MOVEMENTS), '--sweeps',
               str(args.sweeps), '--seed', str(args.seed)]
    with tempfile.TemporaryDirectory() as scratch:
        bags = args.bags or Path(scratch) / 'bags'
        if args.bags:
            steps.append({'command': ' '.join(['tactex', *collect[1:], '--out', 'BAGS']),
                          'seconds': None, 'note': 'recorded earlier (--bags)'})
        else:
            timed([*collect, '--out', str(bags)], steps)
        data = Path(scratch) / 'identification.npz'
        timed([TACTEX, 'convert', str(bags), '--out', str(data), '--window', '128'], steps)
        report, discounted = Path(scratch) / 'report', Path(scratch) / 'discounted'
        command = [TACTEX, 'report', 'identification', str(data), '--movements',
                   str(MOVEMENTS), '--folds', str(args.folds), '--inner-folds',
                   str(args.inner_folds), '--seeds', str(args.seeds), '--repeats',
                   str(args.repeats), '--model', args.model]
        timed([*command, '--policies', ','.join(POLICIES), '--out', str(report)], steps)
        timed([*command, '--repeat-discount', '--out', str(discounted)], steps)
        shutil.rmtree(RESULTS, ignore_errors=True)
        shutil.copytree(report, RESULTS)
        (RESULTS / 'with_repeat_discount').mkdir()
        shutil.copy(discounted / 'identification.json', RESULTS / 'with_repeat_discount')
    (RESULTS / 'run.json').write_text(json.dumps(
        {'sweeps_per_texture_and_movement': args.sweeps, 'scene_seed': args.seed,
         'steps': steps}, indent=2) + '\n', encoding='utf-8')
    print((RESULTS / 'identification.md').read_text(encoding='utf-8').split('![')[0])
    return 0


if __name__ == '__main__':
    sys.exit(main())
