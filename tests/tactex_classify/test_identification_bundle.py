# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex train DATA --movements YAML`: the identification bundle, written and read back.

One checkpoint per movement with its temperature and calibrated out-of-fold evidence;
loading rebuilds the same evidence table and refuses an edited bundle, a movement file
whose movements differ in name, order or any parameter, and textures that differ from a
checkpoint's.
"""

import json
import shutil

import numpy as np
import pytest
from support.movement_data import movement_dataset, movement_file, MOVEMENTS, TEXTURES

from tactex.cli import main
from tactex_classify.errors import CheckpointError
from tactex_classify.identification.bundle import load_bundle
from tactex_description.movements import load_movements


@pytest.fixture(scope='module')
def trained(tmp_path_factory):
    folder = tmp_path_factory.mktemp('bundle')
    movement_dataset(folder)
    assert main(['train', str(folder / 'data.npz'), '--movements',
                 str(movement_file(folder)), '--model', 'extratrees', '--folds', '2',
                 '--out', str(folder / 'run')]) == 0
    return folder


def test_the_bundle_holds_a_checkpoint_per_movement_and_rebuilds_the_evidence(trained):
    bundle = load_bundle(trained / 'run' / 'bundle', load_movements(trained / 'movements.yaml'))
    assert bundle.classes == tuple(TEXTURES)
    assert [m.name for m in bundle.movements] == list(MOVEMENTS)
    assert bundle.table.names == tuple(MOVEMENTS)
    assert bundle.table.seconds == pytest.approx([2.0, 1.0, 1.0])
    assert 0.05 <= bundle.table.tempering <= 4.0
    assert all(0.05 <= t <= 20 for t in bundle.temperatures)
    window = np.random.default_rng(1).normal(size=(2, 32, 10)).astype(np.float32)
    window[:, :, 0] += 6.0  # wood, under tells_all
    assert bundle.estimators[0].predict_proba(window).argmax(axis=1).tolist() == [2, 2]


def test_a_bundle_trained_for_other_movements_is_refused(trained, tmp_path):
    bundle = trained / 'run' / 'bundle'
    other = movement_file(tmp_path, contact_s=(2.0, 1.0, 1.5))
    with pytest.raises(CheckpointError, match='movement tells_nothing was trained as .*the file '
                                              'now says'):
        load_bundle(bundle, load_movements(other))
    renamed = tmp_path / 'renamed.yaml'
    renamed.write_text(other.read_text().replace('tells_wood', 'tells_cork'))
    with pytest.raises(CheckpointError, match='the bundle holds movements tells_all, tells_wood,'
                                              ' tells_nothing; the movement file lists'):
        load_bundle(bundle, load_movements(renamed))


def test_an_edited_or_missing_bundle_is_refused(trained, tmp_path):
    movements = load_movements(trained / 'movements.yaml')
    copy = tmp_path / 'bundle'
    shutil.copytree(trained / 'run' / 'bundle', copy)
    meta = json.loads((copy / 'bundle.json').read_text())
    meta['tempering'] = 0.5
    (copy / 'bundle.json').write_text(json.dumps(meta))
    with pytest.raises(CheckpointError, match='does not match its'):
        load_bundle(copy, movements)
    (copy / 'bundle.json').unlink()
    with pytest.raises(CheckpointError, match='missing bundle.json'):
        load_bundle(copy, movements)
    with pytest.raises(CheckpointError, match='missing bundle.json'):
        load_bundle(tmp_path / 'nothing', movements)
