# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`make demo`'s job: every slice's figure meets its stated threshold, or the demo fails."""

import math
import re

import pytest

from tactex.cli import main
from tactex.commands import demo

SUMMARY = re.compile(r'^  (slice \d): (.+?) (\S+) (\S+) \(threshold (<=|>=) (\S+) \S+\): '
                     r'(PASS|FAIL)$', re.MULTILINE)


@pytest.mark.slow
def test_demo_runs_every_slice_and_each_figure_meets_its_threshold(capsys):
    assert main(['demo', '--points', '2']) == 0  # the data slices as make demo runs them
    out = capsys.readouterr().out
    assert all(f'slice {k}/5' in out for k in (1, 2, 3, 4))
    assert 'Not yet in the demo' in out
    figures = {figure: (float(value), bound, float(limit))
               for _, figure, value, _, bound, limit, _ in SUMMARY.findall(out)}
    # Read from the printed figures, not only the exit code: each against its constant.
    assert figures['worst tracking error'][1:] == ('<=', demo.TRACKING_LIMIT_MM)
    assert figures['worst tracking error'][0] <= demo.TRACKING_LIMIT_MM
    assert figures['roll error'][1:] == ('<=', demo.ROLL_LIMIT_DEG)
    assert figures['roll error'][0] <= demo.ROLL_LIMIT_DEG
    assert figures['frames decoded'][0] >= demo.MIN_DECODED_FRAMES
    assert figures['grouped accuracy'][1:] == ('>=', 100 * demo.ACCURACY_FLOOR)
    assert figures['grouped accuracy'][0] >= 100 * demo.ACCURACY_FLOOR

@pytest.mark.parametrize('value', [3.0, math.nan])
def test_a_missed_threshold_fails_the_demo_and_names_the_slice(monkeypatch, capsys, value):
    passing = demo.Check('slice 1', 'worst tracking error', 0.5, demo.TRACKING_LIMIT_MM, 'mm')
    monkeypatch.setattr(demo, '_description_slice', lambda points, settle_s: [passing])
    monkeypatch.setattr(demo, '_sensor_slice', lambda: [demo.Check(
        'slice 2', 'roll error', value, demo.ROLL_LIMIT_DEG, 'deg')])
    monkeypatch.setattr(demo, '_data_and_classification_slices', lambda sweeps: [])
    assert main(['demo']) == 1
    captured = capsys.readouterr()
    assert 'slice 1: worst tracking error 0.5 mm (threshold <= 2 mm): PASS' in captured.out
    assert re.search(r'error: slice 2 missed its threshold: slice 2: roll error \S+ deg '
                     r'\(threshold <= 1 deg\): FAIL', captured.err)
