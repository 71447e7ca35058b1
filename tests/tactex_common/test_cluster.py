# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Ray sessions refuse what they cannot honour before anything starts."""

import socket
import sys
import threading

import pytest

from tactex_common.cluster import check_reachable, HTTP2_GREETING, ray_session
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
