# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Ray sessions refuse what they cannot honour before anything starts."""

import re
import socket
import subprocess
import sys
import threading

import pytest

from tactex_common import cluster
from tactex_common.cluster import (
    AUTH_VARIABLES,
    check_reachable,
    HTTP2_GREETING,
    own_token_applies,
    ray_session,
)
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



def listener(answer: bytes | None):
    """A local TCP server that reads the greeting, then answers `answer` (None: nothing)."""
    server = socket.create_server(('127.0.0.1', 0))

    def serve():
        link, _ = server.accept()
        with link:
            link.recv(len(HTTP2_GREETING))
            if answer is not None:
                link.sendall(answer)
                return
            link.recv(1)  # silent until the client gives up
    threading.Thread(target=serve, daemon=True).start()
    return server, f'127.0.0.1:{server.getsockname()[1]}'


@pytest.mark.parametrize('answer, reason', [
    (b'HTTP/1.1 400 Bad Request\r\n\r\n', 'is not a Ray head'),  # a web server
    (b'SSH-2.0-OpenSSH_9.2\r\n', 'is not a Ray head'),
    (b'', 'is not a Ray head'),  # accepts and hangs up
    (None, 'no answer within 0.5 s')])  # accepts and says nothing
def test_an_address_where_another_program_listens_is_refused_within_the_timeout(answer,
                                                                                reason):
    server, address = listener(answer)
    with server, pytest.raises(ClusterError, match=reason):
        check_reachable(address, timeout_s=0.5)


def test_a_server_that_greets_with_http2_settings_passes_the_check():
    settings = bytes([0, 0, 0, 4, 0, 0, 0, 0, 0])  # an empty SETTINGS frame, as gRPC sends
    server, address = listener(settings)
    with server:
        check_reachable(address, timeout_s=5.0)


@pytest.fixture
def no_ray_auth(monkeypatch, tmp_path):
    """No token settings of the user's, and a home of the test's own."""
    for name in AUTH_VARIABLES:
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setenv('HOME', str(tmp_path))
    return tmp_path


SESSIONS = """
import os
from tactex_common.cluster import AUTH_VARIABLES, ray_session
for _ in range(2):  # the process's second instance too
    with ray_session(cpus=1):
        import ray
        assert os.environ['RAY_AUTH_MODE'] == 'token', os.environ.get('RAY_AUTH_MODE')
        print(os.environ['RAY_AUTH_TOKEN'], ray.get(ray.remote(lambda: 42).remote()))
    assert not any(name in os.environ for name in AUTH_VARIABLES)
"""


@pytest.mark.slow
def test_a_local_instance_runs_under_a_secret_token_that_nothing_writes_down(no_ray_auth):
    # a fresh interpreter: Ray reads its authentication settings when first imported
    done = subprocess.run([sys.executable, '-c', SESSIONS], capture_output=True, text=True,
                          timeout=300, check=False)
    assert done.returncode == 0, done.stderr[-2000:]
    lines = done.stdout.split('\n')
    assert re.fullmatch('[0-9a-f]{64} 42', lines[0]) and lines[1] == lines[0]
    assert 'Token authentication is enabled' not in done.stderr  # Ray's default's warning
    assert not (no_ray_auth / '.ray').exists()  # Ray's default: ~/.ray/auth_token


@pytest.mark.parametrize('address, setting, imported, applies', [
    (None, None, None, True),
    ('10.0.0.1:6379', None, None, False),  # a cluster's token is its own
    (None, ('RAY_AUTH_MODE', 'disabled'), None, False),  # the user's choice
    (None, ('RAY_AUTH_TOKEN_PATH', '/etc/ray/token'), None, False),
    (None, ('RAY_AUTH_MODE', ''), None, True),  # empty: unset
    (None, None, 'without it', False),  # Ray read its settings when imported
    (None, None, 'under it', True),
])
def test_the_own_token_is_for_a_local_instance_the_user_left_to_tactex(
        no_ray_auth, monkeypatch, address, setting, imported, applies):
    if setting:
        monkeypatch.setenv(*setting)
    if imported:
        monkeypatch.setitem(sys.modules, 'ray', object())
    else:
        monkeypatch.delitem(sys.modules, 'ray', raising=False)
    monkeypatch.setattr(cluster, '_own_token_imported_ray', imported == 'under it')
    assert own_token_applies(address) is applies
