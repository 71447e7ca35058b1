# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Model comparison grids: cells, where their results are kept, and how a grid runs.

A cell is one (model, window, seed, scheme, fold): the model is trained on that fold's
training windows of the dataset cut at that window size and scored on its test
windows, with `grouped` (by recording, honest) and `stratified` (windows, leaky) folds
side by side. The seed draws both the folds and the model's initial weights. Each
finished cell is one JSON file under `DIR/cells/`, written whole (temporary file and
rename), so an interrupted grid resumes where it stopped and never trains a finished
cell again; a deep model's cell in training keeps its state under `DIR/training_state/`
(at an epoch's end, at most once a minute, and at its end until its result is saved), so
a cell stopped part way goes on from its last kept epoch; `DIR/grid.json` holds what
every cell depends on besides its coordinates (training settings, the datasets'
digests), and a resumed grid must agree with it.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
import itertools
import json
import os
from pathlib import Path
import platform
import time
import warnings

import numpy as np

from tactex_classify.data.dataset import Dataset
from tactex_classify.errors import ClassifyError
from tactex_classify.models.registry import BASELINES, SCHEMES
from tactex_classify.training.training_state import forget, TrainingStateWarning

GRID_FORMAT = 1
LATENCY_CALLS = 30


class GridError(ClassifyError):
    """A grid folder that is not a comparison, or one started with other settings."""


@dataclass(frozen=True, order=True)
class Cell:
    """One training and test of the grid (fold counts from 1)."""

    seed: int
    fold: int
    scheme: str
    window: int
    model: str

    @property
    def relative_path(self) -> str:
        """Where its result lives under `DIR/cells/`."""
        return f'{self.model}/w{self.window}/seed{self.seed}-{self.scheme}-fold{self.fold}.json'

    @property
    def state_name(self) -> str:
        """Where its training state lives under `DIR/training_state/` while it trains."""
        return self.relative_path.removesuffix('.json') + '.pt'

    def describe(self) -> str:
        """Short text for progress lines."""
        return f'{self.model} w{self.window} seed {self.seed} {self.scheme} fold {self.fold}'


@dataclass(frozen=True)
class GridSettings:
    """What a cell's result depends on besides its coordinates and its dataset."""

    folds: int = 5
    epochs: int = 250
    early_stopping: int = 0
    validation_fraction: float = 0.1
    scaling: str = 'minmax'
    profile: str = 'original'  # the deep models' training profile


def grid_cells(models: Sequence[str], windows: Sequence[int], seeds: int, folds: int,
               schemes: Sequence[str] = SCHEMES) -> list[Cell]:
    """Every cell, ordered so that each round of folds covers every model and window."""
    return sorted(Cell(seed, fold, scheme, window, model) for seed, fold, scheme, window, model
                  in itertools.product(range(seeds), range(1, folds + 1), schemes, windows,
                                       models))


class GridStore:
    """A grid's folder: `grid.json` (settings, datasets) and one JSON file per cell."""

    def __init__(self, folder: Path) -> None:
        self.folder = Path(folder)

    @property
    def manifest_path(self) -> Path:
        """The grid's settings and datasets."""
        return self.folder / 'grid.json'

    def check(self, settings: GridSettings) -> dict:
        """The manifest of the grid begun here (a new one if none), checked against settings.

        Raises:
            GridError: the folder holds something else, or the grid was started with
                other settings.
        """
        if not self.manifest_path.is_file():
            if self.folder.is_dir() and any(self.folder.iterdir()):
                raise GridError(f'{self.folder} holds files but no grid.json: not a '
                                'comparison; choose a new --out')
            return {'format_version': GRID_FORMAT, 'settings': asdict(settings), 'data': {}}
        try:
            manifest = self.manifest()
        except GridError as err:
            raise GridError(f'{err}; choose a new --out') from None
        # A grid older than a setting had its default.
        before = {**asdict(GridSettings()), **manifest['settings']}
        changed = {k: (before.get(k), v) for k, v in asdict(settings).items()
                   if before.get(k) != v}
        if changed:
            described = ', '.join(f'{k} {was!r} (now {now!r})' for k, (was, now)
                                  in changed.items())
            raise GridError(f'{self.folder} was started with {described}; give the same '
                            'settings to resume it, or a new --out')
        return manifest

    def open(self, settings: GridSettings, datasets: dict[int, Dataset],
             sources: dict[int, str]) -> None:
        """Start the grid here, or check that a grid begun here agrees with these inputs.

        Windows not seen before are added; a window seen before must have the same data.

        Raises:
            GridError: the folder holds something else, or the grid was started with
                other settings or other data for a window.
        """
        manifest = self.check(settings)
        self.check_data(datasets, manifest)
        for window, dataset in datasets.items():
            manifest['data'].setdefault(str(window), {
                'sha256': dataset.digest(), 'source': sources[window],
                'windows': len(dataset.y), 'recordings': int(np.unique(dataset.trial).size),
                'classes': dataset.classes, 'channels': dataset.channels,
                'sampling_rate_hz': dataset.info.get('sampling_rate_hz')})
        (self.folder / 'cells').mkdir(parents=True, exist_ok=True)
        _write_json(self.manifest_path, manifest)

    def check_data(self, datasets: dict[int, Dataset], manifest: dict | None = None) -> None:
        """Check that each window the grid has seen before gets the same data now.

        Raises:
            GridError: a window's data differ from the data the grid was started with.
        """
        kept_data = (manifest or self.manifest())['data']
        for window, dataset in datasets.items():
            kept = kept_data.get(str(window))
            if kept and kept['sha256'] != dataset.digest():
                raise GridError(f'{self.folder} was started with other data for window '
                                f'{window} ({kept["source"]}); give the same data to resume '
                                'it, or a new --out')

    def manifest(self) -> dict:
        """The grid's settings and datasets.

        Raises:
            GridError: grid.json is not a comparison manifest (unreadable JSON, or without
                its settings and data mappings).
        """
        try:
            manifest = json.loads(self.manifest_path.read_text(encoding='utf-8'))
            if not (isinstance(manifest['settings'], dict) and isinstance(manifest['data'], dict)):
                raise TypeError
        except (ValueError, KeyError, TypeError):
            raise GridError(f'{self.manifest_path} is not a tactex comparison manifest') from None
        return manifest

    @property
    def state_folder(self) -> Path:
        """Where cells in training keep their state (`training_state`), until they finish."""
        return self.folder / 'training_state'

    def load(self, cell: Cell) -> dict | None:
        """A finished cell's result, or None (not run, or unreadable: run it again)."""
        path = self.folder / 'cells' / cell.relative_path
        try:
            result = json.loads(path.read_text(encoding='utf-8'))
        except (OSError, ValueError):
            return None
        return result if isinstance(result, dict) and result.get('cell') == asdict(cell) \
            else None

    def save(self, cell: Cell, result: dict) -> None:
        """Keep a finished cell (whole or not at all)."""
        _write_json(self.folder / 'cells' / cell.relative_path, result)

    def results(self) -> list[dict]:
        """Every finished cell kept here, whichever run made it."""
        found = []
        for path in sorted((self.folder / 'cells').rglob('*.json')):
            try:
                result = json.loads(path.read_text(encoding='utf-8'))
            except (OSError, ValueError):
                continue
            if isinstance(result, dict) and isinstance(result.get('cell'), dict):
                found.append(result)
        return found


def _write_json(path: Path, value) -> None:
    """Write JSON through a temporary file and a rename: a reader sees all or nothing."""
    path.parent.mkdir(parents=True, exist_ok=True)
    staged = path.with_name(f'.{path.name}.{os.getpid()}.partial')
    staged.write_text(json.dumps(value, indent=1) + '\n', encoding='utf-8')
    os.replace(staged, path)


def cuda_available() -> bool:
    """Whether torch sees a usable GPU on this machine."""
    import torch
    return torch.cuda.is_available()


def run_cell(datasets: dict[int, Dataset], cell: Cell, settings: GridSettings, threads: int,
             device: str, state_folder: Path | None = None) -> dict:
    """Train and score one cell; returns its result (a Ray task on any node).

    A deep model keeps its training state under `state_folder` (`GridStore.state_folder`)
    and a cell stopped part way resumes from its last kept epoch; `train_s` then counts
    the training before the stop, and `notes` say why a kept state was set aside (a
    worker's warnings do not reach the console).

    Latency is that of classifying one window through `predict_proba` (median of up to
    30 calls on test windows), as the live classifier would; throughput is the whole
    test set in one call.
    """
    from tactex_classify.evaluation.cross_validation import (
        classes_absent,
        confusion,
        metrics,
        splits,
    )
    from tactex_classify.training.deep_classifier import TrainingConfig
    from tactex_classify.training.estimators import build_estimator
    if cell.model not in BASELINES:
        import tactex_classify.models.architectures  # noqa: F401  (torch's import is no training time)
    dataset = datasets[cell.window]
    train, test = splits(dataset, cell.scheme, settings.folds, cell.seed)[cell.fold - 1]
    config = TrainingConfig.for_profile(
        settings.profile, model=cell.model, epochs=settings.epochs,
        early_stopping=settings.early_stopping, validation_fraction=settings.validation_fraction,
        scaling=settings.scaling, seed=cell.seed, threads=threads)
    estimator = build_estimator(config, device=device, state_file=None if (
        state_folder is None) else state_folder / cell.state_name)
    started = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter('always', TrainingStateWarning)
        estimator.fit(dataset.X[train], dataset.y[train], dataset.classes,
                      groups=dataset.trial[train], channels=dataset.channels)
    train_s = time.perf_counter() - started + getattr(estimator, 'resumed_seconds_', 0.0)
    started = time.perf_counter()
    predicted = estimator.predict_proba(dataset.X[test]).argmax(axis=1)
    batch_s = time.perf_counter() - started
    latencies = []
    for index in test[:LATENCY_CALLS]:
        started = time.perf_counter()
        estimator.predict_proba(dataset.X[index:index + 1])
        latencies.append(time.perf_counter() - started)
    scores = metrics(confusion(dataset.y[test], predicted, len(dataset.classes)),
                     dataset.classes)
    history = getattr(estimator, 'history_', [])
    chosen = getattr(estimator, 'best_epoch_', len(history)) if history else None
    return {'cell': asdict(cell), 'accuracy': scores['accuracy'],
            'macro_precision': scores['macro_precision'], 'macro_recall': scores['macro_recall'],
            'macro_f1': scores['macro_f1'],
            'train_accuracy': history[chosen - 1]['train_accuracy'] if history else None,
            'epochs_run': len(history) or None, 'chosen_epoch': chosen,
            'epochs_per_s': len(history) / train_s if history else None,
            'train_s': train_s, 'latency_ms': 1e3 * float(np.median(latencies)),
            'throughput_ms': 1e3 * batch_s / max(len(test), 1),
            'train_windows': int(train.size), 'test_windows': int(test.size),
            'absent_from_training': classes_absent(dataset, train),
            'y_true': dataset.y[test].tolist(), 'y_pred': predicted.tolist(),
            'threads': threads, 'device': device, 'node': platform.node(),
            'config': asdict(config) if history else None,
            'still_falling': getattr(estimator, 'still_falling_', None),
            'train_losses': [record['train_loss'] for record in history],
            'notes': [str(warning.message) for warning in caught
                      if issubclass(warning.category, TrainingStateWarning)],
            'finished': time.strftime('%Y-%m-%dT%H:%M:%S%z')}


@dataclass
class GridRun:
    """What one call of `run_grid` did."""

    total: int
    kept: int  # finished before this run
    ran: int = 0


def run_grid(store: GridStore, cells: Sequence[Cell], datasets: dict[int, Dataset],
             settings: GridSettings, *, threads: int = 1, device: str = 'cpu',
             gpus_per_cell: float = 0.0, keep_states: bool = True,
             progress: Callable[[str], None] = lambda line: None) -> GridRun:
    """Run every cell not yet kept in `store` as a Ray task (inside `ray_session`).

    Deep models ask for `threads` CPUs (and `gpus_per_cell` GPUs on `device` cuda);
    baselines for one CPU. With `keep_states` (cells on this machine, not a cluster's
    other nodes), a deep cell keeps its training state in `store.state_folder` until its
    result is saved. Each result is saved as it arrives, then a progress line (cells
    done / total, ETA from this run's pace) and the cell's notes are reported.
    """
    from tactex_common.cluster import Resources, run_tasks
    todo = [cell for cell in cells if store.load(cell) is None]
    run = GridRun(total=len(cells), kept=len(cells) - len(todo))
    progress(f'{run.kept} of {run.total} cells finished before; {len(todo)} to run')
    started = time.monotonic()

    def resources(index: int) -> Resources:
        if todo[index].model in BASELINES:
            return Resources(cpus=1)
        return Resources(cpus=threads, gpus=gpus_per_cell if device != 'cpu' else 0.0)

    def finished(index: int, result: dict) -> None:
        cell = todo[index]
        store.save(cell, result)
        forget(store.state_folder / cell.state_name, up_to=store.state_folder)
        run.ran += 1
        elapsed = time.monotonic() - started
        eta = elapsed / run.ran * (len(todo) - run.ran)
        progress(f'[{run.kept + run.ran}/{run.total}] {cell.describe()}: '
                 f'{100 * result["accuracy"]:.1f} % in {result["train_s"]:.0f} s '
                 f'(ETA {_duration(eta)})')
        for note in result.get('notes', []):
            progress(f'note: {cell.describe()}: {note}')

    states = store.state_folder.resolve() if keep_states else None
    jobs = [(cell, settings, threads, 'cpu' if cell.model in BASELINES else device, states)
            for cell in todo]
    if jobs:
        run_tasks(run_cell, jobs, shared=(datasets,), resources=resources, on_result=finished)
    return run


def _duration(seconds: float) -> str:
    """'1 h 05 min', '12 min 30 s', '40 s'."""
    seconds = int(round(seconds))
    if seconds >= 3600:
        return f'{seconds // 3600} h {seconds % 3600 // 60:02d} min'
    if seconds >= 60:
        return f'{seconds // 60} min {seconds % 60:02d} s'
    return f'{seconds} s'
