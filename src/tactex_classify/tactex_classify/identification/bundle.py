# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The identification bundle: a checkpoint per movement, its calibration and its evidence.

`tactex train DATA --movements YAML --out RUN` writes RUN/bundle/: one checkpoint folder
per movement (movements/<name>/, the format `tactex train` always writes, read back with
its restricted loaders) and bundle.json: the textures, the stream, the tempering
exponent and repeat discount and, per movement, its parameters, temperature and
calibrated out-of-fold sweep vectors with their true textures (what the evidence table
is built from), under a
SHA-256 of its fields. Loading checks every checkpoint and refuses a bundle whose
textures or window differ from its checkpoints', or whose movements differ, in name,
order or any parameter, or whose checkpoints' window differs, from the movement file the
caller runs; `check_bundle` makes the same checks on bundle.json and the checkpoints'
metadata without loading a model (a launch, before any node starts).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
import json
from pathlib import Path

import numpy as np

from tactex_classify.errors import CheckpointError
from tactex_classify.identification.evidence_table import EvidenceTable, MovementEvidence
from tactex_classify.identification.movement_evidence import FittedMovement
from tactex_classify.identification.tempering import Tempering
from tactex_classify.models.checkpoint import (
    CheckpointInfo,
    CHECKSUM_FIELD,
    load_estimator,
    metadata_sha256,
    read_checkpoint,
    save_checkpoint,
    StreamSpec,
    write_text_atomically,
)
from tactex_common.files import load_json
from tactex_description.movements import Movement, MovementSet

BUNDLE_FILE = 'bundle.json'
FORMAT_VERSION = 1
MAX_BUNDLE_BYTES = 64 * 1024 * 1024
MAX_BUNDLE_DEPTH = 8


@dataclass(frozen=True)
class Bundle:
    """A loaded bundle: the evidence table, each movement's model and temperature, the stream."""

    classes: tuple[str, ...]
    movements: tuple[Movement, ...]
    temperatures: tuple[float, ...]
    estimators: tuple[object, ...]
    table: EvidenceTable
    stream: StreamSpec  # what every movement's model reads (channels, window, hop, rate)


def save_bundle(folder: Path, fitted: list[FittedMovement], movements: MovementSet,
                tempering: Tempering, *, hop: int, sampling_rate_hz: float) -> Path:
    """Write the bundle of `fitted` (in the movement file's order) into `folder`."""
    folder = Path(folder)
    rows = []
    for fit in fitted:
        save_checkpoint(folder / 'movements' / fit.name, fit.estimator, hop=hop,
                        sampling_rate_hz=sampling_rate_hz)
        rows.append({**asdict(movements.by_name(fit.name)), 'temperature': fit.temperature,
                     'labels': fit.labels.tolist(), 'vectors': fit.vectors.tolist()})
    meta = {'format_version': FORMAT_VERSION, 'classes': list(fitted[0].estimator.classes_),
            'window': movements.window, 'tempering': tempering.exponent,
            'repeat_discount': tempering.repeat_discount, 'movements': rows}
    meta[CHECKSUM_FIELD] = metadata_sha256(meta)
    write_text_atomically(folder / BUNDLE_FILE, json.dumps(meta, indent=1))
    return folder


def load_bundle(folder: Path, movements: MovementSet) -> Bundle:
    """Read a bundle written by `save_bundle` for the movements of `movements`.

    Raises:
        CheckpointError: a missing or edited bundle.json, a bad checkpoint, textures or a
            window that differ between the bundle and a checkpoint, or movements or a window
            that differ from the movement file (named).
    """
    folder = Path(folder)
    meta, stated, infos = _checked(folder, movements)
    estimators = [load_estimator(info) for info in infos]
    try:
        evidence = [MovementEvidence(movement.name, movement.contact_s,
                                     np.asarray(row['vectors'], dtype=float),
                                     np.asarray(row['labels'], dtype=int))
                    for movement, row in zip(stated, meta['movements'], strict=True)]
        # A bundle written before the repeat discount counts every sweep fully.
        table = EvidenceTable(tuple(meta['classes']), evidence, float(meta['tempering']),
                              float(meta.get('repeat_discount', 0.0)))
        temperatures = tuple(float(row['temperature']) for row in meta['movements'])
    except (KeyError, TypeError, ValueError, OverflowError) as err:
        raise CheckpointError(f'{folder}: malformed {BUNDLE_FILE}: {err!r}') from None
    return Bundle(tuple(meta['classes']), tuple(stated), temperatures, tuple(estimators),
                  table, infos[0].stream)


def check_bundle(folder: Path, movements: MovementSet) -> None:
    """Refuse what `load_bundle` refuses in bundle.json and the checkpoints' metadata.

    No model is loaded: a launch checks the bundle this way before any node starts.

    Raises:
        CheckpointError: as `load_bundle`, but for a model file's contents.
    """
    _checked(Path(folder), movements)


def _checked(folder: Path, movements: MovementSet
             ) -> tuple[dict, list[Movement], list[CheckpointInfo]]:
    """(bundle.json, its movements, each one's checkpoint metadata), every check passed."""
    try:
        meta = load_json(folder / BUNDLE_FILE, max_bytes=MAX_BUNDLE_BYTES,
                         max_depth=MAX_BUNDLE_DEPTH)
    except FileNotFoundError:
        raise CheckpointError(f'{folder}: missing {BUNDLE_FILE} (write a bundle with `tactex '
                              'train DATA --movements YAML --out RUN`: RUN/bundle)') from None
    except (UnicodeDecodeError, ValueError, OSError) as err:
        raise CheckpointError(f'{folder}: refused {BUNDLE_FILE}: {err}') from None
    if not isinstance(meta, dict) or meta.get('format_version') != FORMAT_VERSION:
        raise CheckpointError(f'{folder}: not an identification bundle of format version '
                              f'{FORMAT_VERSION}')
    if meta.get(CHECKSUM_FIELD) != metadata_sha256(meta):
        raise CheckpointError(f'{folder}: {BUNDLE_FILE} does not match its {CHECKSUM_FIELD}: '
                              'edited or corrupt; train the bundle again')
    try:
        stated = _stated_movements(folder, meta, movements)
        infos = _checkpoints(folder, tuple(meta['classes']), stated)
        _check_window(folder, int(meta['window']), infos[0].stream.window, movements)
    except (KeyError, TypeError, ValueError) as err:
        raise CheckpointError(f'{folder}: malformed {BUNDLE_FILE}: {err!r}') from None
    return meta, stated, infos


def _stated_movements(folder: Path, meta: dict, movements: MovementSet) -> list[Movement]:
    """The bundle's movements, refused unless they are the movement file's, in its order."""
    stated = [Movement(**{key: row[key] for key in Movement.__dataclass_fields__})
              for row in meta['movements']]
    if [m.name for m in stated] != list(movements.names):
        raise CheckpointError(f'{folder}: the bundle holds movements '
                              f'{", ".join(m.name for m in stated)}; the movement file lists '
                              f'{", ".join(movements.names)}: train a bundle for this file')
    for movement in stated:
        if movement != movements.by_name(movement.name):
            raise CheckpointError(f'{folder}: movement {movement.name} was trained as '
                                  f'{movement}, the file now says '
                                  f'{movements.by_name(movement.name)}: train it again')
    return stated


def _checkpoints(folder: Path, classes: tuple[str, ...], stated: list[Movement]
                 ) -> list[CheckpointInfo]:
    """Each movement's checkpoint metadata, refused unless all classify `classes` alike."""
    infos: list[CheckpointInfo] = []
    for movement in stated:
        info = read_checkpoint(folder / 'movements' / movement.name)
        if tuple(info.classes) != classes:
            raise CheckpointError(f'{folder}: movement {movement.name} classifies '
                                  f'{", ".join(info.classes)}, the bundle '
                                  f'{", ".join(classes)}')
        if infos and info.stream != infos[0].stream:
            raise CheckpointError(f'{folder}: movement {movement.name} reads {info.stream}, '
                                  f'{stated[0].name} reads {infos[0].stream}: train the bundle '
                                  'again from one dataset')
        infos.append(info)
    return infos


def _check_window(folder: Path, stated: int, trained: int, movements: MovementSet) -> None:
    """Refuse a window that differs between bundle.json, its checkpoints and the movement file.

    Args:
        folder: the bundle, for the message.
        stated: the window bundle.json states.
        trained: the window every checkpoint reads.
        movements: the movement file the caller runs.

    Raises:
        CheckpointError: naming both windows and the fix.
    """
    if stated != trained:
        raise CheckpointError(f'{folder}: {BUNDLE_FILE} states a window of {stated} samples, '
                              f'its checkpoints read {trained}: train the bundle again')
    if movements.window != trained:
        raise CheckpointError(f'{folder}: its checkpoints read windows of {trained} samples, '
                              f'the movement file says window: {movements.window}: give the '
                              f'movement file the bundle was trained with (window: {trained}) '
                              'or train a bundle for this file')
