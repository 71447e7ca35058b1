# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Ray sessions refuse what they cannot honour before anything starts."""

import sys

import pytest

from tactex_common.cluster import ray_session
from tactex_common.errors import ClusterError


def test_a_core_cap_with_a_cluster_address_is_refused_before_ray_starts():
    with pytest.raises(ClusterError, match='give no core cap with an address'):
        with ray_session(address='10.0.0.1:6379', cpus=2):
            pass


def test_an_address_nothing_answers_at_is_refused_before_ray_starts():
    with pytest.raises(ClusterError, match='cannot reach Ray at 127.0.0.1:1: Connection '
                                           'refused; start the head with `ray start --head`'):
        with ray_session(address='127.0.0.1:1'):
            pass
    assert 'ray' not in sys.modules

