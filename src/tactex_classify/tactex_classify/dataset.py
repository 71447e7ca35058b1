# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Datasets of windows (the design's .npz + JSON sidecar) and how recordings become one.

`X` (n_windows, window, 10) float32 in SI units, unscaled; `y` class index; `trial` the
recording a window came from; `t0` its start (s). Windows are cut per recording, only
from samples "moving and in contact" (the segment topic when the recording has it,
else a motion + pressure rule), and never across a gap in the stream.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
import json
from pathlib import Path
import sys

import numpy as np

from tactex_classify.bags import is_recording, read_recording, Recording
from tactex_classify.errors import BagError, DatasetError
from tactex_common.channels import CHANNELS
from tactex_common.stamps import gaps

FORMAT_VERSION = 1


@dataclass(frozen=True)
class FilterRule:
    """How "moving and in contact" is decided without a segment topic.

    Attributes:
        min_joint_speed: the arm moves when its joint speed norm exceeds this (rad/s).
        contact_pa: in contact when the pressure exceeds the recording's 10th
            percentile by this much (Pa).
    """

    min_joint_speed: float = 0.005
    contact_pa: float = 40.0


@dataclass
class Dataset:
    """Windows with labels, recording ids and start times, plus the sidecar's facts."""

    X: np.ndarray
    y: np.ndarray
    trial: np.ndarray
    t0: np.ndarray
    classes: list[str]
    info: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        """Check shapes and types against the format."""
        n = len(self.X)
        if self.X.ndim != 3 or self.X.shape[2] != len(CHANNELS):
            raise DatasetError(f'X must be (n, window, {len(CHANNELS)}), got {self.X.shape}')
        for name in ('y', 'trial', 't0'):
            if getattr(self, name).shape != (n,):
                raise DatasetError(f'{name} must have shape ({n},), got '
                                   f'{getattr(self, name).shape}')
        if n and (self.y.min() < 0 or self.y.max() >= len(self.classes)):
            raise DatasetError(f'y holds class indices outside 0..{len(self.classes) - 1}')

    def save(self, path: Path) -> Path:
        """Write path (.npz) and its JSON sidecar; return the .npz path."""
        path = Path(path).with_suffix('.npz')
        path.parent.mkdir(parents=True, exist_ok=True)
        np.savez_compressed(path, X=self.X.astype(np.float32), y=self.y.astype(np.int64),
                            trial=self.trial.astype(np.int64), t0=self.t0.astype(np.float64))
        sidecar = {'format_version': FORMAT_VERSION, 'classes': self.classes,
                   'channels': list(CHANNELS), **self.info}
        path.with_suffix('.json').write_text(json.dumps(sidecar, indent=2, default=str),
                                             encoding='utf-8')
        return path

    @classmethod
    def load(cls, path: Path) -> Dataset:
        """Read a dataset (never unpickles: arrays only).

        Raises:
            DatasetError: a file is missing or breaks the format.
        """
        path = Path(path).with_suffix('.npz')
        sidecar_path = path.with_suffix('.json')
        if not path.is_file() or not sidecar_path.is_file():
            raise DatasetError(f'need {path} and its sidecar {sidecar_path}')
        try:
            with np.load(path, allow_pickle=False) as arrays:
                X, y, trial, t0 = (arrays[k] for k in ('X', 'y', 'trial', 't0'))
            sidecar = json.loads(sidecar_path.read_text(encoding='utf-8'))
        except (ValueError, KeyError, OSError) as err:
            raise DatasetError(f'{path}: {err}') from err
        if sidecar.get('channels') != list(CHANNELS):
            raise DatasetError(f'{path}: channels {sidecar.get("channels")} are not '
                               f'{list(CHANNELS)}')
        classes = sidecar.pop('classes')
        sidecar.pop('channels')
        return cls(X.astype(np.float32), y.astype(np.int64), trial.astype(np.int64),
                   t0.astype(np.float64), list(classes), sidecar)


def keep_mask(recording: Recording, rule: FilterRule, all_samples: bool) -> np.ndarray:
    """Samples that are "moving and in contact" (all of them with `all_samples`)."""
    stamps = recording.stamps_ns
    if all_samples:
        return np.ones(stamps.size, dtype=bool)
    if recording.active_ns is not None:
        keep = np.zeros(stamps.size, dtype=bool)
        for start, end in recording.active_ns:
            keep |= (stamps >= start) & (stamps <= end)
        return keep
    pressure = recording.values[:, 9]
    keep = pressure > np.percentile(pressure, 10) + rule.contact_pa
    if recording.joint_stamps_ns.size:
        speed = np.interp(stamps, recording.joint_stamps_ns, recording.joint_speed)
        keep &= speed > rule.min_joint_speed
    return keep


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
            rule: FilterRule = FilterRule(),
            progress: Callable[[str], None] = lambda line: print(line, file=sys.stderr)
            ) -> Dataset:
    """Turn recordings into a dataset; unreadable or too-short ones are reported, skipped.

    Raises:
        DatasetError: bad window/hop, nothing usable at all, or a recording without a label.
    """
    if window < 2 or not 1 <= hop <= window:
        raise DatasetError(f'need window >= 2 and 1 <= hop <= window, got {window}, {hop}')
    recordings = list(_expand(paths))
    if not recordings:
        raise DatasetError('no recordings found under the given paths')
    if trial is not None and len(recordings) > 1:
        raise DatasetError('--trial names one recording, but several were given')
    windows, labels, trials, starts_s, report, skipped = [], [], [], [], [], []
    used_trials: set[int] = set()
    rates = []
    for number, path in enumerate(recordings, 1):
        try:
            recording = read_recording(path)
        except BagError as err:
            skipped.append({'path': str(path), 'reason': str(err)})
            progress(f'[{number}/{len(recordings)}] skipped: {err}')
            continue
        name = label or recording.metadata.get('label')
        if not name:
            raise DatasetError(f'{path}: no label in the recording; pass --label')
        trial_id = trial if trial is not None else recording.metadata.get('trial')
        if trial_id is None or int(trial_id) in used_trials:
            trial_id = max(used_trials, default=-1) + 1
        used_trials.add(int(trial_id))
        keep = keep_mask(recording, rule, all_samples)
        found = window_starts(keep, recording.stamps_ns, window, hop)
        entry = {'path': str(path), 'label': name, 'trial': int(trial_id),
                 'samples': int(recording.stamps_ns.size), 'kept': int(keep.sum()),
                 'windows': len(found), 'rate_hz': recording.rate_hz,
                 'dropped': recording.dropped}
        report.append(entry)
        if not found:
            skipped.append({'path': str(path), 'reason': f'{int(keep.sum())} usable samples, '
                            f'shorter than one window of {window}'})
            progress(f'[{number}/{len(recordings)}] {path.name}: {int(keep.sum())} usable '
                     f'samples < window {window}: no window')
            continue
        rates.append(recording.rate_hz)
        for start in found:
            windows.append(recording.values[start:start + window])
            labels.append(name)
            trials.append(int(trial_id))
            starts_s.append(recording.stamps_ns[start] * 1e-9)
        progress(f'[{number}/{len(recordings)}] {path.name}: {name}, trial {trial_id}, '
                 f'{int(keep.sum())}/{recording.stamps_ns.size} samples kept, '
                 f'{len(found)} windows')
    if not windows:
        raise DatasetError('no windows: every recording was skipped or too short '
                           f'({len(skipped)} skipped)')
    classes = sorted(set(labels))
    return Dataset(np.asarray(windows, dtype=np.float32),
                   np.array([classes.index(n) for n in labels], dtype=np.int64),
                   np.array(trials, dtype=np.int64), np.array(starts_s), classes,
                   {'sampling_rate_hz': float(np.median(rates)), 'window': window, 'hop': hop,
                    'filter': 'all samples' if all_samples else
                    {'segment topic when present, else': rule.__dict__},
                    'recordings': report, 'skipped': skipped})


def _expand(paths: Iterable[Path]) -> Iterable[Path]:
    """Each given recording, or every recording directly below a given folder."""
    for path in map(Path, paths):
        if is_recording(path) or not path.is_dir():
            yield path  # a missing path is reported by read_recording
        else:
            yield from (child for child in sorted(path.iterdir()) if is_recording(child))
