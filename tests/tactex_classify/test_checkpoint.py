# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""One checkpoint format for every model; ONNX export; nothing in a file ever runs."""

import json
from pathlib import Path
import subprocess
import sys

import numpy as np
import pytest
from support.toy_windows import CLASSES, STREAM, toy
from test_training import FAST, rehash

from tactex.cli import main
from tactex_classify.errors import CheckpointError, ExportError
from tactex_classify.models.baselines import MiniRocketRidge, StatsExtraTrees
from tactex_classify.models.checkpoint import load_checkpoint, read_checkpoint
from tactex_classify.models.hydra import HydraRidge, MultiRocketHydraRidge
from tactex_classify.models.multirocket import MultiRocketRidge
from tactex_classify.online.runtime import export_onnx, load_predictor
from tactex_classify.training.deep_classifier import DeepClassifier


@pytest.fixture(scope='module')
def saved(tmp_path_factory):
    """A checkpoint of each kind, the deep one and the forest exported to ONNX."""
    folder = tmp_path_factory.mktemp('checkpoints')
    data = toy()
    models = {'deep': DeepClassifier(FAST), 'minirocket': MiniRocketRidge(dilations=3),
              'extratrees': StatsExtraTrees(trees=20),
              'multirocket': MultiRocketRidge(dilations=2, biases_per_kernel=2),
              'hydra': HydraRidge(groups=8, kernels_per_group=4),
              'multirocket_hydra': MultiRocketHydraRidge(dilations=2, biases_per_kernel=2,
                                                         groups=4, kernels_per_group=4)}
    paths = {}
    for kind, model in models.items():
        paths[kind] = model.fit(data.X, data.y, CLASSES).save(folder / kind, **STREAM)
        if kind in ('deep', 'extratrees'):
            export_onnx(paths[kind])
    return data, models, paths


@pytest.mark.parametrize('kind', ['deep', 'minirocket', 'extratrees', 'multirocket', 'hydra',
                                  'multirocket_hydra'])
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
    code = ('import sys, numpy as np; from tactex_classify.online.runtime import load_predictor; '
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


@pytest.mark.parametrize('kind, array, change', [
    ('multirocket', 'diff_masks_', lambda a: a[:, :, :3]),
    ('multirocket', 'diff_dilations_', lambda a: np.append(a, a[-1])),
    ('hydra', 'hydra_reads_', lambda a: a + 10),
    ('hydra', 'hydra_weights_', lambda a: a[:, :, :, :2]),
    ('hydra', 'hydra_dilations_', lambda a: a * 2),
    ('multirocket_hydra', 'hydra_reads_', lambda a: a - 20),
    ('multirocket_hydra', 'masks_', lambda a: a[:1]),
])
def test_a_random_kernel_checkpoint_whose_arrays_disagree_is_refused(saved, tmp_path, kind,
                                                                    array, change):
    import shutil
    folder = shutil.copytree(saved[2][kind], tmp_path / kind)
    with np.load(folder / 'weights.npz') as npz:
        arrays = dict(npz)
    arrays[array] = change(arrays[array])
    with open(folder / 'weights.npz', 'wb') as handle:
        np.savez(handle, **arrays)
    rehash(folder)
    with pytest.raises(CheckpointError, match='arrays do not fit each other'):
        load_checkpoint(folder)


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
    rehash(folder, change)
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


def swap_first_two_classes(meta):
    return {**meta, 'classes': [meta['classes'][1], meta['classes'][0], *meta['classes'][2:]]}


EDITS = {  # each would change what the model does, and each used to load
    'swapped class names': swap_first_two_classes,
    'one class more': lambda meta: {**meta, 'classes': [*meta['classes'], 'extra']},
    'window 64': lambda meta: {**meta, 'window': 64},
    'rate 1e300': lambda meta: {**meta, 'sampling_rate_hz': 1e300},
    'another scaler': lambda meta: {**meta, 'config': {**meta['config'], 'seed': 5}},
}


@pytest.mark.parametrize('edit', EDITS.values(), ids=EDITS.keys())
@pytest.mark.parametrize('kind', ['deep', 'extratrees'])
def test_any_edit_of_checkpoint_json_fails_its_checksum(saved, tmp_path, kind, edit):
    import shutil
    folder = shutil.copytree(saved[2][kind], tmp_path / kind)
    meta = json.loads((folder / 'checkpoint.json').read_text())
    (folder / 'checkpoint.json').write_text(json.dumps(edit(meta), indent=2))
    with pytest.raises(CheckpointError, match='checkpoint.json does not match its '
                                              'metadata_sha256: edited or corrupt'):
        load_checkpoint(folder)


def test_export_of_a_checkpoint_with_swapped_classes_fails(saved, tmp_path, capsys):
    import shutil
    folder = shutil.copytree(saved[2]['extratrees'], tmp_path / 'et')
    meta = json.loads((folder / 'checkpoint.json').read_text())
    (folder / 'checkpoint.json').write_text(json.dumps(swap_first_two_classes(meta)))
    assert main(['export', str(folder), '--onnx', '--out', str(tmp_path / 'm.onnx')]) == 1
    assert 'does not match its metadata_sha256' in capsys.readouterr().err
    assert not (tmp_path / 'm.onnx').exists()


def test_a_checkpoint_of_format_2_is_refused_with_what_to_do(saved, tmp_path):
    import shutil
    folder = shutil.copytree(saved[2]['minirocket'], tmp_path / 'mr')
    rehash(folder, lambda meta: {k: v for k, v in {**meta, 'format_version': 2}.items()
                                 if k != 'metadata_sha256'})
    with pytest.raises(CheckpointError, match='format version 3 .*got 2.*before checkpoint.json '
                                              'carried its own checksum; retrain with `tactex '
                                              'train`'):
        load_checkpoint(folder)


@pytest.mark.parametrize('kind, change, message', [
    ('extratrees', lambda m: {**m, 'sampling_rate_hz': 1e300},
     r'sampling_rate_hz must be a finite number in 0.01..100000 Hz, got 1e\+300'),
    ('minirocket', lambda m: {**m, 'sampling_rate_hz': 10**400},
     'sampling_rate_hz must be a finite number in 0.01..100000 Hz, got 1000'),
    ('deep', lambda m: {**m, 'scaler': {**m['scaler'], 'offset': [10**400] * 10}},
     'scaler offset must be 10 finite numbers'),
    ('extratrees', lambda m: {**m, 'window': 10**12}, 'window must be <= 65536 samples'),
    ('minirocket', lambda m: {**m, 'channels': [f'c{i}' for i in range(65)]},
     'channels must be at most 64'),
    ('minirocket', lambda m: {**m, 'classes': [f'c{i}' for i in range(1001)]},
     'classes must be at most 1000'),
    ('extratrees', lambda m: {**m, 'classes': m['classes'][:2]}, 'not a forest of 20 trees '
                                                                 'over .* of 2 classes'),
    ('extratrees', lambda m: {**m, 'config': {'trees': 21, 'seed': 0}}, 'not a forest of 21'),
    ('extratrees', lambda m: {**m, 'config': {'trees': 10**9, 'seed': 0}},
     r'config trees must be a whole number in 1..100000'),
    ('extratrees', lambda m: {**m, 'config': {'trees': 20, 'seed': 2**40}},
     r'config seed must be a whole number in 0..4294967295'),
    ('minirocket', lambda m: {**m, 'config': {**m['config'], 'biases_per_kernel': 5}},
     'do not fit each other'),
    ('minirocket', lambda m: {**m, 'config': {**m['config'], 'dilations': 'many'}},
     'config dilations must be a whole number'),
    ('deep', lambda m: {**m, 'config': {**m['config'], 'seed': 10**20}},
     r'seed must be an integer in 0..4294967295'),
    ('deep', lambda m: {**m, 'config': {**m['config'], 'learning_rate': 1e300}},
     'learning_rate must be finite, > 0 and <= 1e6'),
])
def test_every_field_past_the_checksum_is_checked(saved, tmp_path, kind, change, message):
    import shutil
    folder = shutil.copytree(saved[2][kind], tmp_path / kind)
    rehash(folder, change)
    with pytest.raises(CheckpointError, match=message):
        load_checkpoint(folder)


def test_checkpoint_json_nested_deeper_than_read_is_refused_before_parsing(saved, tmp_path):
    import shutil
    folder = shutil.copytree(saved[2]['minirocket'], tmp_path / 'mr')
    (folder / 'checkpoint.json').write_text('[' * 100_000 + ']' * 100_000)
    with pytest.raises(CheckpointError, match='nested 100000 levels deep; at most 16 are read'):
        load_checkpoint(folder)


@pytest.mark.parametrize('name', ['checkpoint.json', 'weights.npz'])
@pytest.mark.parametrize('special', ['fifo', 'folder', 'device'])
def test_a_special_file_in_a_checkpoint_is_refused_without_waiting(saved, tmp_path, name,
                                                                    special):
    import os
    import shutil
    folder = shutil.copytree(saved[2]['minirocket'], tmp_path / 'mr')
    (folder / name).unlink()
    if special == 'fifo':
        os.mkfifo(folder / name)  # opening it for reading would wait for a writer
    elif special == 'folder':
        (folder / name).mkdir()
    else:
        (folder / name).symlink_to('/dev/zero')  # endless
    kinds = {'fifo': r'FIFO \(named pipe\)', 'folder': 'folder', 'device': 'character device'}
    with pytest.raises(CheckpointError, match=f'{name} is a {kinds[special]}, not a regular '
                                              'file'):
        load_checkpoint(folder)
