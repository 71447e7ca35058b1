# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Load a script of the repository (bench/, tools/) as a module, for the tests that check it."""

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def load_script(relative: str):
    """The module of the script at ROOT / `relative`, executed."""
    path = ROOT / relative
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
