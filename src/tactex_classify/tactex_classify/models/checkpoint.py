# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Deployable checkpoints of every model `tactex train` trains, in one format.

A checkpoint is a folder: `checkpoint.json` (format version, kind, model name, classes,
channels, window, hop, sampling rate, the SHA-256 of each model file, the kind's own
fields such as the fitted scaler, and `metadata_sha256`: the SHA-256 of all the other
fields, so no edit of anything that changes behaviour goes unnoticed) beside one model
file, read without running code from it: `weights.pt` (deep models: a state_dict loaded
with torch's `weights_only=True`), `weights.npz` (MiniRocket: plain arrays,
`allow_pickle=False`) or `model.skops` (ExtraTrees: skops with an explicit list of
trusted types). `tactex export --onnx` adds `model.onnx`, which carries the SHA-256 of
the model file it came from. Every size a checkpoint gives (window, channels, classes,
rate) is bounded, so a lying file cannot make a reader allocate or wait without end.

Each estimator class provides `CHECKPOINT_KIND`, `MODEL_FILE`, `model_name`,
`checkpoint_fields()`, `write_model(path)` and `from_checkpoint(info)` (which raises
KeyError, TypeError or ValueError for a bad field and CheckpointError for a refused model
file); this module does the rest.
"""

from __future__ import annotations

from dataclasses import dataclass
import hashlib
import importlib
import json
import os
from pathlib import Path
import reprlib
import secrets

from tactex_classify.errors import CheckpointError
from tactex_common.files import load_json, open_regular
from tactex_common.numbers import is_finite_number

FORMAT_VERSION = 3
# Why checkpoints of an older format are refused (each needs `tactex train` again).
OLD_FORMATS = {1: 'it was saved before hop and sampling rate were kept',
               2: 'it was saved before checkpoint.json carried its own checksum'}
METADATA_FILE = 'checkpoint.json'
ONNX_FILE = 'model.onnx'
# kind -> (module, class) of the estimator that reads and writes it.
KINDS = {'deep': ('tactex_classify.training.deep_classifier', 'DeepClassifier'),
         'minirocket': ('tactex_classify.models.baselines', 'MiniRocketRidge'),
         'extratrees': ('tactex_classify.models.baselines', 'StatsExtraTrees'),
         'multirocket': ('tactex_classify.models.multirocket', 'MultiRocketRidge'),
         'hydra': ('tactex_classify.models.hydra', 'HydraRidge'),
         'multirocket_hydra': ('tactex_classify.models.hydra', 'MultiRocketHydraRidge')}
CHECKSUM_FIELD = 'metadata_sha256'
COMMON_FIELDS = ('format_version', 'kind', 'model', 'classes', 'channels', 'window', 'hop',
                 'sampling_rate_hz', 'files', 'trained_on', CHECKSUM_FIELD)
MAX_JSON_BYTES = 1024 * 1024
MAX_MODEL_BYTES = 512 * 1024 * 1024  # a model file, or its model.onnx
MAX_JSON_DEPTH = 16
# What a stream may be; every size that memory or time scales with is bounded.
MAX_WINDOW = 65536  # samples per window (9 minutes at 120 Hz)
MAX_CHANNELS = 64
MAX_CLASSES = 1000
SAMPLING_RATE_RANGE_HZ = (0.01, 100_000.0)


@dataclass(frozen=True)
class StreamSpec:
    """The stream a model was trained on: what a live stream must match.

    Attributes:
        channels: channel names in the model's order.
        window: samples per window.
        hop: samples between window starts (training's; live may use another).
        sampling_rate_hz: the training data's sampling rate.
    """

    channels: tuple[str, ...]
    window: int
    hop: int
    sampling_rate_hz: float

    def __post_init__(self) -> None:
        """Check every field.

        Raises:
            ValueError: naming the field and the rule.
        """
        names = self.channels
        if not isinstance(names, tuple) or not names or not all(
                isinstance(n, str) and n for n in names) or len(set(names)) != len(names):
            raise ValueError(f'channels must be distinct names, got {names!r}')
        if len(names) > MAX_CHANNELS:
            raise ValueError(f'channels must be at most {MAX_CHANNELS}, got {len(names)}')
        for name, low in (('window', 2), ('hop', 1)):
            value = getattr(self, name)
            if not isinstance(value, int) or isinstance(value, bool) or value < low:
                raise ValueError(f'{name} must be an integer >= {low}, got {value!r}')
        if self.window > MAX_WINDOW:
            raise ValueError(f'window must be <= {MAX_WINDOW} samples, got {self.window!r}')
        if self.hop > self.window:
            raise ValueError(f'hop must be <= window ({self.window}), got {self.hop!r}')
        rate, (low, high) = self.sampling_rate_hz, SAMPLING_RATE_RANGE_HZ
        if not (is_finite_number(rate) and low <= rate <= high):
            raise ValueError(f'sampling_rate_hz must be a finite number in {low:g}..{high:g} '
                             f'Hz, got {reprlib.repr(rate)}')

    @property
    def window_s(self) -> float:
        """Seconds of signal in one window."""
        return self.window / self.sampling_rate_hz

    def mismatches(self, *, channels=None, window=None, sampling_rate_hz=None,
                   rate_tolerance: float = 0.05) -> list[str]:
        """What differs between this spec and a stream's (None: not compared).

        Returns:
            One line per mismatch naming both sides, e.g. 'rate: the model was trained at
            120 Hz, the stream runs at 350 Hz'.
        """
        lines = []
        if channels is not None and tuple(channels) != self.channels:
            lines.append(f'channels: the model was trained on {", ".join(self.channels)}, the '
                         f'stream has {", ".join(channels) or "none"}')
        if window is not None and window != self.window:
            lines.append(f'window: the model was trained on {self.window}-sample windows, the '
                         f'stream is cut into {window}')
        if sampling_rate_hz is not None and not (
                abs(sampling_rate_hz - self.sampling_rate_hz)
                <= rate_tolerance * self.sampling_rate_hz):
            lines.append(f'rate: the model was trained at {self.sampling_rate_hz:g} Hz, the '
                         f'stream runs at {sampling_rate_hz:.4g} Hz')
        return lines


@dataclass(frozen=True)
class CheckpointInfo:
    """A checkpoint's validated metadata; no model file loaded yet.

    Attributes:
        folder: the checkpoint folder.
        kind: 'deep' or a baseline's name (KINDS).
        model: the model's name (`cnn_3`, `minirocket`, ...).
        classes: class names in the model's output order.
        stream: what the model expects of its input.
        files: model file name -> SHA-256 (hex).
        fields: the kind's own fields of checkpoint.json (scaler, configuration).
        trained_on: `Dataset.digest()` of the dataset it was trained on ('' unknown).
    """

    folder: Path
    kind: str
    model: str
    classes: tuple[str, ...]
    stream: StreamSpec
    files: dict[str, str]
    fields: dict
    trained_on: str = ''

    @property
    def model_file(self) -> Path:
        """Path of the model file."""
        return self.folder / next(iter(self.files))

    @property
    def scaling(self) -> str | None:
        """The input scaling a deep model was trained with (`minmax`, ...; None: a baseline)."""
        return self.fields.get('scaler', {}).get('kind')

    @property
    def model_id(self) -> str:
        """`name@sha` (first 7 hex digits of the model file's SHA-256)."""
        return f'{self.model}@{next(iter(self.files.values()))[:7]}'


def sha256(path: Path) -> str:
    """Hex SHA-256 of a regular file's bytes (at most MAX_MODEL_BYTES)."""
    digest = hashlib.sha256()
    with open_regular(path, max_bytes=MAX_MODEL_BYTES) as handle:
        for block in iter(lambda: handle.read(1 << 20), b''):
            digest.update(block)
    return digest.hexdigest()


def estimator_class(kind: str):
    """The class that reads and writes checkpoints of `kind`."""
    module, name = KINDS[kind]
    return getattr(importlib.import_module(module), name)


def save_checkpoint(folder: Path, estimator, *, hop: int, sampling_rate_hz: float,
                    trained_on: str = '') -> Path:
    """Write a fitted estimator's checkpoint into `folder` (created; files replaced whole).

    Args:
        folder: the checkpoint folder.
        estimator: a fitted DeepClassifier, MiniRocketRidge or StatsExtraTrees.
        hop: the training data's hop (samples).
        sampling_rate_hz: the training data's sampling rate.
        trained_on: the training dataset's `Dataset.digest()`, so that a prediction on
            that same dataset can say its accuracy is in-sample ('' leaves it out).

    Raises:
        NotFittedError: the estimator is not fitted.
        ValueError: a bad hop or rate.
    """
    stream = StreamSpec(tuple(estimator.channels_), estimator.window_, int(hop),
                        float(sampling_rate_hz))
    fields = estimator.checkpoint_fields()  # raises NotFittedError first
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    name = estimator.MODEL_FILE
    staged = folder / f'.{name}.{secrets.token_hex(4)}.partial'
    try:
        estimator.write_model(staged)
        digest = sha256(staged)
        os.replace(staged, folder / name)
    finally:
        staged.unlink(missing_ok=True)
    (folder / ONNX_FILE).unlink(missing_ok=True)  # exported from other weights
    meta = {'format_version': FORMAT_VERSION, 'kind': estimator.CHECKPOINT_KIND,
            'model': estimator.model_name, 'classes': list(estimator.classes_),
            'channels': list(stream.channels), 'window': stream.window, 'hop': stream.hop,
            'sampling_rate_hz': stream.sampling_rate_hz, 'files': {name: digest}, **fields,
            **({'trained_on': trained_on} if trained_on else {})}
    meta = json.loads(json.dumps(meta))  # as it will be read back
    meta[CHECKSUM_FIELD] = metadata_sha256(meta)
    write_text_atomically(folder / METADATA_FILE, json.dumps(meta, indent=2))
    return folder


def metadata_sha256(meta: dict) -> str:
    """Hex SHA-256 of checkpoint.json's fields but the checksum itself, in canonical JSON."""
    fields = {k: v for k, v in meta.items() if k != CHECKSUM_FIELD}
    canonical = json.dumps(fields, sort_keys=True, separators=(',', ':'), ensure_ascii=True)
    return hashlib.sha256(canonical.encode('ascii')).hexdigest()


def write_text_atomically(path: Path, text: str) -> None:
    """Replace `path` by `text` whole (a crash leaves the old file or the new one)."""
    staged = path.with_name(f'.{path.name}.{secrets.token_hex(4)}.partial')
    try:
        staged.write_text(text, encoding='utf-8')
        os.replace(staged, path)
    finally:
        staged.unlink(missing_ok=True)


def read_checkpoint(folder: Path) -> CheckpointInfo:
    """Validate checkpoint.json and the model file's checksum; load nothing.

    Raises:
        CheckpointError: naming the folder and what is wrong (a missing file, a field and
            its rule, a checksum that does not match).
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise CheckpointError(f'{folder}: not a checkpoint folder (the model/ folder '
                              '`tactex train` writes)')
    path = folder / METADATA_FILE
    try:
        meta = load_json(path, max_bytes=MAX_JSON_BYTES, max_depth=MAX_JSON_DEPTH)
    except FileNotFoundError:
        run = (folder / 'model' / METADATA_FILE).is_file()  # a `tactex train` run folder
        raise CheckpointError(f'{folder}: missing {METADATA_FILE}'
                              + (f'; give its checkpoint, {folder / "model"}' if run else '')
                              ) from None
    except (UnicodeDecodeError, ValueError, OSError) as err:
        raise CheckpointError(f'{folder}: refused {METADATA_FILE}: {err}; retrain or copy the '
                              'whole folder again') from None
    if not isinstance(meta, dict) or meta.get('kind') not in KINDS:
        raise CheckpointError(f'{folder}: not a tactex checkpoint (kind must be one of '
                              f'{", ".join(KINDS)})')
    version = meta.get('format_version')
    if version != FORMAT_VERSION:
        hint = (f': {OLD_FORMATS[version]}; retrain with `tactex train` (and export again)'
                if version in OLD_FORMATS else '')
        raise CheckpointError(f'{folder}: not a tactex checkpoint of format version '
                              f'{FORMAT_VERSION} (got {version!r}){hint}')
    if meta.get(CHECKSUM_FIELD) != metadata_sha256(meta):
        raise CheckpointError(f'{folder}: {METADATA_FILE} does not match its {CHECKSUM_FIELD}: '
                              'edited or corrupt (classes, stream and settings are part of '
                              'the model); retrain or copy the whole folder again')
    try:
        info = _info(folder, meta)
    except KeyError as err:
        raise CheckpointError(f'{folder}: malformed {METADATA_FILE}: missing {err}') from None
    except (TypeError, ValueError) as err:
        raise CheckpointError(f'{folder}: malformed {METADATA_FILE}: {err}') from None
    for name, digest in info.files.items():
        try:
            actual = sha256(folder / name)
        except FileNotFoundError:
            raise CheckpointError(f'{folder}: missing {name}') from None
        except OSError as err:
            raise CheckpointError(f'{folder}: refused {name}: {err}') from None
        if actual != digest:
            raise CheckpointError(f'{folder}: {name} does not match its SHA-256 in '
                                  f'{METADATA_FILE}: corrupt or replaced; retrain or copy the '
                                  'whole folder again')
    return info


def _info(folder: Path, meta: dict) -> CheckpointInfo:
    """CheckpointInfo of checkpoint.json's fields (KeyError, TypeError, ValueError)."""
    kind = meta['kind']
    classes = _names(meta['classes'], 'classes')
    stream = StreamSpec(tuple(_names(meta['channels'], 'channels')), meta['window'],
                        meta['hop'], meta['sampling_rate_hz'])
    model_file = estimator_class(kind).MODEL_FILE
    files = meta['files']
    if not isinstance(files, dict) or list(files) != [model_file] or not isinstance(
            files[model_file], str) or len(files[model_file]) != 64 or not all(
            c in '0123456789abcdef' for c in files[model_file]):
        raise ValueError(f'files must be {{"{model_file}": SHA-256 hex}} for kind {kind!r}, '
                         f'got {files!r}')
    model = meta['model']
    if not isinstance(model, str) or not model:
        raise ValueError(f'model must be a name, got {model!r}')
    fields = {k: v for k, v in meta.items() if k not in COMMON_FIELDS}
    trained_on = meta.get('trained_on', '')
    if not (isinstance(trained_on, str) and len(trained_on) in (0, 64)):
        raise ValueError('trained_on must be a SHA-256 hex digest, got '
                         f'{reprlib.repr(trained_on)}')
    return CheckpointInfo(folder, kind, model, tuple(classes), stream, dict(files), fields,
                          trained_on)


def _names(value, field: str) -> list[str]:
    """A non-empty list of distinct, non-empty strings from a checkpoint field."""
    if not isinstance(value, list) or not value or not all(
            isinstance(v, str) and v for v in value) or len(set(value)) != len(value):
        raise ValueError(f'{field} must be a non-empty list of distinct names, got {value!r}')
    if field == 'classes' and len(value) > MAX_CLASSES:
        raise ValueError(f'classes must be at most {MAX_CLASSES}, got {len(value)}')
    return value


def load_estimator(info: CheckpointInfo):
    """The fitted estimator of a validated checkpoint (its model file read safely).

    Raises:
        CheckpointError: the kind's fields or the model file are refused.
    """
    try:
        estimator = estimator_class(info.kind).from_checkpoint(info)
    except KeyError as err:
        raise CheckpointError(f'{info.folder}: malformed {METADATA_FILE}: missing {err}'
                              ) from None
    except (TypeError, ValueError) as err:
        raise CheckpointError(f'{info.folder}: malformed {METADATA_FILE}: {err}') from None
    if estimator.model_name != info.model:
        raise CheckpointError(f'{info.folder}: model {info.model!r} disagrees with its '
                              f'configuration ({estimator.model_name!r})')
    return estimator


def restore_fitted(estimator, info: CheckpointInfo) -> None:
    """Set the fitted attributes every estimator shares from a checkpoint's metadata."""
    estimator.classes_ = list(info.classes)
    estimator.channels_ = list(info.stream.channels)
    estimator.n_channels_ = len(info.stream.channels)
    estimator.window_ = info.stream.window


class Deployable:
    """`save` and `load` of the estimators, through this module's one format."""

    CHECKPOINT_KIND = ''
    MODEL_FILE = ''

    def save(self, folder: Path, *, hop: int, sampling_rate_hz: float,
             trained_on: str = '') -> Path:
        """Write the checkpoint into `folder` (see `save_checkpoint`); return the folder."""
        return save_checkpoint(folder, self, hop=hop, sampling_rate_hz=sampling_rate_hz,
                               trained_on=trained_on)

    @classmethod
    def load(cls, folder: Path):
        """The estimator saved in `folder`.

        Raises:
            CheckpointError: not a checkpoint of this class's kind, or refused.
        """
        info = read_checkpoint(folder)
        if info.kind != cls.CHECKPOINT_KIND:
            raise CheckpointError(f'{folder}: a {info.kind} checkpoint, not a '
                                  f'{cls.CHECKPOINT_KIND} one; load it with load_checkpoint')
        return load_estimator(info)


def load_checkpoint(folder: Path):
    """(CheckpointInfo, estimator) of a checkpoint folder (see `read_checkpoint`)."""
    info = read_checkpoint(folder)
    return info, load_estimator(info)
