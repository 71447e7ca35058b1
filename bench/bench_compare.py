# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The kept model comparison: the synthetic set, eight models and two baselines, 3 windows.

Collects the synthetic set once (`tactex sim collect`, 12 textures x 25 sweeps, on
`--cpus` Ray workers; or takes `--bags`), converts it at 128, 256 and 512 samples (50 %
overlap) into `--work`, then runs `tactex compare` on the three datasets into
bench/results/compare/. The grid resumes: run this again (same settings) and only the
cells not yet finished are trained, so the kept run can be built in chunks on a busy
machine. Each call appends its steps and their durations to
bench/results/compare/run.json; `bench/render_results.py` builds the README's
comparison from summary.json and run.json only.
"""

import argparse
import hashlib
import json
import os
from pathlib import Path
import subprocess
import sys
import time

RESULTS = Path(__file__).parent / 'results' / 'compare'
TACTEX = str(Path(sys.executable).parent / 'tactex')
WINDOWS = (128, 256, 512)


def _timed(command: list[str], steps: list[dict]) -> None:
    """Run a command (failing loudly) and note how long it took and the load around it."""
    start, load = time.monotonic(), os.getloadavg()[0]
    subprocess.run(command, check=True)
    steps.append({'command': ' '.join(['tactex', *command[1:]]),
                  'seconds': round(time.monotonic() - start, 1),
                  'load_average': [round(load, 1), round(os.getloadavg()[0], 1)]})


def main() -> int:
    """Build the data if needed, run (or resume) the grid, note what was done."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('--work', type=Path, default=Path('/tmp/tactex-compare-data'),
                        help='where the bags and the converted datasets are kept')
    parser.add_argument('--bags', type=Path, help='use these bags instead of collecting')
    parser.add_argument('--epochs', type=int, default=1)
    parser.add_argument('--folds', type=int, default=5)
    parser.add_argument('--seeds', type=int, default=1)
    parser.add_argument('--cpus', type=int, default=2)
    parser.add_argument('--models', help='comma-separated (default: every model)')
    parser.add_argument('--windows', default=','.join(map(str, WINDOWS)),
                        help='comma-separated window sizes (default 128,256,512); a later call '
                             'with more windows adds them to the same grid')
    args = parser.parse_args()
    steps: list[dict] = []
    bags = args.bags or args.work / 'bags'
    if not bags.is_dir():
        _timed([TACTEX, 'sim', 'collect', '--scene', 'uneven_texture', '--sweeps', '25',
                '--workers', str(args.cpus), '--out', str(bags)], steps)
    datasets = []
    for window in (int(w) for w in args.windows.split(',')):
        data = args.work / f'sim{window}.npz'
        if not data.is_file():
            _timed([TACTEX, 'convert', str(bags), '--out', str(data), '--window',
                    str(window)], steps)
        datasets.append(data)
    command = [TACTEX, 'compare', *map(str, datasets), '--epochs', str(args.epochs),
               '--folds', str(args.folds), '--seeds', str(args.seeds), '--cpus', str(args.cpus),
               '--out', str(RESULTS)]
    if args.models:
        command += ['--models', args.models]
    try:
        _timed(command, steps)
    finally:
        path = RESULTS / 'run.json'
        record = json.loads(path.read_text(encoding='utf-8')) if path.is_file() else {
            'datasets': {}, 'calls': []}
        for data in datasets:
            record['datasets'][data.name] = hashlib.sha256(data.read_bytes()).hexdigest()
        record['calls'].append({'started': time.strftime('%Y-%m-%dT%H:%M:%S%z'),
                                'cpus': args.cpus, 'steps': steps})
        RESULTS.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(record, indent=2) + '\n', encoding='utf-8')
    return 0


if __name__ == '__main__':
    sys.exit(main())
