# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What the result sections share: the kept outputs in bench/results/ and reading numbers."""

import json
from pathlib import Path
import re

RESULTS = Path(__file__).resolve().parent / 'results'
# bench/results/ as a page one folder below docs/ sees it (docs/results links there).
FIGURES = '../results'
TEXTURE_MODELS = {'extratrees': 'statistics + ExtraTrees', 'minirocket': 'MiniRocket + ridge'}
DEVICE_NOTE = ('a device in brackets: the point trained there, not on one core of the CPU, '
               "its seconds that device's")


def device_mark(point: dict) -> str:
    """' (cuda)' for a kept point trained on a GPU (its seconds are not a core's), or ''."""
    device = point.get('device', 'cpu')
    return '' if device == 'cpu' else f' ({device})'


def kept_text(name: str) -> str:
    """A kept output's text."""
    return (RESULTS / name).read_text(encoding='utf-8')


def kept_json(name: str):
    """A kept JSON output."""
    return json.loads(kept_text(name))


def numbers_in(line: str) -> list[float]:
    """The numbers of a line of a kept text output, in order."""
    return [float(v) for v in re.findall(r'(?<![\w.])-?\d+(?:\.\d+)?(?:e[-+]?\d+)?', line)]


def line_starting(text: str, start: str) -> str:
    """The first line of `text` that starts with `start`."""
    return next(line for line in text.splitlines() if line.startswith(start))
