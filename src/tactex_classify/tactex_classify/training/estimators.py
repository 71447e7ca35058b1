# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""One constructor for every classifier name: the eight deep models and the baselines."""

from __future__ import annotations

from collections.abc import Callable
import importlib
from pathlib import Path

from tactex_classify.models.registry import ALL_MODELS, BASELINES


def build_estimator(config, *, progress: Callable[[dict], None] | None = None,
                    device: str = 'cpu', state_file: Path | None = None):
    """A fresh, unfitted classifier for `config.model` (a `TrainingConfig`).

    Baselines take only the seed from the config; deep models take all of it, report
    each epoch to `progress`, train on `device` and keep their training state in
    `state_file` (if given) to resume from it.

    Raises:
        ValueError: an unknown model name.
    """
    from tactex_classify.models.checkpoint import KINDS
    from tactex_classify.training.deep_classifier import DeepClassifier
    if config.model in BASELINES:
        module, name = KINDS[config.model]
        return getattr(importlib.import_module(module), name)(seed=config.seed)
    if config.model not in ALL_MODELS:
        raise ValueError(f'unknown model {config.model!r}; known: {", ".join(ALL_MODELS)}')
    return DeepClassifier(config, progress=progress, device=device, state_file=state_file)
