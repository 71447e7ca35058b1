# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""A deep model's training state kept between epochs, so an interrupted fit resumes.

The file holds everything the next epoch depends on: weights, optimizer, schedule, weight
average, the random generators (torch's global and the fit's own, numpy's), the
early-stopping bookkeeping and the history. A fit resumed from it goes on as if never
stopped: on the same machine and torch, with the same threads, it ends bit for bit where
the uninterrupted fit would. It is written whole (a temporary file renamed) at an epoch's
end, at most every `every_s` seconds, and once more when the fit ends, marked finished
(a fit that finds it finished only restores it); the caller `forget`s it once it has kept
the result, so a stop between the two loses nothing. It is read with
`torch.load(weights_only=True)` (no arbitrary objects) and set aside (the fit starts
over, with a `TrainingStateWarning`) when it is unreadable, was written for other data,
settings, threads or device, or does not fit the model.
"""

from __future__ import annotations

import contextlib
from dataclasses import asdict
import hashlib
import json
import os
from pathlib import Path
import time
import warnings

import numpy as np

STATE_VERSION = 1
KEEP_EVERY_S = 60.0  # the least time between two saves of a fit's state


class TrainingStateWarning(UserWarning):
    """A kept training state was set aside (the fit starts over) or could not be written."""


def training_key(config, X: np.ndarray, y: np.ndarray, groups, classes, device) -> str:
    """What a state belongs to: the settings, the windows, labels, recordings and device."""
    digest = hashlib.sha256(json.dumps(
        [asdict(config), list(classes), str(device), STATE_VERSION],
        sort_keys=True, default=str).encode())
    for array in (X, y, np.asarray([] if groups is None else groups).astype(str)):
        array = np.ascontiguousarray(array)
        digest.update(f'{array.dtype.str}{array.shape}'.encode())
        digest.update(array.tobytes())
    return digest.hexdigest()


class TrainingState:
    """Load and keep one fit's state in `path`, tied to its `key` (`training_key`)."""

    def __init__(self, path: Path, key: str, every_s: float = KEEP_EVERY_S) -> None:
        self.path = Path(path)
        self.key = key
        self.every_s = every_s
        self._last_save = time.monotonic()

    def load(self) -> dict | None:
        """The kept state, or None when there is none to resume from.

        A file that is not a training state, or one kept for another fit (other data,
        settings, threads or device), is set aside (`set_aside`): the fit starts from the
        beginning and its first save replaces the file.
        """
        import torch
        if not self.path.exists():
            return None
        try:
            with warnings.catch_warnings():  # torch's note on a foreign pickle protocol
                warnings.simplefilter('ignore')
                state = torch.load(self.path, map_location='cpu', weights_only=True)
        except Exception as error:  # noqa: BLE001 (any unreadable file is set aside alike)
            return self.set_aside(f'is not a training state ({error})')
        if not isinstance(state, dict) or state.get('key') != self.key:
            return self.set_aside('was kept for other data or settings')
        return state

    def set_aside(self, why: str) -> None:
        """Say with a `TrainingStateWarning` why the kept state is not resumed from."""
        warnings.warn(f'{self.path} {why}: training from the start', TrainingStateWarning,
                      stacklevel=3)

    def due(self) -> bool:
        """Whether `every_s` has passed since the last save (or since the fit began)."""
        return time.monotonic() - self._last_save >= self.every_s

    def save(self, state: dict) -> None:
        """Write `state` whole (a temporary file renamed); a failed write only warns."""
        import torch
        partial = self.path.with_name(f'.{self.path.name}.{os.getpid()}.partial')
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            torch.save({**state, 'key': self.key}, partial)
            os.replace(partial, self.path)
        except OSError as error:
            with contextlib.suppress(OSError):  # no partial file, or no folder for one
                partial.unlink()
            warnings.warn(f'{self.path}: the training state cannot be kept ({error}); the '
                          'fit goes on without it', TrainingStateWarning, stacklevel=2)
        self._last_save = time.monotonic()


def forget(path: Path, up_to: Path | None = None) -> None:
    """Remove a kept state, its partial writes and its folders left empty below `up_to`.

    The caller forgets a fit's state once it has kept what the fit gave.
    """
    path = Path(path)
    for stale in [path, *path.parent.glob(f'.{path.name}.*.partial')]:
        stale.unlink(missing_ok=True)
    folder = path.parent
    while up_to is not None and folder != Path(up_to) and Path(up_to) in folder.parents:
        try:
            folder.rmdir()
        except OSError:  # not empty, or gone
            break
        folder = folder.parent


def kept_state(parts: dict, generator, rng: np.random.Generator, **bookkeeping) -> dict:
    """Each part's `state_dict` (None for one absent), the generators' and the bookkeeping."""
    return {**{name: None if part is None else part.state_dict()
               for name, part in parts.items()},
            'random': random_states(generator, rng), **bookkeeping}


def restore_state(kept: dict, parts: dict, generator, rng: np.random.Generator) -> None:
    """Load each present part and the random generators from a `kept_state`."""
    for name, part in parts.items():
        if part is not None:
            part.load_state_dict(kept[name])
    restore_random_states(kept['random'], generator, rng)


def random_states(generator, rng: np.random.Generator) -> dict:
    """The random generators a fit draws from, as tensors and text a restricted load reads."""
    import torch
    states = {'torch': torch.get_rng_state(), 'generator': generator.get_state(),
              'numpy': json.dumps(rng.bit_generator.state)}
    if torch.cuda.is_available() and generator.device.type == 'cuda':
        states['cuda'] = torch.cuda.get_rng_state(generator.device)
    return states


def restore_random_states(states: dict, generator, rng: np.random.Generator) -> None:
    """Put the generators back as `random_states` found them."""
    import torch
    torch.set_rng_state(states['torch'])
    generator.set_state(states['generator'])
    rng.bit_generator.state = json.loads(states['numpy'])
    if 'cuda' in states:
        torch.cuda.set_rng_state(states['cuda'], generator.device)
