# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Does `not converged` matter? A kept grid's unconverged cells, trained again for longer.

For every deep-model cell of a kept grid (`--grid`, default the main comparison) that
`grid_report.cell_unconverged_because` marks, `model_grid.run_cell` trains it again with
`--epochs` (default twice the grid's), the same seed, fold and settings otherwise (so the
warm-up and cosine schedule stretch over the longer run, as `tactex compare --epochs`
would), on the grid's data (`--data`, default the source its manifest names), `--cpus`
cells at a time. Prints each cell's accuracy and epochs before and after, and why it
still did not converge if it did not; keeps them in results/convergence_check.json.
"""

import argparse
from concurrent.futures import as_completed, ProcessPoolExecutor
import dataclasses
import json
import os
from pathlib import Path
import sys
import time

os.environ.setdefault('OMP_NUM_THREADS', '1')

from tactex_classify.data.dataset import Dataset  # noqa: E402
from tactex_classify.evaluation.grid_report import cell_unconverged_because  # noqa: E402
from tactex_classify.evaluation.model_grid import (  # noqa: E402
    Cell,
    GridSettings,
    GridStore,
    run_cell,
)
from tactex_classify.models.registry import BASELINES  # noqa: E402

RESULTS = Path(__file__).parent / 'results'


def train_again(data: Path, cell: Cell, settings: GridSettings) -> dict:
    """One cell trained with `settings` (a worker process)."""
    return run_cell({cell.window: Dataset.load(data)}, cell, settings, threads=1,
                    device='cpu')


def main() -> int:
    """Train the marked cells again; print and keep before and after."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('--grid', default='compare_converged',
                        help='a kept grid under bench/results/ (default compare_converged)')
    parser.add_argument('--data', type=Path, help="the grid's dataset (default: its source)")
    parser.add_argument('--epochs', type=int, help="epochs at most (default: twice the grid's)")
    parser.add_argument('--cpus', type=int, default=2)
    args = parser.parse_args()
    store = GridStore(RESULTS / args.grid)
    manifest = store.manifest()
    settings = GridSettings(**manifest['settings'])
    (window, data_info), = manifest['data'].items()
    data = args.data or Path(data_info['source'])
    if not data.is_file():
        print(f'error: --data {data}: no such file; give the dataset the grid was run on',
              file=sys.stderr)
        return 1
    classes = len(data_info['classes'])
    marked = [(Cell(**result['cell']), result, cell_unconverged_because(result, classes))
              for result in store.results() if result['cell']['model'] not in BASELINES]
    marked = [(cell, result, why) for cell, result, why in marked if why]
    longer = dataclasses.replace(settings, epochs=args.epochs or 2 * settings.epochs)
    rows = []
    started = time.monotonic()
    with ProcessPoolExecutor(args.cpus) as pool:
        running = {pool.submit(train_again, data, cell, longer): (cell, result, why)
                   for cell, result, why in marked}
        for done in as_completed(running):
            cell, before, why = running[done]
            after = done.result()
            rows.append({'cell': dataclasses.asdict(cell), 'why_before': why,
                         'before': {'accuracy': before['accuracy'],
                                    'epochs': before['epochs_run']},
                         'after': {'accuracy': after['accuracy'], 'epochs': after['epochs_run'],
                                   'train_s': round(after['train_s'], 1),
                                   'unconverged': cell_unconverged_because(after, classes)}})
            print(f'[{time.monotonic() - started:6.0f} s] {cell.describe()}: '
                  f'{100 * before["accuracy"]:.1f} % after {before["epochs_run"]} epochs '
                  f'({why}) -> {100 * after["accuracy"]:.1f} % after {after["epochs_run"]} '
                  f'({rows[-1]["after"]["unconverged"] or "converged"})', flush=True)
    rows.sort(key=lambda row: (row['cell']['model'], row['cell']['seed'], row['cell']['fold']))
    kept = {'command': ' '.join(['python', 'bench/bench_convergence_check.py', *sys.argv[1:]]),
            'grid': args.grid, 'grid_epochs': settings.epochs, 'epochs': longer.epochs,
            'cells': rows}
    (RESULTS / 'convergence_check.json').write_text(json.dumps(kept, indent=1) + '\n',
                                                    encoding='utf-8')
    return 0


if __name__ == '__main__':
    sys.exit(main())
