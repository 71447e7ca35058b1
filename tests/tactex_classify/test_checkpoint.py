# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""One checkpoint format for every model; ONNX export; nothing in a file ever runs."""

import json
from pathlib import Path
import subprocess
import sys

import numpy as np
import pytest
from test_training import CLASSES, FAST, rehash, STREAM, toy

from tactex.cli import main
from tactex_classify.baselines import MiniRocketRidge, StatsExtraTrees
from tactex_classify.checkpoint import load_checkpoint, read_checkpoint
from tactex_classify.classifier import DeepClassifier
from tactex_classify.errors import CheckpointError, ExportError
from tactex_classify.runtime import export_onnx, load_predictor


@pytest.fixture(scope='module')
def saved(tmp_path_factory):
    """A checkpoint of each kind, the deep one and the forest exported to ONNX."""
    folder = tmp_path_factory.mktemp('checkpoints')
    data = toy()
    models = {'deep': DeepClassifier(FAST), 'minirocket': MiniRocketRidge(dilations=3),
              'extratrees': StatsExtraTrees(trees=20)}
    paths = {}
    for kind, model in models.items():
        paths[kind] = model.fit(data.X, data.y, CLASSES).save(folder / kind, **STREAM)
        if kind != 'minirocket':
            export_onnx(paths[kind])
    return data, models, paths


@pytest.mark.parametrize('kind', ['deep', 'minirocket', 'extratrees'])
def test_every_kind_round_trips_with_its_stream_and_classes(saved, kind):
    data, models, paths = saved
    info, loaded = load_checkpoint(paths[kind])
    assert info.kind == kind and list(info.classes) == CLASSES
    assert info.stream.window == 96 and info.stream.hop == 48
    assert info.stream.sampling_rate_hz == 100.0 and len(info.stream.channels) == 10
    assert info.model_id.startswith(f'{info.model}@') and len(info.model_id.split('@')[1]) == 7
    np.testing.assert_allclose(loaded.predict_proba(data.X[:6]),
                               models[kind].predict_proba(data.X[:6]), rtol=1e-6, atol=1e-7)


@pytest.mark.parametrize('kind', ['deep', 'extratrees'])
def test_onnxruntime_gives_the_native_probabilities(saved, kind):
    data, _, paths = saved
    native, exported = (load_predictor(paths[kind], runtime) for runtime in
                        ('native', 'onnxruntime'))
    assert exported.runtime == 'onnxruntime'
    np.testing.assert_allclose(exported.predict_proba(data.X[:8]),
                               native.predict_proba(data.X[:8]), atol=1e-5)


def test_the_onnxruntime_path_never_imports_torch(saved):
    _, _, paths = saved
    code = ('import sys, numpy as np; from tactex_classify.runtime import load_predictor; '
            f'p = load_predictor({str(paths["deep"])!r}, "onnxruntime"); '
            'p.predict_proba(np.zeros((2, 96, 10))); '
            'print("torch" in sys.modules)')
    result = subprocess.run([sys.executable, '-c', code], capture_output=True, text=True,
                            check=True)
    assert result.stdout.strip() == 'False'


def test_minirocket_has_no_onnx_form_and_runs_in_numpy(saved):
    _, _, paths = saved
    with pytest.raises(ExportError, match='minirocket has no ONNX form'):
        export_onnx(paths['minirocket'])
    assert load_predictor(paths['minirocket'], 'onnxruntime').runtime == 'numpy'


def test_an_onnx_file_exported_from_other_weights_is_refused(saved, tmp_path):
    import shutil
    _, _, paths = saved
    folder = shutil.copytree(paths['deep'], tmp_path / 'deep')
    data = toy(seed=3)
    DeepClassifier(FAST).fit(data.X, data.y, CLASSES).save(tmp_path / 'other', **STREAM)
    shutil.copy(folder / 'model.onnx', tmp_path / 'other' / 'model.onnx')
    with pytest.raises(CheckpointError, match='was not exported from this checkpoint'):
        load_predictor(tmp_path / 'other', 'onnxruntime')
    (folder / 'model.onnx').write_bytes(b'\x08\x01garbage')
    with pytest.raises(CheckpointError, match='model.onnx: refused'):
        load_predictor(folder, 'onnxruntime')
    (folder / 'model.onnx').unlink()
    with pytest.raises(CheckpointError, match='tactex export .* --onnx'):
        load_predictor(folder, 'onnxruntime')


def test_saving_again_removes_an_export_of_the_old_weights(saved, tmp_path):
    data, models, _ = saved
    folder = models['deep'].save(tmp_path / 'deep', **STREAM)
    export_onnx(folder)
    models['deep'].save(folder, **STREAM)
    assert not (folder / 'model.onnx').exists()


def test_a_changed_model_file_fails_its_checksum(saved, tmp_path):
    import shutil
    folder = shutil.copytree(saved[2]['minirocket'], tmp_path / 'mr')
    raw = bytearray((folder / 'weights.npz').read_bytes())
    raw[-40] ^= 0xFF
    (folder / 'weights.npz').write_bytes(bytes(raw))
    with pytest.raises(CheckpointError, match='does not match its SHA-256'):
        read_checkpoint(folder)


def test_an_npz_holding_objects_is_refused_without_unpickling(saved, tmp_path):
    import shutil
    folder = shutil.copytree(saved[2]['minirocket'], tmp_path / 'mr')
    marker = tmp_path / 'pwned'

    class Payload:
        def __reduce__(self):
            import os
            return (os.system, (f'touch {marker}',))
    with np.load(folder / 'weights.npz') as npz:
        arrays = dict(npz)
    arrays['coef_'] = np.array([Payload()], dtype=object)
    with open(folder / 'weights.npz', 'wb') as handle:
        np.savez(handle, **arrays)
    rehash(folder)
    with pytest.raises(CheckpointError, match='refused weights.npz'):
        load_checkpoint(folder)
    assert not marker.exists()


def test_a_skops_file_with_foreign_types_is_refused_before_anything_runs(saved, tmp_path):
    import functools
    import os
    import shutil

    import skops.io
    folder = shutil.copytree(saved[2]['extratrees'], tmp_path / 'et')
    marker = tmp_path / 'pwned'
    skops.io.dump({'forest': functools.partial(os.system, f'touch {marker}')},
                  folder / 'model.skops')
    rehash(folder)
    with pytest.raises(CheckpointError, match="types outside the forest's own"):
        load_checkpoint(folder)
    assert not marker.exists()


@pytest.mark.parametrize('change, message', [
    (lambda m: {**m, 'config': {'dilations': 3}}, 'config must hold'),
    (lambda m: {**m, 'kind': 'extratrees'}, 'files must be'),
    (lambda m: {**m, 'classes': ['a', 'b']}, 'do not fit each other'),
])
def test_a_malformed_baseline_checkpoint_names_what_is_wrong(saved, tmp_path, change, message):
    import shutil
    folder = shutil.copytree(saved[2]['minirocket'], tmp_path / 'mr')
    meta = json.loads((folder / 'checkpoint.json').read_text())
    (folder / 'checkpoint.json').write_text(json.dumps(change(meta)))
    with pytest.raises(CheckpointError, match=message):
        load_checkpoint(folder)


def test_a_checkpoint_of_another_kind_is_named(saved):
    with pytest.raises(CheckpointError, match='a minirocket checkpoint, not a deep one'):
        DeepClassifier.load(saved[2]['minirocket'])


@pytest.mark.parametrize('model', ['minirocket', 'extratrees'])
def test_train_keeps_a_deployable_baseline_and_export_writes_its_onnx(tmp_path, model, capsys):
    data = toy()
    path = data.save(tmp_path / 'toy.npz')
    assert main(['train', str(path), '--model', model, '--folds', '2', '--cv', 'grouped',
                 '--out', str(tmp_path / 'run')]) == 0
    info, _ = load_checkpoint(tmp_path / 'run' / 'model')
    assert info.model == model and info.stream.hop == 48
    code = main(['export', str(tmp_path / 'run' / 'model'), '--onnx'])
    if model == 'extratrees':
        assert code == 0 and Path(tmp_path / 'run' / 'model' / 'model.onnx').is_file()
        assert 'runtime:=onnxruntime' in capsys.readouterr().out
    else:
        assert code == 1 and 'no ONNX form' in capsys.readouterr().err
