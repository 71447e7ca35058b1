# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Training: the deep models' loop (`deep_classifier`) and one constructor for every model."""

from tactex_classify.exports import lazy_exports

_EXPORTS = {'TrainingConfig': 'deep_classifier', 'DeepClassifier': 'deep_classifier',
            'build_estimator': 'estimators'}
__all__ = sorted(_EXPORTS)
__getattr__ = lazy_exports(__name__, _EXPORTS)
