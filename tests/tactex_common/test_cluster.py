# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Ray sessions refuse what they cannot honour before anything starts."""

import pytest

from tactex_common.cluster import ray_session
from tactex_common.errors import ClusterError


def test_a_core_cap_with_a_cluster_address_is_refused_before_ray_starts():
    with pytest.raises(ClusterError, match='give no core cap with an address'):
        with ray_session(address='10.0.0.1:6379', cpus=2):
            pass
