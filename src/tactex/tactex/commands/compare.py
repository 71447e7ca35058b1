# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex compare`: a model x window x seed x fold grid on Ray, resumable, with its table."""

from __future__ import annotations

import argparse
from contextlib import ExitStack
import math
import time

from tactex.commands.train import check_folds
from tactex.errors import CommandError
from tactex.options import (
    fold_count,
    input_path,
    integer,
    output_path,
    ray_address,
    window_samples,
)
from tactex.training_options import add_training_options
from tactex_classify.models.registry import ALL_MODELS, BASELINES, SCHEMES

DEFAULT_WINDOWS = (128, 256, 512)


def names(value: str) -> list[str]:
    """An argparse type: comma-separated model names, each known, none twice."""
    items = [item.strip() for item in value.split(',')]
    unknown = [item for item in items if item not in ALL_MODELS]
    if unknown:
        raise argparse.ArgumentTypeError(f'unknown model(s) {unknown}; known: '
                                         f'{",".join(ALL_MODELS)}')
    if len(set(items)) != len(items):
        raise argparse.ArgumentTypeError(f'{value!r} names a model twice')
    return items


def windows(value: str) -> list[int]:
    """An argparse type: comma-separated window sizes (samples >= 2), none twice."""
    parse = window_samples
    items = [parse(item.strip()) for item in value.split(',')]
    if len(set(items)) != len(items):
        raise argparse.ArgumentTypeError(f'{value!r} names a window twice')
    return items


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('data', nargs='+', type=input_path, metavar='DATA',
                        help='recordings (rosbag2 folders, .bag, .mcap or .db3 files, or '
                             'folders of them: converted per window, 50 %% overlap) or '
                             'datasets (.npz, one per window)')
    parser.add_argument('--models', type=names, default=list(ALL_MODELS), metavar='NAME,...',
                        help=f'models to compare (default: all {len(ALL_MODELS)}, every '
                             'deep model and every baseline)')
    parser.add_argument('--windows', type=windows, metavar='N,...',
                        help='window sizes (default 128,256,512 for recordings; the '
                             "datasets' own for .npz)")
    parser.add_argument('--folds', type=fold_count, default=5, help='folds per scheme (5)')
    parser.add_argument('--seeds', type=integer(1, 1000), default=1,
                        help='seeds 0..N-1; each draws the folds and the initial weights (1)')
    parser.add_argument('--cv', default='both', choices=[*SCHEMES, 'both'],
                        help='grouped by recording (honest), stratified windows (leaky), or '
                             'both side by side (default)')
    add_training_options(parser, threads_help='torch threads (and CPUs asked) per deep-model '
                                              'cell (1)')
    parser.add_argument('--cpus', type=integer(1, 4096),
                        help='most cores the local Ray instance may use (default: all it '
                             'detects); not with --address')
    parser.add_argument('--address', type=ray_address, metavar='HOST:PORT',
                        help='run on this Ray cluster instead of a local instance (nodes '
                             'need tactex installed; results land in --out here)')
    parser.add_argument('--device', default='auto', choices=['auto', 'cpu', 'cuda'],
                        help='auto: a GPU per deep-model cell when the cluster has one')
    parser.add_argument('--cells-per-gpu', type=integer(1, 64), default=1,
                        help='deep-model cells sharing one GPU (1)')
    parser.add_argument('--mps', action='store_true',
                        help="run the cells sharing a GPU at once through NVIDIA's "
                             'Multi-Process Service, started for the grid (a local GPU; '
                             'not with --address)')
    parser.add_argument('--out', type=output_path, required=True,
                        help='grid folder: new, or one to resume (finished cells are kept, '
                             'cells in training go on from their last kept epoch)')


def run(args: argparse.Namespace) -> int:
    """Check everything, run the missing cells on Ray, write the table and plots."""
    from tactex_classify.evaluation.model_grid import grid_cells, GridSettings, GridStore

    if args.mps:
        check_mps(args)
    elif args.device == 'cuda' and not args.address:
        from tactex_classify.evaluation.model_grid import cuda_available
        if not cuda_available():
            raise CommandError('--device cuda: this machine has no usable GPU; use --device '
                               'auto or cpu')
    if args.address and args.cpus:
        raise CommandError("--cpus caps a local Ray instance; a cluster's cores are set where "
                           'its nodes start (ray start --num-cpus): drop --cpus or --address')
    if args.address:
        from tactex_common.cluster import check_reachable
        check_reachable(args.address)  # before anything is written
    store = GridStore(args.out)
    check_grid_folder(store)
    from tactex_classify.training.deep_classifier import TrainingConfig
    patience = (TrainingConfig.for_profile(args.profile).early_stopping
                if args.early_stopping is None else args.early_stopping)
    settings = GridSettings(folds=args.folds, epochs=args.epochs, early_stopping=patience,
                            profile=args.profile, scaling=args.scaling or 'minmax')
    store.check(settings)
    started = time.monotonic()

    def log(line: str) -> None:
        print(f'[{time.monotonic() - started:7.1f} s] {line}', flush=True)

    datasets, sources, converted = load_data(args, store, log)
    schemes = SCHEMES if args.cv == 'both' else (args.cv,)
    for window, dataset in datasets.items():
        try:
            check_folds(dataset, schemes, args.folds)
        except CommandError as err:
            raise CommandError(f'window {window}: {err}') from None
        check_models_fit(args.models, window)
    cells = grid_cells(args.models, sorted(datasets), args.seeds, args.folds, schemes)
    with ExitStack() as sharing:
        if args.mps and not any(cell.model not in BASELINES and store.load(cell) is None
                                for cell in cells):
            log('--mps: no deep-model cell is left to train; MPS not started')
        elif args.mps:  # before the grid's folder is written: a refusal leaves nothing behind
            from tactex_common.errors import GpuSharingError
            from tactex_common.gpu_sharing import multi_process_service
            try:
                sharing.enter_context(multi_process_service())
            except GpuSharingError as err:
                raise CommandError(f'--mps: {err}') from None
            log('NVIDIA MPS started: the cells sharing a GPU run on it at once')
        store.open(settings, datasets, sources)
        for window in converted:
            datasets[window].save(store.folder / 'data' / f'w{window}.npz')
        run_cells(args, store, cells, datasets, settings,
                  expected_cells=args.seeds * args.folds * len(schemes), log=log)
    return 0


def check_mps(args: argparse.Namespace) -> None:
    """--mps asks for a GPU on this machine.

    Raises:
        CommandError: with --address, --device cpu, or no usable GPU here.
    """
    if args.address:
        raise CommandError('--mps starts NVIDIA MPS on this machine; on a cluster start it on '
                           'each GPU node (nvidia-cuda-mps-control -d) and drop --mps')
    if args.device == 'cpu':
        raise CommandError('--mps shares a GPU; drop it with --device cpu')
    from tactex_classify.evaluation.model_grid import cuda_available
    if not cuda_available():
        raise CommandError('--mps: this machine has no usable GPU; drop --mps')


def run_cells(args: argparse.Namespace, store, cells, datasets, settings, *,
              expected_cells: int, log) -> None:
    """Run the grid's missing cells on Ray, then write its report (also when stopped)."""
    from tactex_classify.evaluation.grid_report import fold_notes, write_report
    from tactex_classify.evaluation.model_grid import run_grid
    from tactex_common.cluster import ray_session
    with ray_session(address=args.address, cpus=args.cpus) as resources:
        gpus = resources.get('GPU', 0.0)
        if args.device == 'cuda' and not gpus:
            raise CommandError('--device cuda: the Ray instance has no GPU; use --device '
                               'auto or cpu')
        device = 'cuda' if args.device != 'cpu' and gpus else 'cpu'
        log(f'Ray: {resources.get("CPU", 0):.0f} CPUs, {gpus:.0f} GPUs; deep models on '
            f'{device}, {args.threads} thread(s) per cell')
        try:
            run_grid(store, cells, datasets, settings, threads=args.threads, device=device,
                     gpus_per_cell=1.0 / args.cells_per_gpu, progress=log,
                     keep_states=args.address is None)  # a cluster's nodes write elsewhere
        finally:
            results = store.results()
            report = write_report(args.out, results, store.manifest(),
                                  expected_cells=expected_cells)
            for note in fold_notes(results):
                log(f'note: a class absent from training in {note}')
            log(f'report: {report}')


def check_grid_folder(store) -> None:
    """--out is a new folder, an empty one, or a comparison to resume.

    Raises:
        CommandError: a file, an unwritable place, or a folder of something else.
    """
    from tactex.options import check_output_folder
    folder = store.folder
    if folder.is_dir() and store.manifest_path.is_file():
        return
    check_output_folder(folder)


def load_data(args: argparse.Namespace, store, log) -> tuple[dict, dict, list[int]]:
    """The dataset and its source of every window, and the windows converted now.

    Datasets converted from recordings are kept in `--out/data/` (by the caller, once
    the grid folder is checked) and read back when the grid resumes on the same
    recordings.

    Raises:
        CommandError: missing paths, datasets mixed with recordings, a window without a
            dataset or given twice.
    """
    from tactex_classify.data.dataset import convert, Dataset
    for path in args.data:
        if not path.exists():
            raise CommandError(f'DATA {path} does not exist')
    from tactex_classify.data.sources import is_recording
    for path in args.data:
        if path.is_file() and path.suffix != '.npz' and not is_recording(path):
            raise CommandError(f'DATA {path} is neither a dataset (.npz) nor a recording (a '
                               'rosbag2 folder, .bag, .mcap or .db3 file) nor a folder of them')
    npz = [path for path in args.data if path.suffix == '.npz']
    if npz and len(npz) != len(args.data):
        raise CommandError('DATA mixes dataset files with recordings: give datasets (.npz, '
                           'one per window) or recordings, not both')
    if npz:
        datasets = {}
        for path in npz:
            dataset = Dataset.load(path)
            window = dataset.X.shape[1]
            if window in datasets:
                raise CommandError(f'DATA gives two datasets of window {window} ({path}); '
                                   'give one per window')
            datasets[window] = (dataset, str(path))
        check_one_source([datasets[w] for w in sorted(datasets)])
        wanted = args.windows or sorted(datasets)
        missing = [w for w in wanted if w not in datasets]
        if missing:
            have = ','.join(map(str, sorted(datasets)))
            raise CommandError(f'--windows {",".join(map(str, missing))}: no dataset of that '
                               f'window in DATA (they have {have})')
        return ({w: datasets[w][0] for w in wanted}, {w: datasets[w][1] for w in wanted}, [])
    source = ' '.join(str(path.resolve()) for path in args.data)
    kept = store.manifest()['data'] if store.manifest_path.is_file() else {}
    datasets, sources, converted = {}, {}, []
    for window in args.windows or DEFAULT_WINDOWS:
        cached = store.folder / 'data' / f'w{window}.npz'
        if cached.is_file() and kept.get(str(window), {}).get('source') == source:
            log(f'window {window}: the recordings converted before ({cached})')
            datasets[window] = Dataset.load(cached)
        else:
            log(f'window {window}: converting the recordings (hop {window // 2})')
            datasets[window] = convert(args.data, window=window, hop=window // 2,
                                       progress=lambda line: None)
            converted.append(window)
        sources[window] = source
    return datasets, sources, converted


def check_one_source(datasets: list[tuple]) -> None:
    """The datasets are one set of recordings at several windows.

    A longer window may lose a recording too short for it (and with it a class), so one
    dataset's recordings (label, trial) and classes must hold the other's; the channels
    must be the same and the rates within the converter's RATE_TOLERANCE (each dataset's
    rate is the median of the recordings that gave it windows).

    Raises:
        CommandError: naming the two datasets and what differs.
    """
    from tactex_classify.data.resampling import RATE_TOLERANCE

    def recordings(dataset) -> set:
        return {(dataset.classes[y], int(t)) for y, t in zip(dataset.y, dataset.trial,
                                                              strict=True)}

    def held(a: set, b: set) -> bool:
        return a <= b or b <= a

    (first, first_path), *rest = datasets
    for dataset, path in rest:
        rates = first.info.get('sampling_rate_hz'), dataset.info.get('sampling_rate_hz')
        differs = [what for what, same in (
            ('classes', held(set(first.classes), set(dataset.classes))),
            ('channels', first.channels == dataset.channels),
            ('rate', None in rates or math.isclose(*rates, rel_tol=RATE_TOLERANCE)),
            ('recordings', held(recordings(first), recordings(dataset)))) if not same]
        if differs:
            raise CommandError(f'DATA {path} and {first_path} differ in {", ".join(differs)}: '
                               'they are not one set of recordings at two windows; give '
                               'datasets converted from the same recordings at each --window '
                               '(or the recordings themselves)')


def check_models_fit(models: list[str], window: int) -> None:
    """Every deep model can take the window (`architectures.min_window`).

    Raises:
        CommandError: naming the model, the window and the shortest it takes.
    """
    from tactex_classify.models.architectures import min_window
    for model in models:
        if model not in BASELINES and window < min_window(model):
            raise CommandError(f'--models {model} cannot take window {window}: it needs at '
                               f'least {min_window(model)} samples; drop the model or the '
                               'window')
