# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`make demo`'s job runs end to end and says honestly which slices it covers."""

import pytest

from tactex.cli import main

pytestmark = pytest.mark.slow


def test_demo_runs_both_slices(capsys):
    assert main(['demo', '--points', '2', '--settle-s', '0.5']) == 0
    out = capsys.readouterr().out
    assert 'slice 1/5' in out and 'slice 2/5' in out
    assert 'Not yet in the demo' in out
    assert 'estimated roll' in out
