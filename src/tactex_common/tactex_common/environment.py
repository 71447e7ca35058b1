# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Environment variables set for a block (child processes inherit them), then restored."""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from contextlib import contextmanager
import os


@contextmanager
def environment_set(variables: Mapping[str, str]) -> Iterator[None]:
    """Set `variables` in this process's environment for the block; restore them after.

    A variable that was unset before is removed again, one that had a value gets it back,
    also when the block raises.
    """
    before = {name: os.environ.get(name) for name in variables}
    os.environ.update(variables)
    try:
        yield
    finally:
        for name, value in before.items():
            if value is None:
                os.environ.pop(name, None)
            else:
                os.environ[name] = value
