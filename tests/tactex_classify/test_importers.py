# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Importers: MUN pickles through the restricted unpickler, folders of CSV."""

import os
import pickle

import numpy as np
import pandas as pd
import pytest

from tactex.cli import main
from tactex_classify.errors import DatasetError
from tactex_classify.importers import (
    import_csv,
    import_mun,
    load_frame,
    MUN_IMU_COLUMNS,
    parse_column_mapping,
)

QUIET = {'progress': lambda line: None}


def write_mun(root, textures=2, trials=2, samples=800, protocol=4):
    rng = np.random.default_rng(0)
    for speed in ('30', '40'):
        for texture in range(1, textures + 1):
            folder = root / f'pickles_{speed}' / f'texture_{texture:02d}'
            (folder / 'full_imu').mkdir(parents=True)
            (folder / 'full_baro').mkdir(parents=True)
            for trial in range(trials):
                imu = pd.DataFrame(rng.normal(texture, 1.0, (samples, 9)),
                                   columns=list(MUN_IMU_COLUMNS))
                baro = pd.DataFrame({'baro': rng.normal(1000.0, 1.0, samples)})
                name = f'trial_{trial}.pkl'
                (folder / 'full_imu' / name).write_bytes(pickle.dumps(imu, protocol=protocol))
                (folder / 'full_baro' / name).write_bytes(pickle.dumps(baro, protocol=protocol))


class Boom:
    """Runs a shell command when unpickled."""

    def __reduce__(self):
        return (os.system, ('echo pwned > /tmp/tactex_pwned',))


@pytest.mark.parametrize('protocol', [2, 4, 5])
def test_mun_layout_imports_with_trials_and_classes(tmp_path, protocol):
    write_mun(tmp_path, protocol=protocol)
    data = import_mun(tmp_path, window=350, hop=175, **QUIET)
    assert data.classes == ['texture_01', 'texture_02']
    assert data.X.shape[1:] == (350, 10)
    assert len(set(data.trial.tolist())) == 8  # 2 speeds x 2 textures x 2 trials
    assert data.info['sampling_rate_hz'] == 350.0


def test_malicious_pickle_is_refused_and_runs_nothing(tmp_path):
    write_mun(tmp_path)
    target = next(tmp_path.glob('pickles_30/texture_01/full_imu/*.pkl'))
    target.write_bytes(pickle.dumps(Boom()))
    if os.path.exists('/tmp/tactex_pwned'):
        os.remove('/tmp/tactex_pwned')
    with pytest.raises(DatasetError, match='refusing to load posix.system'):
        import_mun(tmp_path, window=350, hop=175, **QUIET)
    assert not os.path.exists('/tmp/tactex_pwned')


def test_a_pickle_of_something_else_is_refused(tmp_path):
    path = tmp_path / 'x.pkl'
    path.write_bytes(pickle.dumps(np.arange(3)))
    with pytest.raises(DatasetError, match='not a DataFrame'):
        load_frame(path)
    path.write_bytes(b'not a pickle')
    with pytest.raises(DatasetError, match='not a readable pickle'):
        load_frame(path)


def test_csv_folder_with_column_mapping(tmp_path):
    names = ['acc_x', 'acc_y', 'acc_z', 'gx', 'gy', 'gz', 'mx', 'my', 'mz', 'pressure']
    for label in ('wood', 'carpet wool'):
        (tmp_path / label).mkdir()
        for trial in range(2):
            table = np.random.default_rng(trial).normal(size=(300, 10))
            header = ','.join(names)
            np.savetxt(tmp_path / label / f'{trial}.csv', table, delimiter=',', header=header,
                       comments='')
    mapping = parse_column_mapping('ax=acc_x, ay=acc_y, az=acc_z, baro=pressure')
    data = import_csv(tmp_path, rate_hz=350.0, window=100, hop=50, columns=mapping, **QUIET)
    assert data.classes == ['carpet wool', 'wood'] and data.X.shape == (20, 100, 10)
    with pytest.raises(DatasetError, match='missing column'):
        import_csv(tmp_path, rate_hz=350.0, window=100, hop=50, **QUIET)
    with pytest.raises(DatasetError, match='unknown channel'):
        import_csv(tmp_path, rate_hz=350.0, window=100, hop=50, columns={'accel': 'x'},
                   **QUIET)


def test_cli_import(tmp_path, capsys):
    write_mun(tmp_path / 'mun')
    assert main(['import', 'mun', str(tmp_path / 'mun'), '--out', str(tmp_path / 'm.npz'),
                 '--window', '350']) == 0
    assert 'wrote' in capsys.readouterr().out
    assert main(['import', 'csv', str(tmp_path), '--out', str(tmp_path / 'c.npz')]) == 1
