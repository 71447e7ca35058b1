# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Does `not converged` matter? A kept grid's unconverged cells, trained again for longer.

For every deep-model cell of a kept grid (`--grid`, default the main comparison) that
`grid_report.cell_unconverged_because` marks, `model_grid.run_cell` trains it again with
`--epochs` (default twice the grid's), the same seed, fold and settings otherwise (so the
warm-up and cosine schedule stretch over the longer run, as `tactex compare --epochs`
would), on the grid's data (`--data`, default the source its manifest names), `--cpus`
cells at a time. Prints each cell's accuracy and epochs before and after, and why it
still did not converge if it did not; keeps them in results/convergence_check.json
(`--out`). The grid (a comparison of one window), the data (the grid's own, by the digest
its manifest keeps) and --out are checked before any training; a grid without such a
cell has nothing to check, says so, and writes nothing.
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

from tactex.cli import CommandParser, guarded  # noqa: E402
from tactex.errors import CommandError  # noqa: E402
from tactex.options import (  # noqa: E402
    check_input_folder,
    check_output_file,
    epoch_count,
    integer,
    load_dataset,
)
from tactex_classify.data.dataset import Dataset  # noqa: E402
from tactex_classify.evaluation.grid_report import cell_unconverged_because  # noqa: E402
from tactex_classify.evaluation.model_grid import (  # noqa: E402
    Cell,
    GridError,
    GridSettings,
    GridStore,
    run_cell,
)
from tactex_classify.models.registry import BASELINES  # noqa: E402
from tactex_common.stopping import raise_on_stop_signals  # noqa: E402

RESULTS = Path(__file__).parent / 'results'


def open_grid(name: str) -> tuple[GridStore, GridSettings, dict]:
    """The kept grid `name` (or a grid folder's path): its store, settings and its data.

    The data is grid.json's entry of the grid's one window (source, digest, classes).

    Raises:
        CommandError: no such folder.
        GridError: not a comparison, or one of several windows (naming --grid).
    """
    store = GridStore(check_input_folder(RESULTS / name, '--grid'))
    if not store.manifest_path.is_file():
        raise GridError(f'--grid {store.folder} has no grid.json: not a tactex comparison; '
                        'give a grid folder `tactex compare` wrote')
    not_a_grid = GridError(f'--grid {store.manifest_path} is not a tactex comparison manifest; '
                           'give a grid folder `tactex compare` wrote')
    try:
        manifest = store.manifest()
        settings = GridSettings(**manifest['settings'])
    except (GridError, TypeError):  # TypeError: a setting GridSettings does not have
        raise not_a_grid from None
    windows = manifest['data']
    if len(windows) != 1:
        raise GridError(f'--grid {store.folder} holds {len(windows)} windows '
                        f'({", ".join(windows)}); this check takes a grid of one window')
    data, = windows.values()
    if not (isinstance(data, dict) and isinstance(data.get('source'), str)
            and isinstance(data.get('sha256'), str) and isinstance(data.get('classes'), list)):
        raise not_a_grid
    return store, settings, data


def check_data(path: Path, kept: dict) -> None:
    """--data is the dataset the grid was run on (the digest grid.json keeps).

    Raises:
        CommandError: naming --data: missing, not a dataset, or other data.
    """
    if load_dataset(path, '--data').digest() != kept['sha256']:
        raise CommandError(f'--data {path} is not the dataset the grid was run on (its source '
                           f'was {kept["source"]}); give that one')


def train_again(data: Path, cell: Cell, settings: GridSettings) -> dict:
    """One cell trained with `settings` (a worker process)."""
    return run_cell({cell.window: Dataset.load(data)}, cell, settings, threads=1,
                    device='cpu')


def parse(argv: list[str] | None) -> argparse.Namespace:
    """The command line; a bad value is one `error:` line and exit status 1."""
    parser = CommandParser(prog='bench/bench_convergence_check.py', description=__doc__)
    parser.add_argument('--grid', default='compare_converged',
                        help='a kept grid under bench/results/ (default compare_converged), '
                             "or a grid folder's path")
    parser.add_argument('--data', type=Path, help="the grid's dataset (default: its source)")
    parser.add_argument('--epochs', type=epoch_count,
                        help="epochs at most (default: twice the grid's)")
    parser.add_argument('--cpus', type=integer(1, os.cpu_count() or 1), default=2,
                        help='cells trained at a time, at most the cores (2)')
    parser.add_argument('--out', type=Path, default=RESULTS / 'convergence_check.json',
                        help='the JSON file to write (default results/convergence_check.json)')
    return parser.parse_args(argv)


def run(args: argparse.Namespace) -> int:
    """Train the marked cells again; print and keep before and after."""
    store, settings, data_info = open_grid(args.grid)
    check_output_file(args.out)
    classes = len(data_info['classes'])
    finished = store.results()
    marked = [(Cell(**result['cell']), result, cell_unconverged_because(result, classes))
              for result in finished if result['cell']['model'] not in BASELINES]
    marked = [(cell, result, why) for cell, result, why in marked if why]
    if not marked:
        print(f'--grid {store.folder}: no unconverged deep-model cell among its {len(finished)} '
              f'finished cells; nothing to check, nothing written to {args.out}')
        return 0
    data = args.data or Path(data_info['source'])
    check_data(data, data_info)
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
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(kept, indent=1) + '\n', encoding='utf-8')
    return 0


def main(argv: list[str] | None = None) -> int:
    """Entry point: one `error:` line and exit status 1 on bad input, 128+n on a signal."""
    raise_on_stop_signals()
    args = parse(argv)
    return guarded(lambda: run(args))


if __name__ == '__main__':
    sys.exit(main())
