# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""How fast deep-model cells train together on one GPU, with and without CUDA MPS.

The GPU grid trains each cell in a process of its own, several sharing the GPU
(`tactex compare --device cuda --cells-per-gpu N`). This bench starts N such trainings at
once (fold 1 of seed 0, grouped, of the kept GPU grid's data; the modern profile with
per-window scaling, as that grid), lets each warm up for one epoch, times the epochs after
it, and reports the GPU's throughput in cell-epochs per second, against one cell alone
where the same call ran that model in one cell without options first. A run marked
`mps` repeats it under NVIDIA's Multi-Process Service, which lets the processes' kernels
share the GPU at once instead of taking turns.
A profile of one cell says whether the host (Python and kernel launches) or the GPU's
arithmetic sets a step's pace. A run marked `autotune` lets cuDNN time its algorithms for
each shape first (`torch.backends.cudnn.benchmark`), as tactex's training does on a GPU.
Each call is appended to results/gpu_pace.json (`--out`), written after each run, so a
call stopped at its time limit keeps what it measured. Its options, --data (a tactex
dataset) and --out (this bench's file) are checked before anything starts, and a machine
without a CUDA device is refused; a run none of whose cells trained stops the call with
the workers' error, and a call that measured nothing writes nothing.
"""

import argparse
from contextlib import ExitStack
import hashlib
import itertools
import json
import math
import os
from pathlib import Path
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time

os.environ.setdefault('OMP_NUM_THREADS', '1')

from bench_compare import machine  # noqa: E402
import numpy as np  # noqa: E402

from tactex.cli import CommandParser, guarded  # noqa: E402
from tactex.errors import CommandError  # noqa: E402
from tactex.options import (  # noqa: E402
    check_finite_windows,
    check_output_file,
    epoch_count,
    integer,
    load_dataset,
    number,
)
from tactex_classify.evaluation.model_grid import cuda_available  # noqa: E402
from tactex_classify.models.registry import DEEP_MODELS  # noqa: E402
from tactex_common.errors import GpuSharingError  # noqa: E402
from tactex_common.gpu_sharing import multi_process_service  # noqa: E402
from tactex_common.stopping import raise_on_stop_signals  # noqa: E402

RESULTS = Path(__file__).parent / 'results' / 'gpu_pace.json'
# Where bench/bench_compare.py converts the kept GPU grid's recordings (its --work).
DATA = Path('/tmp/tactex-compare-data/sim128_first20.npz')
FOLDS = 5  # the kept grids' folds: fold 1's training windows are a cell's
# The kept calls measured cnn_3 and inception_time; by default the next one measures the
# models the guide's full-grid estimate still scales from them, at tactex's GPU setting.
DEFAULT_RUNS = ('cnn_3:16:mps:autotune,resnet:16:mps:autotune,bilstm_1:16:mps:autotune,'
                'cnn_bilstm_1:16:mps:autotune,self_attention:16:mps:autotune,'
                'inception_time_ensemble:12:mps:autotune')
# mps: under NVIDIA's Multi-Process Service; autotune: cuDNN times its algorithms per shape.
OPTIONS = ('mps', 'autotune')
cell_count = integer(1, 64)  # trainings at once, at most as `tactex compare --cells-per-gpu`


def model_items(text: str, field: str, count, options: tuple[str, ...] = ()) -> list[tuple]:
    """Comma-separated MODEL:FIELD[:OPTION]... items as (model, count, options).

    An argparse type's helper: at least one item, each a deep model's name, its FIELD
    checked by `count`, its options among `options`.
    """
    form = f'MODEL:{field}' + ''.join(f'[:{option}]' for option in options)
    found = []
    for item in filter(str.strip, text.split(',')):
        model, *rest = item.split(':')
        wrong = f'{item!r} is not {form}'
        if model not in DEEP_MODELS:
            raise argparse.ArgumentTypeError(f'{wrong}: unknown model {model!r}; known: '
                                             f'{",".join(DEEP_MODELS)}')
        if not rest or not set(rest[1:]) <= set(options):
            raise argparse.ArgumentTypeError(wrong)
        try:
            found.append((model, count(rest[0]), rest[1:]))
        except argparse.ArgumentTypeError as err:
            raise argparse.ArgumentTypeError(f'{wrong}: {field} {err}') from None
    if not found:
        raise argparse.ArgumentTypeError(f'give at least one {form}, got {text!r}')
    return found


def parse_runs(text: str) -> list[dict]:
    """--runs: 'MODEL:CELLS[:OPTION...],...' as runs."""
    return [{'model': model, 'cells': cells, **{option: option in chosen for option in OPTIONS}}
            for model, cells, chosen in model_items(text, 'CELLS', cell_count, OPTIONS)]


def parse_epochs(text: str) -> dict[str, int]:
    """--epochs: 'MODEL:EPOCHS,...' as epochs by model."""
    return {model: epochs for model, epochs, _ in model_items(text, 'EPOCHS', epoch_count)}


def cell_pace(epoch_seconds: list[float]) -> float | None:
    """Epochs per second of one cell: the median epoch after the first (warm-up) one."""
    timed = [s for s in epoch_seconds[1:] if s > 0]
    return 1.0 / statistics.median(timed) if timed else None


def overlap(cells: list[dict]) -> tuple[float, float] | None:
    """The span (start, end) in which every cell was in its timed epochs, or None.

    It starts when the last cell ends its warm-up epoch and ends when the first cell ends
    its last epoch; outside it some cells trained on a less crowded GPU.
    """
    if not cells or any(len(cell.get('stamps', [])) < 3 for cell in cells):
        return None
    start = max(cell['stamps'][1] for cell in cells)
    end = min(cell['stamps'][-1] for cell in cells)
    return (start, end) if end > start else None


def summarise(run: dict, cells: list[dict], alone: dict | None) -> dict:
    """A run's result: each cell's pace, the GPU's throughput, and its ratio to one cell.

    The throughput counts the epochs every cell trained while all of them were training
    (`overlap`; a cell's epochs counted in fractions, from its epoch stamps).
    """
    paces = [cell_pace(cell['epoch_s']) for cell in cells]
    finished = [pace for pace in paces if pace is not None]
    span = overlap(cells) if len(cells) == run['cells'] else None
    throughput = None
    if span:
        start, end = span
        throughput = sum(float(np.interp(end, cell['stamps'], range(len(cell['stamps'])))
                               - np.interp(start, cell['stamps'], range(len(cell['stamps']))))
                         for cell in cells) / (end - start)
    result = {**run, 'epochs_per_s': [round(p, 3) for p in finished],
              'median_epochs_per_s': round(statistics.median(finished), 3) if finished else None,
              'cell_epochs_per_s': round(throughput, 3) if throughput else None,
              'throughput_over': 'overlap', 'overlap_s': round(span[1] - span[0], 1)
              if span else None,
              'steps_per_epoch': cells[0]['steps_per_epoch'] if cells else None}
    if throughput and alone and alone.get('cell_epochs_per_s'):
        result['vs_one_cell'] = round(throughput / alone['cell_epochs_per_s'], 2)
    return result


def earlier_calls(path: Path) -> list[dict]:
    """The calls kept in `path` before this one (each call appends its own); none if new.

    Raises:
        CommandError: `path` is not this bench's file (what `plot` reads of it is checked).
    """
    if not path.is_file():
        return []
    try:
        calls = json.loads(path.read_text(encoding='utf-8'))['calls']
        if isinstance(calls, list) and all(kept_call(call) for call in calls):
            return calls
    except (ValueError, KeyError, TypeError, AttributeError):
        pass
    raise CommandError(f'--out {path} is not a gpu_pace result ({{"calls": [...]}} as this bench '
                       'writes); give a file it wrote, or a new --out')


def kept_call(call: dict) -> bool:
    """Whether `call` is one this bench keeps, as far as `plot` reads it."""
    gpu = call['machine']['gpu']
    return (gpu is None or isinstance(gpu['name'], str)) and all(map(kept_run, call['runs']))


def kept_run(run: dict) -> bool:
    """Whether `run` is one this bench keeps: a model, its cells, MPS or not, a pace or None."""
    pace = run['cell_epochs_per_s']
    return (isinstance(run['model'], str) and type(run['cells']) is int and run['cells'] >= 1
            and isinstance(run['mps'], bool)
            and (pace is None or type(pace) in (int, float) and 0 <= pace < math.inf))


def check_data(path: Path) -> None:
    """--data is a tactex dataset of finite windows, read as each cell will read it.

    Raises:
        CommandError: naming --data: not a .npz file, or not a dataset.
    """
    if path.suffix != '.npz':
        raise CommandError(f'--data {path}: give a converted dataset (.npz)')
    check_finite_windows(load_dataset(path, '--data'), path, '--data')


def worker(args) -> int:
    """One cell's training (a child process): wait for the start signal, then time epochs."""
    import torch

    from tactex_classify.data.dataset import Dataset
    from tactex_classify.evaluation.cross_validation import splits
    from tactex_classify.training import deep_classifier
    from tactex_classify.training.deep_classifier import DeepClassifier, TrainingConfig
    from tactex_classify.training.validation import validation_split
    dataset = Dataset.load(args.data)
    train, _ = splits(dataset, 'grouped', FOLDS, 0)[0]
    config = TrainingConfig.for_profile('modern', model=args.worker,
                                        epochs=args.epochs[args.worker],
                                        scaling='window', seed=0, threads=1)
    fitted, _ = validation_split(dataset.y[train], dataset.trial[train], config)
    marks: list[float] = []
    classifier = DeepClassifier(config, device=args.device,
                                progress=lambda record: marks.append(time.perf_counter()))
    if not args.autotune:  # as tactex trained before it autotuned cuDNN on a GPU
        deep_classifier.prepare_training_device = torch.device
    torch.zeros(1, device=args.device)  # the device's context before the clock starts
    Path(args.ready).touch()
    while not Path(args.go).exists():
        time.sleep(0.02)
    started = time.perf_counter()
    classifier.fit(dataset.X[train], dataset.y[train], dataset.classes,
                   groups=dataset.trial[train])
    stamps = [started, *marks]  # CLOCK_MONOTONIC: one clock for every process here
    result = {'epoch_s': [b - a for a, b in itertools.pairwise(stamps)], 'stamps': stamps,
              'steps_per_epoch': math.ceil(fitted.size / config.batch_size)}
    if args.profile_cell:
        result['profile'] = profile_epoch(classifier, dataset, train, result)
    print(json.dumps(result), flush=True)
    return 0


def profile_epoch(classifier, dataset, train, timed: dict) -> dict:
    """One more epoch under torch's profiler: GPU operations and their time per step.

    The host's time per step is the unprofiled run's (its median epoch after the first,
    over its steps); where the GPU's busy time per step is far below it, the host sets
    the pace and more cells at once can use the idle GPU.
    """
    import torch
    from torch.autograd import DeviceType
    from torch.profiler import profile, ProfilerActivity
    classifier.config.epochs = 1
    activities = [ProfilerActivity.CPU]
    if torch.cuda.is_available():
        activities.append(ProfilerActivity.CUDA)
    with profile(activities=activities) as profiled:
        classifier.fit(dataset.X[train], dataset.y[train], dataset.classes,
                       groups=dataset.trial[train])
        if torch.cuda.is_available():
            torch.cuda.synchronize()
    operations, busy_us = 0, 0.0
    for event in profiled.key_averages():
        if event.device_type == DeviceType.CUDA:
            operations += event.count
            busy_us += event.self_device_time_total
    steps = timed['steps_per_epoch']
    return {'host_ms_per_step': round(1e3 / cell_pace(timed['epoch_s']) / steps, 2),
            'gpu_busy_ms_per_step': round(busy_us / 1e3 / steps, 2),
            'gpu_operations_per_step': round(operations / steps, 1)}


class Utilisation:
    """The GPU's utilisation sampled every half second while it runs (NVML), if available."""

    def __init__(self) -> None:
        self.samples: list[tuple[float, int]] = []  # (perf_counter, percent busy)
        self._stop = threading.Event()
        self._thread = None
        try:
            import pynvml
            pynvml.nvmlInit()
            self._handle, self._nvml = pynvml.nvmlDeviceGetHandleByIndex(0), pynvml
        except Exception:  # noqa: BLE001  (no NVML, no GPU: no samples, nothing else lost)
            self._handle = None

    def __enter__(self) -> 'Utilisation':
        if self._handle is not None:
            self._thread = threading.Thread(target=self._sample, daemon=True)
            self._thread.start()
        return self

    def __exit__(self, *exc) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join()

    def _sample(self) -> None:
        while not self._stop.wait(0.5):
            self.samples.append((time.perf_counter(),
                                 self._nvml.nvmlDeviceGetUtilizationRates(self._handle).gpu))

    def mean(self, span: tuple[float, float] | None) -> float | None:
        """Mean percent busy over the samples inside `span`, or None without any."""
        inside = [busy for at, busy in self.samples if span and span[0] <= at <= span[1]]
        return round(statistics.mean(inside), 1) if inside else None


def run_cells(run: dict, args, refused: dict) -> tuple[list[dict], dict]:
    """Start `run['cells']` trainings at once; their results and what went wrong, if anything.

    A run under MPS starts the service for itself (`multi_process_service`); once it could
    not start, `refused['mps']` says why and later MPS runs are skipped with that reason.
    """
    with ExitStack() as sharing:
        if run['mps']:
            try:
                if 'mps' not in refused:
                    sharing.enter_context(multi_process_service())
            except GpuSharingError as err:
                refused['mps'] = str(err)
            if 'mps' in refused:
                return [], {'skipped': refused['mps']}
        return start_cells(run, args)


def start_cells(run: dict, args) -> tuple[list[dict], dict]:
    """The cells of a run, started together and released at once when all are ready.

    Cells not all ready within `--start-timeout`, or once one has failed, are stopped
    unreleased; released cells get `--run-timeout` more. The notes keep the last line a
    failed cell wrote to stderr (its error). The GPU's utilisation is averaged over the
    span all were timed.
    """
    notes: dict = {}
    folder = Path(tempfile.mkdtemp(prefix='gpu-pace-'))
    go = folder / 'go'
    children, outputs = [], []
    try:
        for index in range(run['cells']):
            command = [sys.executable, __file__, '--worker', run['model'], '--data',
                       str(args.data), '--epochs', f"{run['model']}:{args.epochs[run['model']]}",
                       '--device', args.device, '--ready', str(folder / f'ready{index}'),
                       '--go', str(go)]
            if run['autotune']:
                command.append('--autotune')
            if args.profile and run['cells'] == 1:
                command.append('--profile-cell')
            children.append(subprocess.Popen(command, stdout=subprocess.PIPE,
                                             stderr=subprocess.PIPE, text=True))
        ready_by = time.monotonic() + args.start_timeout
        while len(list(folder.glob('ready*'))) < run['cells']:
            if time.monotonic() > ready_by:
                notes['not_ready'] = (f'{len(list(folder.glob("ready*")))} of {run["cells"]} '
                                      f'cells ready within {args.start_timeout:g} s')
            if 'not_ready' in notes or any(c.poll() is not None for c in children):
                for child in children:
                    child.kill()
                break
            time.sleep(0.05)
        else:
            go.touch()
        deadline = time.monotonic() + args.run_timeout
        with Utilisation() as busy:
            for child in children:
                try:
                    out, err = child.communicate(timeout=max(1.0, deadline - time.monotonic()))
                except subprocess.TimeoutExpired:
                    child.kill()
                    out, err = child.communicate()
                    notes['timed_out'] = notes.get('timed_out', 0) + 1
                outputs.append((child.returncode, out, err))
    finally:
        for child in children:
            if child.poll() is None:
                child.kill()
        shutil.rmtree(folder, ignore_errors=True)
    cells = []
    for returncode, out, err in outputs:
        lines = out.strip().splitlines()
        if returncode == 0 and lines:
            cells.append(json.loads(lines[-1]))
        elif returncode > 0:  # it failed; negative: this bench stopped it
            notes.setdefault('failed', []).append(
                (err.strip().splitlines() or [f'exit status {returncode}'])[-1])
    notes['gpu_busy_percent'] = busy.mean(overlap(cells))
    return cells, notes


def run_label(run: dict, call: int) -> str:
    """'12 cells, mps, autotune (call 2)'."""
    options = ''.join(f', {option}' for option in OPTIONS if run.get(option))
    return f"{run['cells']} cell{'s' if run['cells'] > 1 else ''}{options} (call {call})"


def plot(kept: dict, path: Path) -> None:
    """The GPU's throughput of each run, a panel per model, one bar per run."""
    from tactex_common import plotting
    runs = [(run, number) for number, call in enumerate(kept['calls'], 1)
            for run in call['runs'] if run.get('cell_epochs_per_s')]
    models = sorted({run['model'] for run, _ in runs})
    plt, figure, axes = plotting.figure(1, len(models), squeeze=False)
    for axis, model in zip(axes[0], models, strict=True):
        mine = sorted(((run, number) for run, number in runs if run['model'] == model),
                      key=lambda item: item[0]['cell_epochs_per_s'])
        values = [run['cell_epochs_per_s'] for run, _ in mine]
        colours = ['tab:green' if run['mps'] else 'tab:gray' for run, _ in mine]
        axis.barh(range(len(mine)), values, color=colours)
        axis.set_yticks(range(len(mine)), [run_label(run, number) for run, number in mine],
                        fontsize=7)
        for row, value in enumerate(values):
            axis.text(value, row, f' {value:.2f}', va='center', fontsize=7)
        axis.set(xscale='log', xlabel='cell-epochs per second (GPU throughput)', title=model)
        plotting.plain_log_ticks(axis.xaxis)
        axis.set_xlim(right=max(values) * 3)
    gpu = kept['calls'][-1]['machine']['gpu'] or {'name': 'no GPU'}
    plotting.save(plt, figure, path, footnote=f'trainings at once on one {gpu["name"]} '
                  '(green: under MPS); `python bench/bench_gpu_pace.py`')


def parse(argv: list[str] | None) -> argparse.Namespace:
    """The command line; a bad value is one `error:` line and exit status 1."""
    parser = CommandParser(prog='bench/bench_gpu_pace.py', description=__doc__)
    parser.add_argument('--data', type=Path, default=DATA,
                        help="a converted dataset (.npz); default the kept GPU grid's")
    parser.add_argument('--runs', type=parse_runs, default=DEFAULT_RUNS,
                        help='MODEL:CELLS[:mps][:autotune],... in order, CELLS 1..64 '
                             '(default %(default)s)')
    parser.add_argument('--epochs', type=parse_epochs,
                        default='cnn_3:4,inception_time:3,inception_time_ensemble:2',
                        help='MODEL:EPOCHS,...: epochs per cell, the first a warm-up; other '
                             'models 3 (default %(default)s)')
    parser.add_argument('--device', default='cuda', choices=['cuda'],
                        help='the GPU the cells share (this bench measures a GPU)')
    parser.add_argument('--start-timeout', type=number(), default=120.0,
                        help='seconds for every cell of a run to load before none starts')
    parser.add_argument('--run-timeout', type=number(), default=120.0,
                        help='seconds a run may train before its cells are stopped')
    parser.add_argument('--no-profile', dest='profile', action='store_false',
                        help='skip the profile of the runs of one cell')
    parser.add_argument('--out', type=Path, default=RESULTS)
    parser.add_argument('--plot', action='store_true',
                        help='only draw the PNG beside --out again from the kept calls')
    parser.add_argument('--worker', help=argparse.SUPPRESS)
    parser.add_argument('--ready', help=argparse.SUPPRESS)
    parser.add_argument('--go', help=argparse.SUPPRESS)
    parser.add_argument('--profile-cell', action='store_true', help=argparse.SUPPRESS)
    parser.add_argument('--autotune', action='store_true', help=argparse.SUPPRESS)
    return parser.parse_args(argv)


def run(args: argparse.Namespace) -> int:
    """Each run in turn; print a line per run and keep every result."""
    if args.worker:
        return worker(args)
    check_output_file(args.out, companions=('.png',))
    calls = earlier_calls(args.out)
    if args.plot:
        if not any(run['cell_epochs_per_s'] for call in calls for run in call['runs']):
            raise CommandError(f'--out {args.out}: no measured run kept there to plot; run '
                               'the bench first')
        plot({'calls': calls}, args.out.with_suffix('.png'))
        return 0
    check_data(args.data)
    if not cuda_available():
        raise CommandError('no CUDA device: this bench measures a GPU; run it on a GPU machine')
    args.epochs = dict.fromkeys({run['model'] for run in args.runs}, 3) | args.epochs
    call = {'command': ' '.join(['python', 'bench/bench_gpu_pace.py', *sys.argv[1:]]),
            'started': time.strftime('%Y-%m-%dT%H:%M:%S%z'),
            'data': {'file': args.data.name,
                     'sha256': hashlib.sha256(args.data.read_bytes()).hexdigest()},
            'machine': machine(), 'epochs': args.epochs, 'runs': []}
    alone: dict[str, dict] = {}
    refused: dict[str, str] = {}
    trained = False
    for run in args.runs:
        name = f"{run['model']} x{run['cells']}" + ''.join(
            ' ' + option for option in OPTIONS if run[option])
        started = time.monotonic()
        cells, notes = run_cells(run, args, refused)
        if not cells and 'skipped' not in notes:
            reason = (notes.get('failed') or [notes.get('not_ready')
                                              or 'every cell ran past --run-timeout'])[0]
            raise CommandError(f'--runs {name}: no cell trained ({reason}); '
                               + (f'{args.out} keeps the runs before it' if trained else
                                  'nothing written'))
        trained = trained or bool(cells)
        result = {**summarise(run, cells, alone.get(run['model'])), **notes,
                  'wall_s': round(time.monotonic() - started, 1)}
        profiles = [cell['profile'] for cell in cells if 'profile' in cell]
        if profiles:
            result['profile'] = profiles[0]
        if run['cells'] == 1 and not (run['mps'] or run['autotune']) and \
                result['cell_epochs_per_s']:
            alone[run['model']] = result
        call['runs'].append(result)
        if trained:
            args.out.parent.mkdir(parents=True, exist_ok=True)
            args.out.write_text(json.dumps({'calls': [*calls, call]}, indent=1) + '\n',
                                encoding='utf-8')
        print(f"{name}: {result['median_epochs_per_s']} epochs/s a cell, "
              f"{result['cell_epochs_per_s']} cell-epochs/s "
              f"(x{result.get('vs_one_cell', '-')} one cell), GPU "
              f"{result.get('gpu_busy_percent')} % busy, {result['wall_s']} s"
              f"{'; ' + json.dumps(notes) if set(notes) - {'gpu_busy_percent'} else ''}"
              f"{'; profile ' + json.dumps(result['profile']) if profiles else ''}",
              flush=True)
    if not trained:
        raise CommandError(f'--runs: every run was skipped (mps: {refused["mps"]}); nothing '
                           'written: run without :mps, or where MPS starts')
    if any(run.get('cell_epochs_per_s') for run in call['runs']):
        plot({'calls': [*calls, call]}, args.out.with_suffix('.png'))
    return 0


def main(argv: list[str] | None = None) -> int:
    """Entry point: one `error:` line and exit status 1 on bad input, 128+n on a signal."""
    raise_on_stop_signals()
    args = parse(argv)
    return guarded(lambda: run(args))


if __name__ == '__main__':
    sys.exit(main())
