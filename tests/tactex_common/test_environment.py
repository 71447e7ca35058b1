# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Variables set for a block are restored after it, also when it raises."""

import os

import pytest

from tactex_common.environment import environment_set


def test_a_variable_unset_before_is_removed_and_one_set_gets_its_value_back(monkeypatch):
    monkeypatch.delenv('TACTEX_TEST_NEW', raising=False)
    monkeypatch.setenv('TACTEX_TEST_OLD', 'mine')
    with pytest.raises(RuntimeError):
        with environment_set({'TACTEX_TEST_NEW': 'a', 'TACTEX_TEST_OLD': 'b'}):
            assert os.environ['TACTEX_TEST_NEW'] == 'a' and os.environ['TACTEX_TEST_OLD'] == 'b'
            raise RuntimeError
    assert 'TACTEX_TEST_NEW' not in os.environ and os.environ['TACTEX_TEST_OLD'] == 'mine'
