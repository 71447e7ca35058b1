# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Datasets of windows (the design's .npz + JSON sidecar) and how recordings become one.

`X` (n_windows, window, channels) float32 in SI units, unscaled, in the order the
sidecar's `channels` names; `y` class index; `trial` the recording a window came from;
`t0` its start (s). Windows are cut per recording, only from samples where the sensor
slid in contact over the labelled texture (the simulator's ground truth when the
recording has it, else the segment topic, else a motion + pressure rule; a recording
with none of these converts only with all_samples), and never across a gap in the stream.
All recordings must share one rate (`resampling.common_rate`), or are resampled onto one.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
import hashlib
import json
import math
import os
from pathlib import Path
import sys

import numpy as np

from tactex_classify.data.bags import (
    common_channels,
    inside,
    read_recording,
    Recording,
)
from tactex_classify.data.resampling import carry_mask, common_rate, resample
from tactex_classify.data.sidecar import check_sidecar_stream, recorded_sweep
from tactex_classify.data.sources import is_recording
from tactex_classify.data.stream_alignment import nearest
from tactex_classify.errors import BagError, DatasetError
from tactex_classify.models.checkpoint import MAX_CHANNELS, MAX_CLASSES, MAX_WINDOW
from tactex_common.channels import CHANNELS
from tactex_common.files import check_npz_sizes, load_json, npz_refusal, open_regular
from tactex_common.naming import natural_key, natural_sorted
from tactex_common.stamps import gaps

FORMAT_VERSION = 1
# What a dataset may take in memory, and what its JSON sidecar may be.
MAX_DATASET_BYTES = 8 * 1024**3
MAX_SIDECAR_BYTES = 16 * 1024**2
MAX_SIDECAR_DEPTH = 32
NO_CONTACT_INFORMATION = ('no sweep/active topic, joint states or ground truth tell when the '
                          'sensor slid in contact; give --all-samples to keep every sample')


@dataclass(frozen=True)
class FilterRule:
    """How "sliding in contact" is decided.

    Attributes:
        min_joint_speed: without ground truth or segments, the arm moves when its joint
            speed norm exceeds this (rad/s).
        contact_pa: ... and touches when the pressure exceeds the recording's 10th
            percentile by this much (Pa).
        min_slide_m_s: with ground truth, the edge slides when it moves faster than this.
        slide_span_s: the edge speed is measured over this span, so vibration does not
            count as sliding.
    """

    min_joint_speed: float = 0.005
    contact_pa: float = 40.0
    min_slide_m_s: float = 0.002
    slide_span_s: float = 0.1


def check_channel_names(channels: Sequence[str], width: int | None = None) -> list[str]:
    """The channel names as a list: non-empty, unique text, `width` of them if given.

    Raises:
        DatasetError: saying which rule is broken.
    """
    names = list(channels)
    if len(names) > MAX_CHANNELS:
        raise DatasetError(f'{len(names)} channels; at most {MAX_CHANNELS} are read')
    if not names or not all(isinstance(n, str) and n.strip() for n in names):
        raise DatasetError(f'channel names must be non-empty text, got {names!r}')
    repeated = sorted({n for n in names if names.count(n) > 1})
    if repeated:
        raise DatasetError(f'channel name(s) {repeated} repeat')
    if width is not None and len(names) != width:
        raise DatasetError(f'{len(names)} channel names for {width} channels')
    return names


@dataclass
class Dataset:
    """Windows with labels, recording ids and start times, plus the sidecar's facts."""

    X: np.ndarray
    y: np.ndarray
    trial: np.ndarray
    t0: np.ndarray
    classes: list[str]
    info: dict = field(default_factory=dict)
    channels: list[str] = field(default_factory=lambda: list(CHANNELS))

    def __post_init__(self) -> None:
        """Check shapes and types against the format."""
        n = len(self.X)
        if self.X.ndim != 3:
            raise DatasetError(f'X must be (n, window, channels), got {self.X.shape}')
        if not 2 <= self.X.shape[1] <= MAX_WINDOW or len(self.classes) > MAX_CLASSES:
            raise DatasetError(f'windows of {self.X.shape[1]} samples and {len(self.classes)} '
                               f'classes: need 2..{MAX_WINDOW} samples and at most '
                               f'{MAX_CLASSES} classes')
        self.channels = check_channel_names(self.channels, self.X.shape[2])
        for name in ('y', 'trial', 't0'):
            if getattr(self, name).shape != (n,):
                raise DatasetError(f'{name} must have shape ({n},), got '
                                   f'{getattr(self, name).shape}')
        if not all(isinstance(c, str) for c in self.classes):
            raise DatasetError(f'classes must be names, got {self.classes!r}')
        if n and (self.y.min() < 0 or self.y.max() >= len(self.classes)):
            raise DatasetError(f'y holds class indices outside 0..{len(self.classes) - 1}')

    def select(self, keep: np.ndarray) -> Dataset:
        """The windows `keep` (a mask or indices) selects, every class and the sidecar kept."""
        return Dataset(self.X[keep], self.y[keep], self.trial[keep], self.t0[keep],
                       self.classes, self.info, self.channels)

    def describe(self) -> str:
        """One line: windows, classes, recordings, channels and rate."""
        def counted(count: int, noun: str, plural: str) -> str:
            return f'{count} {noun if count == 1 else plural}'
        return (f'{counted(len(self.X), "window", "windows")} of {self.X.shape[1]} samples, '
                f'{counted(len(self.classes), "class", "classes")}, '
                f'{counted(len(np.unique(self.trial)), "recording", "recordings")}, channels '
                f'{",".join(self.channels)}, {self.info.get("sampling_rate_hz", math.nan):.4g} Hz')

    def digest(self) -> str:
        """SHA-256 of the arrays, classes and channels (what training reads)."""
        digest = hashlib.sha256()
        for array in (self.X, self.y, self.trial):
            digest.update(np.ascontiguousarray(array).tobytes())
        digest.update(json.dumps([self.classes, self.channels]).encode())
        return digest.hexdigest()

    def save(self, path: Path) -> Path:
        """Write path (.npz) and its JSON sidecar, each replaced whole; return the .npz path."""
        path = Path(path).with_suffix('.npz')
        path.parent.mkdir(parents=True, exist_ok=True)
        sidecar = {'format_version': FORMAT_VERSION, 'classes': self.classes,
                   'channels': self.channels, **self.info}
        staged = [path.with_name(f'.{path.name}.partial'),
                  path.with_name(f'.{path.stem}.json.partial')]
        try:
            with open(staged[0], 'wb') as handle:
                np.savez_compressed(handle, X=self.X.astype(np.float32),
                                    y=self.y.astype(np.int64), trial=self.trial.astype(np.int64),
                                    t0=self.t0.astype(np.float64))
            staged[1].write_text(json.dumps(sidecar, indent=2, default=str), encoding='utf-8')
            os.replace(staged[0], path)
            os.replace(staged[1], path.with_suffix('.json'))
        finally:
            for item in staged:
                item.unlink(missing_ok=True)
        return path

    @classmethod
    def load(cls, path: Path) -> Dataset:
        """Read a dataset (never unpickles: arrays only).

        Raises:
            DatasetError: a file is missing or breaks the format.
        """
        import zipfile

        path = Path(path).with_suffix('.npz')
        sidecar_path = path.with_suffix('.json')
        if not path.exists() or not sidecar_path.exists():
            raise DatasetError(f'need {path} and its sidecar {sidecar_path}')
        try:
            sidecar = load_json(sidecar_path, max_bytes=MAX_SIDECAR_BYTES,
                                max_depth=MAX_SIDECAR_DEPTH)
            with open_regular(path, max_bytes=MAX_DATASET_BYTES) as handle, \
                    np.load(handle, allow_pickle=False) as arrays:
                check_npz_sizes(arrays, MAX_DATASET_BYTES, path)
                X, y, trial, t0 = (arrays[k] for k in ('X', 'y', 'trial', 't0'))
        except (ValueError, KeyError, OSError, EOFError, zipfile.BadZipFile) as err:
            raise DatasetError(f'{path} is not a tactex dataset: {npz_refusal(err)}') from None
        if not isinstance(sidecar, dict) or not isinstance(sidecar.get('classes'), list) \
                or not isinstance(sidecar.get('channels'), list):
            raise DatasetError(f'{sidecar_path} is not a dataset sidecar (needs "classes" and '
                               '"channels" lists)')
        if X.dtype.kind != 'f' or y.dtype.kind not in 'iu' or trial.dtype.kind not in 'iu':
            raise DatasetError(f'{path}: X must hold floats, y and trial integers')
        classes = sidecar.pop('classes')
        channels = sidecar.pop('channels')
        check_sidecar_stream(sidecar, X.shape[1] if X.ndim == 3 else None, sidecar_path)
        try:
            return cls(X.astype(np.float32), y.astype(np.int64), trial.astype(np.int64),
                       t0.astype(np.float64), list(classes), sidecar, channels)
        except DatasetError as err:
            raise DatasetError(f'{path}: {err}') from None


class WindowCollector:
    """Windows of many recordings, gathered into one dataset.

    Args:
        window: samples per window.
        hop: samples between window starts.
    """

    def __init__(self, window: int, hop: int) -> None:
        check_window(window, hop)
        self.window, self.hop = window, hop
        self._windows: list[np.ndarray] = []
        self._labels: list[str] = []
        self._trials: list[int] = []
        self._starts: list[float] = []

    def add(self, label: str, trial: int, stamps_ns: np.ndarray, values: np.ndarray,
            keep: np.ndarray | None = None) -> int:
        """Cut the windows of one recording; return how many."""
        keep = np.ones(len(stamps_ns), dtype=bool) if keep is None else keep
        found = window_starts(keep, stamps_ns, self.window, self.hop)
        for start in found:
            self._windows.append(values[start:start + self.window])
            self._labels.append(label)
            self._trials.append(int(trial))
            self._starts.append(float(stamps_ns[start]) * 1e-9)
        return len(found)

    def dataset(self, channels: Sequence[str], info: dict) -> Dataset:
        """The dataset of every window added; classes in natural order.

        Raises:
            DatasetError: no window was added.
        """
        if not self._windows:
            raise DatasetError('no windows: every recording was skipped or too short')
        classes = natural_sorted(set(self._labels))
        index = {name: i for i, name in enumerate(classes)}
        return Dataset(np.asarray(self._windows, dtype=np.float32),
                       np.array([index[n] for n in self._labels], dtype=np.int64),
                       np.array(self._trials, dtype=np.int64), np.array(self._starts),
                       classes, {'window': self.window, 'hop': self.hop, **info},
                       list(channels))


def check_window(window: int, hop: int) -> None:
    """Refuse a window outside 2..MAX_WINDOW or a hop outside 1..window.

    Raises:
        DatasetError: naming the value and the rule.
    """
    if not 2 <= window <= MAX_WINDOW or not 1 <= hop <= window:
        raise DatasetError(f'need 2 <= window <= {MAX_WINDOW} and 1 <= hop <= window, got '
                           f'window {window}, hop {hop}')


def keep_mask(recording: Recording, rule: FilterRule, all_samples: bool,
              label: str | None = None) -> np.ndarray:
    """Samples where the sensor slid in contact over `label` (all with `all_samples`).

    With the simulator's ground truth: touching, the edge moving faster than
    `rule.min_slide_m_s`, the texture under it `label`, and inside a `sweep/active`
    segment when the recording has one. Else the segments alone; else the joints
    moving and the pressure `rule.contact_pa` above the recording's 10th percentile.
    """
    stamps = recording.stamps_ns
    if all_samples:
        return np.ones(stamps.size, dtype=bool)
    keep = np.ones(stamps.size, dtype=bool)
    if recording.active_ns is not None:
        keep = inside(stamps, recording.active_ns)
    if recording.truth is not None:
        return keep & _truly_sliding(recording, rule, label)
    if recording.active_ns is not None:
        return keep
    if 'baro' in recording.channels and stamps.size:
        pressure = recording.channel('baro')
        keep &= pressure > np.percentile(pressure, 10) + rule.contact_pa
    if recording.joint_stamps_ns.size:
        speed = np.interp(stamps, recording.joint_stamps_ns, recording.joint_speed)
        keep &= speed > rule.min_joint_speed
    return keep


def _truly_sliding(recording: Recording, rule: FilterRule, label: str | None) -> np.ndarray:
    """Ground truth: touching, sliding, over the labelled texture."""
    truth, stamps = recording.truth, recording.stamps_ns
    half_period = 0.5e9 / recording.rate_hz if stamps.size > 1 else 0.0
    touching = nearest(stamps, truth.contact_ns, half_period) >= 0
    texture = nearest(stamps, truth.texture_ns, half_period)
    names = np.append(truth.texture, '')  # index -1: no texture message near
    over = names[texture] == (label or '\0')
    sliding = np.zeros(stamps.size, dtype=bool)
    if truth.edge_ns.size > 1:
        span_ns = rule.slide_span_s * 1e9
        after = np.stack([np.interp(stamps + span_ns / 2, truth.edge_ns, axis)
                          for axis in truth.edge_m.T], axis=1)
        before = np.stack([np.interp(stamps - span_ns / 2, truth.edge_ns, axis)
                           for axis in truth.edge_m.T], axis=1)
        sliding = np.linalg.norm(after - before, axis=1) / rule.slide_span_s > rule.min_slide_m_s
    return touching & over & sliding


def window_starts(keep: np.ndarray, stamps_ns: np.ndarray, window: int, hop: int
                  ) -> list[int]:
    """Start indices of windows lying inside runs of kept, gap-free samples.

    A gap is what `tactex_common.stamps.gaps` says it is.

    Raises:
        ValueError: a window or hop below 1.
    """
    if window < 1 or hop < 1:
        raise ValueError(f'window and hop must be >= 1, got window {window!r}, hop {hop!r}')
    count = stamps_ns.size
    if count < 2:
        return []
    gap = gaps(stamps_ns)
    boundary = np.concatenate([[True], (keep[1:] != keep[:-1]) | gap])
    run_starts = np.flatnonzero(boundary)
    run_ends = np.append(run_starts[1:], count)
    starts: list[int] = []
    for run_start, run_end in zip(run_starts, run_ends, strict=True):
        if keep[run_start]:
            starts.extend(range(int(run_start), int(run_end) - window + 1, hop))
    return starts


def convert(paths: Sequence[Path], *, window: int, hop: int, label: str | None = None,
            trial: int | None = None, all_samples: bool = False,
            rule: FilterRule = FilterRule(), channels: Sequence[str] | None = None,
            remaps: Mapping[str, str] | None = None, renumber: bool = False,
            resample_hz: float | None = None,
            progress: Callable[[str], None] = lambda line: print(line, file=sys.stderr)
            ) -> Dataset:
    """Turn recordings into a dataset; unreadable, unlabelled or short ones are named, skipped.

    Args:
        paths: recordings, or folders holding recordings (each converted once).
        window: samples per window.
        hop: samples between window starts.
        label: class of the recordings that carry no label (never replaces one).
        trial: recording id of a single recording.
        all_samples: keep every sample, not only "sliding in contact".
        rule: how sliding in contact is decided.
        channels: the dataset's channels (a subset of CHANNELS); default every channel
            all recordings have (a recording without a magnetometer leaves mx, my, mz out).
        remaps: role -> topic name for bags whose topics are named otherwise.
        renumber: give a recording whose trial id another one already has the next free
            id (named in the progress and kept in the sidecar as `renumbered_from`);
            without it such recordings are refused, as one id must name one recording.
            A recording with no trial id always gets the next free one.
        resample_hz: put every recording onto this rate (`resampling.resample`); without
            it the recordings must share one rate.
        progress: receives a line per recording.

    Raises:
        DatasetError: bad window/hop or channels, no window from any recording, (without
            `renumber`) two recordings with one trial id, or (without `resample_hz`)
            recordings of different rates.
    """
    check_window(window, hop)
    recordings = recording_paths(paths, progress)
    if not recordings:
        raise DatasetError('no recordings found under the given paths')
    if trial is not None and len(recordings) > 1:
        raise DatasetError(f'--trial names one recording, but {len(recordings)} were given')
    notes: list[str] = []
    if channels is None:
        channels = common_channels(recordings, remaps, notes)
        for note in notes:
            progress(note)
    else:
        check_channel_names(channels)
    collector = WindowCollector(window, hop)
    report, skipped, rates = [], [], []
    used_trials: dict[int, str] = {}  # trial id -> the recording it names
    duplicates: list[str] = []

    def skip(number: int, path: Path, reason: str) -> None:
        skipped.append({'path': str(path), 'reason': reason})
        progress(f'[{number}/{len(recordings)}] skipped {path}: {reason}')

    for number, path in enumerate(recordings, 1):
        try:
            recording = read_recording(path, remaps=remaps, channels=channels)
        except BagError as err:
            skip(number, path, str(err).removeprefix(f'{path}: '))
            continue
        for note in recording.notes:
            progress(f'[{number}/{len(recordings)}] {path.name}: {note}')
        name = recording.metadata.get('label') or label
        if not name:
            skip(number, path, 'no label in the recording; give --label NAME for recordings '
                               'without one')
            continue
        trial_id = trial if trial is not None else recording.metadata.get('trial')
        claimed = trial_id
        if trial_id is not None and int(trial_id) in used_trials:
            duplicates.append(f'{path.name} (trial {trial_id}, as {used_trials[int(trial_id)]})')
            if not renumber:
                continue
        if trial_id is None or int(trial_id) in used_trials:
            trial_id = max(used_trials, default=-1) + 1
            if claimed is not None:
                progress(f'[{number}/{len(recordings)}] {path.name}: trial {claimed} is '
                         f"{used_trials[int(claimed)]}'s; numbered {trial_id}")
        used_trials[int(trial_id)] = path.name
        contactless = not all_samples and recording.active_ns is None \
            and recording.truth is None and not recording.joint_stamps_ns.size
        keep = np.zeros(recording.stamps_ns.size, dtype=bool) if contactless else \
            keep_mask(recording, rule, all_samples, name)
        series = [(recording.stamps_ns, recording.values, keep)]
        if resample_hz:
            try:
                series = [(stamps, values, carry_mask(keep, recording.stamps_ns, stamps))
                          for stamps, values in resample(recording.stamps_ns, recording.values,
                                                         recording.rate_hz, resample_hz)]
            except ValueError as err:
                skip(number, path, str(err))
                continue
        count = sum(collector.add(name, trial_id, *run) for run in series)
        samples = sum(int(stamps.size) for stamps, _, _ in series)
        kept = sum(int(run_keep.sum()) for _, _, run_keep in series)
        movement = recording.metadata.get('movement')
        swept = recorded_sweep(recording.metadata)
        report.append({'path': str(path), 'label': name, 'trial': int(trial_id),
                       **({'movement': movement} if isinstance(movement, str) else {}),
                       **({'sweep': swept} if swept else {}),
                       **({'renumbered_from': int(claimed)} if claimed is not None
                          and int(claimed) != int(trial_id) else {}),
                       'samples': samples, 'kept': kept, 'windows': count,
                       'rate_hz': resample_hz or recording.rate_hz,
                       **({'resampled_from_hz': recording.rate_hz} if resample_hz else {}),
                       'ground_truth': recording.truth is not None,
                       'dropped': recording.dropped, 'reordered': recording.reordered,
                       'clock_resets': recording.clock_resets,
                       'notes': recording.notes})
        if not count:
            skip(number, path, f'{samples} samples, shorter than one window of {window}'
                 if samples < window else NO_CONTACT_INFORMATION if contactless else
                 f'{kept} samples slid in contact, shorter than one window of {window}')
            continue
        rates.append((path.name, recording.rate_hz))
        progress(f'[{number}/{len(recordings)}] {path.name}: {name}, trial {trial_id}, '
                 f'{kept}/{samples} samples kept, {count} windows'
                 + (f', resampled from {recording.rate_hz:.4g} Hz' if resample_hz else ''))
    if duplicates and not renumber:
        raise DatasetError(f'{len(duplicates)} recording(s) carry a trial id another one has: '
                           f'{"; ".join(duplicates[:3])}{"; ..." if len(duplicates) > 3 else ""}'
                           '; one id must name one recording (grouped folds keep it whole): '
                           'convert them apart, or pass --renumber to give them the next '
                           'free ids')
    if not rates:
        reasons = '; '.join(f'{Path(s["path"]).name}: {s["reason"]}' for s in skipped[:3])
        raise DatasetError(f'no windows: all {len(recordings)} recording(s) skipped ({reasons}'
                           f'{"; ..." if len(skipped) > 3 else ""})')
    return collector.dataset(channels, {
        'sampling_rate_hz': float(resample_hz) if resample_hz else common_rate(rates),
        'filter': 'all samples' if all_samples else {
            'ground truth when present, else segment topic, else': rule.__dict__},
        'recordings': report, 'skipped': skipped, 'notes': notes})


def recording_paths(paths: Iterable[Path], progress: Callable[[str], None] = print
                    ) -> list[Path]:
    """The recordings given, or directly below given folders, each once."""
    return _unique(_expand(paths), progress)


def _expand(paths: Iterable[Path]) -> Iterable[Path]:
    """Each given recording, or every recording directly below a given folder."""
    for path in map(Path, paths):
        if is_recording(path) or not path.is_dir():
            yield path  # a missing path is reported by read_recording
        else:
            yield from (child for child in sorted(path.iterdir(), key=natural_key)
                        if is_recording(child))


def _unique(paths: Iterable[Path], progress: Callable[[str], None]) -> list[Path]:
    """Paths with repeats (the same recording by another name) removed, with a warning."""
    first: dict[Path, Path] = {}
    for path in paths:
        resolved = path.resolve()
        if resolved in first:
            progress(f'warning: {path} is {first[resolved]} again: converted once (the same '
                     'recording in two folds would leak)')
            continue
        first[resolved] = path
    return list(first.values())
