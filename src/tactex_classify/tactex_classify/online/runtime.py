# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Inference from a checkpoint with the model's own library or with onnxruntime.

`load_predictor(folder, runtime)` returns a `Predictor`: raw windows (n, window,
channels) in, probabilities (n, classes) out, in the checkpoint's class order. Runtimes:

- `native`: torch for the deep models, numpy for the random-kernel baselines,
  scikit-learn for ExtraTrees.
- `onnxruntime`: the `model.onnx` that `tactex export --onnx` wrote beside the weights
  (deep models: the scaled window in, logits out; ExtraTrees: the window statistics in,
  class probabilities out). torch is never imported, so a robot computer needs only
  numpy, scikit-learn and onnxruntime. The random-kernel baselines (MiniRocket,
  MultiRocket, HYDRA) have no ONNX form; they run in numpy.

`export_onnx` writes that file, checks it against the native model on random windows,
and stamps it with the SHA-256 of the model file it came from: a `model.onnx` exported
from other weights is refused at load.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
import io
import json
import os
from pathlib import Path
import secrets

import numpy as np

from tactex_classify.errors import CheckpointError, ExportError
from tactex_classify.models.checkpoint import (
    CheckpointInfo,
    load_estimator,
    MAX_MODEL_BYTES,
    ONNX_FILE,
    read_checkpoint,
)
from tactex_classify.models.windows import ChannelScaler, check_windows, softmax
from tactex_common.files import read_bytes

RUNTIMES = ('native', 'onnxruntime')
ONNX_KINDS = ('deep', 'extratrees')
SOURCE_KEY = 'tactex_model_sha256'  # ONNX metadata: the model file it was exported from
COLUMNS_KEY = 'tactex_seen_classes'  # ONNX metadata: class index of each output column
OPSET = 17
EXPORT_TOLERANCE = 1e-4  # largest probability difference accepted between the two runtimes


@dataclass
class Predictor:
    """Probabilities of raw windows, from one checkpoint in one runtime.

    Attributes:
        info: the checkpoint's metadata (classes, stream, model id).
        runtime: what runs the model: 'torch', 'numpy', 'scikit-learn' or 'onnxruntime'.
        run: (n, window, channels) checked float32 windows -> (n, classes) probabilities.
    """

    info: CheckpointInfo
    runtime: str
    run: Callable[[np.ndarray], np.ndarray]

    def predict_proba(self, X) -> np.ndarray:
        """(n, classes) probabilities of (n, window, channels) raw windows.

        Raises:
            TypeError, ValueError: not windows of the checkpoint's shape, or NaN/inf.
        """
        stream = self.info.stream
        return self.run(check_windows(X, window=stream.window, channels=len(stream.channels)))


def load_predictor(folder: Path, runtime: str = 'native', *, threads: int = 1) -> Predictor:
    """A predictor of a checkpoint folder.

    Args:
        folder: the checkpoint (the model/ folder `tactex train` writes).
        runtime: 'native' or 'onnxruntime' (see the module docstring).
        threads: intra-op threads of torch or onnxruntime.

    Raises:
        CheckpointError: the checkpoint, its model file or its model.onnx is refused, or
            model.onnx is missing for the onnxruntime runtime.
        ValueError: an unknown runtime.
    """
    if runtime not in RUNTIMES:
        raise ValueError(f'runtime must be one of {", ".join(RUNTIMES)}, got {runtime!r}')
    info = read_checkpoint(folder)
    if runtime == 'onnxruntime' and info.kind in ONNX_KINDS:
        return _onnx_predictor(info, threads)
    estimator = load_estimator(info)
    name = {'deep': 'torch', 'extratrees': 'scikit-learn'}.get(info.kind, 'numpy')
    if info.kind == 'deep':
        import torch
        torch.set_num_threads(threads)
    return Predictor(info, name, estimator.predict_proba)


def _onnx_predictor(info: CheckpointInfo, threads: int, path: Path | None = None
                    ) -> Predictor:
    """The onnxruntime predictor of `path` (default: the checkpoint's model.onnx)."""
    import onnxruntime

    path = path or info.folder / ONNX_FILE
    try:
        model = read_bytes(path, max_bytes=MAX_MODEL_BYTES)
    except FileNotFoundError:
        raise CheckpointError(f'{info.folder}: no {ONNX_FILE} for the onnxruntime runtime; '
                              f'write it with `tactex export {info.folder} --onnx`') from None
    except OSError as err:
        raise CheckpointError(f'{path}: refused: {err}') from None
    options = onnxruntime.SessionOptions()
    options.intra_op_num_threads = options.inter_op_num_threads = threads
    try:
        session = onnxruntime.InferenceSession(model, options,
                                               providers=['CPUExecutionProvider'])
    except Exception as err:  # noqa: BLE001 - onnxruntime raises its own exception types
        raise CheckpointError(f'{path}: refused: {str(err).splitlines()[0]}') from None
    metadata = session.get_modelmeta().custom_metadata_map
    if metadata.get(SOURCE_KEY) != next(iter(info.files.values())):
        raise CheckpointError(f"{path} was not exported from this checkpoint's "
                              f'{info.model_file.name}; export it again with `tactex export '
                              f'{info.folder} --onnx`')
    classes = len(info.classes)
    try:
        columns = np.asarray(json.loads(metadata[COLUMNS_KEY]), dtype=np.int64)
        if columns.ndim != 1 or not np.all((columns >= 0) & (columns < classes)):
            raise ValueError(columns)
    except (KeyError, ValueError, TypeError):
        raise CheckpointError(f'{path}: metadata {COLUMNS_KEY} must list output columns as '
                              f'class indices below {classes}') from None
    (inputs,), output = session.get_inputs(), session.get_outputs()[-1].name
    if info.kind == 'deep':
        scaler = ChannelScaler.from_state(info.fields['scaler'], len(info.stream.channels))

        def run(X: np.ndarray) -> np.ndarray:
            logits = session.run([output], {inputs.name: scaler.transform(X)})[0]
            return _spread(softmax(logits), columns, classes)
    else:
        from tactex_classify.models.baselines import StatsExtraTrees

        def run(X: np.ndarray) -> np.ndarray:
            features = StatsExtraTrees.features(X).astype(np.float32)
            return _spread(session.run([output], {inputs.name: features})[0], columns,
                           classes)
    return Predictor(info, 'onnxruntime', run)


def _spread(proba: np.ndarray, columns: np.ndarray, classes: int) -> np.ndarray:
    full = np.zeros((len(proba), classes))
    full[:, columns] = proba
    return full


def export_onnx(folder: Path, out: Path | None = None) -> Path:
    """Write the checkpoint's model as ONNX (default: FOLDER/model.onnx), checked.

    Raises:
        CheckpointError: the checkpoint is refused.
        ExportError: the kind has no ONNX form (MiniRocket), or the exported model's
            probabilities differ from the native model's on random windows.
    """
    import onnx

    info = read_checkpoint(folder)
    if info.kind not in ONNX_KINDS:
        raise ExportError(f'{folder}: {info.model} has no ONNX form; it runs in numpy '
                          '(no torch needed) with runtime native')
    estimator = load_estimator(info)
    rng = np.random.default_rng(0)
    stream = info.stream
    windows = rng.normal(size=(8, stream.window, len(stream.channels))).astype(np.float32)
    if info.kind == 'deep':
        model, columns = _deep_onnx(estimator, windows), list(range(len(info.classes)))
    else:
        model = _forest_onnx(estimator)
        columns = [int(c) for c in estimator.forest_.classes_]
    onnx.helper.set_model_props(model, {SOURCE_KEY: next(iter(info.files.values())),
                                        COLUMNS_KEY: json.dumps(columns),
                                        'tactex_model_id': info.model_id})
    onnx.checker.check_model(model)
    out = Path(out) if out is not None else info.folder / ONNX_FILE
    staged = out.with_name(f'.{out.name}.{secrets.token_hex(4)}.partial')
    try:
        staged.write_bytes(model.SerializeToString())
        exported = _onnx_predictor(info, 1, staged).predict_proba(windows)
        difference = float(np.max(np.abs(exported - estimator.predict_proba(windows))))
        if not difference <= EXPORT_TOLERANCE:
            raise ExportError(f"{folder}: the ONNX model's probabilities differ from the "
                              f"native model's by {difference:.3g} on random windows")
        os.replace(staged, out)
    finally:
        staged.unlink(missing_ok=True)
    return out


def _deep_onnx(estimator, windows: np.ndarray):
    """The deep model (scaled windows in, logits out) through torch's TorchScript exporter."""
    import warnings

    import onnx
    import torch

    sample = torch.from_numpy(estimator.scaler_.transform(windows[:1]))
    buffer = io.BytesIO()
    with warnings.catch_warnings():
        warnings.simplefilter('ignore')  # the exporter's deprecation and tracer notes
        torch.onnx.export(estimator.model_.eval(), (sample,), buffer, dynamo=False,
                          input_names=['windows'], output_names=['logits'],
                          dynamic_axes={'windows': {0: 'batch'}, 'logits': {0: 'batch'}},
                          opset_version=OPSET)
    return onnx.load_from_string(buffer.getvalue())


def _forest_onnx(estimator):
    """The forest (window statistics in, probabilities out) through skl2onnx."""
    from skl2onnx import convert_sklearn
    from skl2onnx.common.data_types import FloatTensorType

    forest = estimator.forest_
    return convert_sklearn(forest, initial_types=[
        ('features', FloatTensorType([None, forest.n_features_in_]))],
        options={id(forest): {'zipmap': False}}, target_opset={'': OPSET, 'ai.onnx.ml': 3})
