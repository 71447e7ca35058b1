# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""A recording's recording/metadata JSON: parsed, and its label and trial checked."""

from __future__ import annotations

from collections.abc import Mapping
import json
from pathlib import Path

from tactex_classify.errors import BagError


def parse_metadata(text: str, path: Path) -> dict:
    """The recording/metadata JSON object of a recording at `path`."""
    try:
        value = json.loads(text)
    except json.JSONDecodeError as err:
        raise BagError(f'{path}: recording/metadata is not JSON: {err}') from None
    if not isinstance(value, dict):
        raise BagError(f'{path}: recording/metadata must be a JSON object')
    return value


def check_metadata(metadata: Mapping, path: Path) -> dict:
    """The recording's metadata with `label` text and `trial` an integer, if present.

    Raises:
        BagError: naming the bag and the key whose value has the wrong type.
    """
    metadata = dict(metadata)
    label = metadata.get('label')
    if label is not None and (not isinstance(label, str) or not label.strip()):
        raise BagError(f'{path}: metadata key "label" must be non-empty text, got {label!r}')
    trial = metadata.get('trial')
    if trial is not None:
        if isinstance(trial, float) and trial.is_integer():
            trial = int(trial)
        if isinstance(trial, bool) or not isinstance(trial, int) or trial < 0:
            raise BagError(f'{path}: metadata key "trial" must be an integer >= 0, got '
                           f'{metadata["trial"]!r}')
        metadata['trial'] = trial
    return metadata
