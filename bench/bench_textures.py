# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The texture results end to end, from one dataset build: simulate, convert, train each.

Runs `tactex sim collect` (12 textures x 25 sweeps of the uneven-texture scene) once,
`tactex convert` (128-sample windows, 50 % overlap) once, then `tactex train` for the
two baselines and the deep models given on the command line (default: cnn_3, at most
80 epochs of the `modern` profile with per-window scaling, the recipe the profile
ablation found best; `--profile original --scaling minmax` trains as the original did,
whose 250 epochs x 8 models take hours on one CPU), each with both CV schemes, all on
that one dataset. Reports land in bench/results/textures/<model>/, and
bench/results/textures/run.json records the dataset (its SHA-256, windows, recordings),
the commands and how long each step took; `bench/render_results.py` builds the README's
texture table from these files only. `--data` retrains some models on a dataset an
earlier run kept (`--keep-data`), refused unless it is the very build run.json names.
"""

import argparse
import hashlib
import json
from pathlib import Path
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

from tactex_classify.models.registry import BASELINES

RESULTS = Path(__file__).parent / 'results' / 'textures'
TACTEX = str(Path(sys.executable).parent / 'tactex')


def timed(command: list[str], steps: list[dict]) -> None:
    """Run a command (failing loudly) and note how long it took."""
    start = time.monotonic()
    subprocess.run(command, check=True)
    steps.append({'command': ' '.join(['tactex', *command[1:]]),
                  'seconds': round(time.monotonic() - start, 1)})


def build_dataset(folder: Path, sweeps: int, steps: list[dict]) -> Path:
    """Simulate the uneven-texture set into `folder` and convert it; return the .npz."""
    bags, data = folder / 'bags', folder / 'sim128.npz'
    timed([TACTEX, 'sim', 'collect', '--scene', 'uneven_texture', '--sweeps', str(sweeps),
            '--out', str(bags)], steps)
    timed([TACTEX, 'convert', str(bags), '--out', str(data), '--window', '128'], steps)
    return data


def _sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _describe(data: Path, sweeps: int) -> dict:
    """The dataset as run.json records it."""
    sidecar = json.loads(data.with_suffix('.json').read_text(encoding='utf-8'))
    with np.load(data) as arrays:
        return {'sha256': _sha256(data), 'window': 128, 'sweeps_per_texture': sweeps,
                'sampling_rate_hz': sidecar.get('sampling_rate_hz'),
                'windows': int(arrays['y'].size),
                'recordings': int(np.unique(arrays['trial']).size)}


def main() -> int:
    """Collect, convert, train every model on the same windows, keep the reports."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('--models', nargs='+', default=['extratrees', 'minirocket', 'cnn_3'])
    parser.add_argument('--epochs', type=int, default=80)
    parser.add_argument('--sweeps', type=int, default=25)
    parser.add_argument('--threads', type=int, default=2)
    parser.add_argument('--profile', choices=('original', 'modern'), default='modern',
                        help="deep models' training profile (baselines have none)")
    parser.add_argument('--scaling', choices=('minmax', 'standard', 'window'), default='window',
                        help="deep models' scaling")
    parser.add_argument('--keep-data', type=Path,
                        help='also keep the dataset (.npz + .json) here, e.g. for bench_init')
    parser.add_argument('--data', type=Path,
                        help='retrain --models on a dataset kept by an earlier run; it must be '
                             'the build bench/results/textures/run.json names (same SHA-256)')
    args = parser.parse_args()
    previous = json.loads((RESULTS / 'run.json').read_text(encoding='utf-8')) \
        if args.data else None
    with tempfile.TemporaryDirectory() as folder:
        if args.data:
            data = args.data.with_suffix('.npz')
            if _sha256(data) != previous['dataset']['sha256']:
                print(f'error: --data {data} is not the build run.json names; run without '
                      f'--data to rebuild every result', file=sys.stderr)
                return 1
            steps = [step for step in previous['steps'] if not any(
                f' --model {model} ' in step['command'] for model in args.models)]
        else:
            steps = []
            data = build_dataset(Path(folder), args.sweeps, steps)
        dataset = _describe(data, args.sweeps)
        if args.keep_data:
            args.keep_data.parent.mkdir(parents=True, exist_ok=True)
            for suffix in ('.npz', '.json'):
                shutil.copy2(data.with_suffix(suffix), args.keep_data.with_suffix(suffix))
        for model in args.models:
            run = Path(folder) / model
            recipe = [] if model in BASELINES else [
                '--profile', args.profile, '--scaling', args.scaling]
            timed([TACTEX, 'train', str(data), '--model', model, '--epochs', str(args.epochs),
                    *recipe, '--threads', str(args.threads), '--out', str(run),
                    '--no-final'], steps)
            target = RESULTS / model
            shutil.rmtree(target, ignore_errors=True)
            target.mkdir(parents=True)
            for item in run.iterdir():
                if item.is_file():
                    shutil.copy2(item, target / item.name)
            print((target / 'report.md').read_text(encoding='utf-8').split('## Per class')[0])
    models = list(dict.fromkeys([*(previous['models'] if previous else []), *args.models]))
    record = {'dataset': dataset, 'models': models, 'epochs': args.epochs,
              'threads': args.threads, 'steps': steps}
    (RESULTS / 'run.json').write_text(json.dumps(record, indent=2) + '\n', encoding='utf-8')
    return 0


if __name__ == '__main__':
    sys.exit(main())
