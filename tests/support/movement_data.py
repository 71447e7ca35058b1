# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""A small dataset of three textures under three movements, and its movement file.

`tells_all` separates every texture (an offset on channel 0 that grows with the
texture), `tells_wood` only wood from the others, `tells_nothing` none: what active
identification must tell apart, in seconds for a test.
"""

from pathlib import Path

import numpy as np

from tactex_classify.data.dataset import Dataset

TEXTURES = ['felt', 'cork', 'wood']
MOVEMENTS = {'tells_all': lambda texture: 3.0 * texture,
             'tells_wood': lambda texture: 3.0 * (texture == 2),
             'tells_nothing': lambda texture: 0.0}
RECORDINGS, WINDOWS, WINDOW = 4, 3, 32


def movement_file(folder: Path, contact_s=(2.0, 1.0, 1.0)) -> Path:
    """folder/movements.yaml listing the three movements (contact seconds as given)."""
    rows = ''.join(f'  - {{name: {name}, speed: 0.02, press_depth: 0.002, edge_tilt: 0.5, '
                   f'direction: forward, contact_length: {0.02 * seconds}}}\n'
                   for name, seconds in zip(MOVEMENTS, contact_s, strict=True))
    path = folder / 'movements.yaml'
    path.write_text(f'window: {WINDOW}\nmovements:\n{rows}')
    return path


def movement_dataset(folder: Path, named: bool = True) -> Dataset:
    """RECORDINGS recordings of each texture under each movement, saved in folder, loaded."""
    rng = np.random.default_rng(0)
    X, y, trial, rows = [], [], [], []
    for movement, offset in MOVEMENTS.items():
        for texture in range(len(TEXTURES)):
            for _ in range(RECORDINGS):
                number = len(rows)
                windows = rng.normal(size=(WINDOWS, WINDOW, 10))
                windows[:, :, 0] += offset(texture)
                X.append(windows)
                y += [texture] * WINDOWS
                trial += [number] * WINDOWS
                rows.append({'trial': number, 'label': TEXTURES[texture], 'samples': 300,
                             'rate_hz': 120.0, **({'movement': movement} if named else {})})
    data = Dataset(np.concatenate(X).astype(np.float32), np.array(y), np.array(trial),
                   np.zeros(len(y)), TEXTURES, {'recordings': rows, 'sampling_rate_hz': 120.0,
                                                'hop': WINDOW // 2})
    return Dataset.load(data.save(folder / ('data.npz' if named else 'unnamed.npz')))
