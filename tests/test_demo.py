# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`make demo`'s job runs end to end and says honestly which slices it covers."""

import pytest

from tactex.cli import main

pytestmark = pytest.mark.slow


def test_demo_runs_every_slice_it_has(capsys):
    assert main(['demo', '--points', '2', '--settle-s', '0.5', '--sweeps', '3']) == 0
    out = capsys.readouterr().out
    assert all(f'slice {k}/5' in out for k in (1, 2, 3, 4))
    assert 'Not yet in the demo' in out
    assert 'estimated roll' in out and 'accuracy' in out
