# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The models: one registry of names, the architectures, the baselines, checkpoints.

- `registry`: every model's name (the one list), importable without torch.
- `architectures`: the original's eight deep models in PyTorch.
- `baselines`: MiniRocket + ridge and statistics + ExtraTrees.
- `windows`: what every model shares about windows (checks, channel scaling, softmax).
- `checkpoint`: the saved form of a fitted model and its safe loading.
"""

from tactex_classify.exports import lazy_exports

_EXPORTS = {'ALL_MODELS': 'registry', 'BASELINES': 'registry', 'DEEP_MODELS': 'registry',
            'build_model': 'architectures', 'MiniRocketRidge': 'baselines',
            'StatsExtraTrees': 'baselines', 'ChannelScaler': 'windows',
            'load_checkpoint': 'checkpoint', 'save_checkpoint': 'checkpoint',
            'Deployable': 'checkpoint', 'StreamSpec': 'checkpoint'}
__all__ = sorted(_EXPORTS)
__getattr__ = lazy_exports(__name__, _EXPORTS)
