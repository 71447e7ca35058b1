# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What the simulated sensor reports while sliding: `tactex sim stats` on a fresh collection.

Simulates the uneven-texture scene (`tactex sim collect`, 12 textures x `--sweeps`) and
keeps `tactex sim stats` of it in bench/results/sensor_stats/ (stats.md, stats.json, the
four spectra) with run.json (the commands, when, how long). The README's sensor figures
are generated from stats.json by bench/render_results.py.
"""

import argparse
import json
from pathlib import Path
import shutil
import subprocess
import sys
import tempfile
import time

RESULTS = Path(__file__).parent / 'results' / 'sensor_stats'
TACTEX = str(Path(sys.executable).parent / 'tactex')


def run(command: list[str]) -> float:
    """Run a tactex command quietly; its seconds, or exit with its output."""
    started = time.monotonic()
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode:
        sys.exit(f'{" ".join(command)} failed:\n{result.stdout[-2000:]}{result.stderr[-2000:]}')
    return round(time.monotonic() - started, 1)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--sweeps', type=int, default=1, help='sweeps per texture (1)')
    parser.add_argument('--out', type=Path, default=RESULTS)
    args = parser.parse_args()
    steps = []
    with tempfile.TemporaryDirectory(prefix='tactex-sensor-stats-') as scratch:
        bags, stats = Path(scratch) / 'bags', Path(scratch) / 'stats'
        collect, summarise = ['sim', 'collect', '--sweeps', str(args.sweeps)], ['sim', 'stats']
        for shown, command in ((collect, [*collect, '--out', str(bags)]),
                               (summarise, [*summarise, str(bags), '--out', str(stats)])):
            print('tactex', ' '.join(shown), flush=True)
            steps.append({'command': 'tactex ' + ' '.join(shown),
                          'seconds': run([TACTEX, *command])})
        if args.out.exists():
            shutil.rmtree(args.out)
        shutil.copytree(stats, args.out)
    (args.out / 'run.json').write_text(json.dumps(
        {'started': time.strftime('%Y-%m-%d', time.gmtime()), 'sweeps_per_texture': args.sweeps,
         'scene': 'uneven_texture', 'steps': steps}, indent=1) + '\n', encoding='utf-8')
    print(f'wrote {args.out}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
