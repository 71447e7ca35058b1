# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Public names of a subpackage, imported from their module on first use (PEP 562).

A subpackage's `__init__` lists its public API in `__all__` without importing torch,
scikit-learn or rclpy until a name that needs them is used.
"""

from __future__ import annotations

from collections.abc import Callable
import importlib
from typing import Any


def lazy_exports(package: str, exports: dict[str, str]) -> Callable[[str], Any]:
    """A module `__getattr__` giving `name` from `package.exports[name]` on first use."""
    def attribute(name: str) -> Any:
        if name not in exports:
            raise AttributeError(f'module {package!r} has no attribute {name!r}')
        return getattr(importlib.import_module(f'{package}.{exports[name]}'), name)
    return attribute
