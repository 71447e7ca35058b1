# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Evaluation: cross-validation (grouped and leaky), the model grid, and their reports.

- `cross_validation`: folds by recording or by window, metrics, whole-recording decisions.
- `training_report`: a `tactex train` run's metrics.json, report.md and plots.
- `model_grid`: `tactex compare`'s resumable grid of models x datasets x seeds.
- `grid_report`: the grid's summary table and plots.
"""

from tactex_classify.exports import lazy_exports

_EXPORTS = {'cross_validate': 'cross_validation', 'splits': 'cross_validation',
            'confusion': 'cross_validation', 'metrics': 'cross_validation',
            'CrossValidation': 'cross_validation', 'run_grid': 'model_grid',
            'GridSettings': 'model_grid'}
__all__ = sorted(_EXPORTS)
__getattr__ = lazy_exports(__name__, _EXPORTS)
