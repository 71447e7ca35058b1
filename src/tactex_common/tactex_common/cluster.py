# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Independent jobs as Ray tasks: on a local instance sized to a core budget, or a cluster.

`ray_session` starts a Ray instance of this machine (`address=None`: never one that
another program started here; `cpus` caps the cores it may use, default the cores Ray
detects) or joins a cluster by address, and shuts it down (or leaves it) on exit.
`run_tasks` submits one task per job with its CPU/GPU request and hands each result to
the caller in the order they finish, in the calling process: whatever node ran a job,
its result lands where the caller puts it. Ray is imported only here, only when used.
A cluster's address is tried first (`check_reachable`): a connection, then the HTTP/2
greeting every gRPC server (Ray's head and its client server) answers with its settings.
Ray's own client waits minutes, deaf to signals, for a head that is not there or for an
answer from a program that is not Ray.

Ray 2.60's servers listen on every network interface and cannot be told otherwise, so a
local instance gets a token of its own (Ray's token authentication): a secret drawn once
per process, in the environment the instance's processes inherit, which nothing else
holds and nothing writes down (Ray's default keeps one in ~/.ray/auth_token, readable
by every user of the machine). A process whose Ray was imported before without that
token (measured: its next local instance then fails to start), or a user who set
RAY_AUTH_MODE, RAY_AUTH_TOKEN or RAY_AUTH_TOKEN_PATH, keeps Ray's own way.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
import functools
import os
import secrets
import socket
import sys
from typing import Any

from tactex_common.environment import environment_set
from tactex_common.errors import ClusterError

CONNECT_TIMEOUT_S = 10.0
# Where Ray reads its token authentication settings; any of them set is the user's choice.
AUTH_VARIABLES = ('RAY_AUTH_MODE', 'RAY_AUTH_TOKEN', 'RAY_AUTH_TOKEN_PATH')
# The HTTP/2 client preface and an empty SETTINGS frame (RFC 9113, 3.4 and 6.5); a gRPC
# server answers with a frame header whose type byte (the fourth) is SETTINGS, 0x4.
HTTP2_GREETING = b'PRI * HTTP/2.0\r\n\r\nSM\r\n\r\n' + bytes([0, 0, 0, 4, 0, 0, 0, 0, 0])
HTTP2_SETTINGS = 4
FRAME_HEADER_BYTES = 9


@dataclass(frozen=True)
class Resources:
    """What one task asks the scheduler for."""

    cpus: float = 1.0
    gpus: float = 0.0


def own_token_applies(address: str | None) -> bool:
    """Whether a session gets this process's token: a local instance, the user's choice unset.

    Only where Ray was not imported yet or was imported under the token: a Ray imported
    without it did not start an instance under a token set later (see the module's text).
    An empty variable counts as unset.
    """
    return address is None and not any(os.environ.get(name) for name in AUTH_VARIABLES) \
        and ('ray' not in sys.modules or _own_token_imported_ray)


# Whether this process imported Ray with its own token set (so later sessions keep it).
_own_token_imported_ray = False


@functools.cache
def process_token() -> str:
    """This process's secret for its local Ray instances (Ray's client caches the first)."""
    return secrets.token_hex(32)


@contextmanager
def ray_session(*, address: str | None = None, cpus: int | None = None) -> Iterator[dict]:
    """A Ray connection for the block; yields the cluster's resources (CPU, GPU, ...).

    Args:
        address: a cluster to join (`ray start --head` prints it); None starts a local
            instance that ends with the block.
        cpus: most cores the local instance may use (default: the cores Ray detects);
            a cluster's nodes declare their own, so it must be None with `address`.

    Raises:
        ClusterError: `cpus` given with `address`, or the cluster cannot be reached.
    """
    if address is not None and cpus is not None:
        raise ClusterError('the cores of a cluster are set where its nodes start (ray start '
                           '--num-cpus); give no core cap with an address')
    if address is not None:
        check_reachable(address)
    os.environ.setdefault('RAY_USAGE_STATS_ENABLED', '0')  # never phone home
    token = {'RAY_AUTH_MODE': 'token', 'RAY_AUTH_TOKEN': process_token()} \
        if own_token_applies(address) else {}
    global _own_token_imported_ray
    _own_token_imported_ray = _own_token_imported_ray or bool(token)
    options = {'include_dashboard': False, 'log_to_driver': False,
               'logging_level': 'WARNING', 'configure_logging': True}
    with environment_set(token):  # before Ray is imported
        import ray
        try:
            if address is None:
                ray.init(address='local', num_cpus=cpus, **options)
            else:
                ray.init(address=address, **options)
        except (ConnectionError, RuntimeError, ValueError) as err:
            reason = (str(err).strip().splitlines() or [type(err).__name__])[0]
            raise ClusterError(f'cannot start or reach Ray at {address or "a local instance"}'
                               f': {reason}') from None
        try:
            yield dict(ray.cluster_resources())
        finally:
            ray.shutdown()


def check_reachable(address: str, timeout_s: float = CONNECT_TIMEOUT_S) -> None:
    """Refuse a cluster address (HOST:PORT or ray://HOST:PORT) where no gRPC server answers.

    Raises:
        ClusterError: the connection is refused, unroutable or not accepted within
            `timeout_s`, or what answers there does not speak HTTP/2 (not a Ray head).
    """
    host, _, port = address.removeprefix('ray://').rpartition(':')
    hint = 'start the head with `ray start --head` and give the address it prints'
    try:
        with socket.create_connection((host.strip('[]'), int(port)), timeout=timeout_s) as link:
            link.settimeout(timeout_s)
            link.sendall(HTTP2_GREETING)
            header = _read_up_to(link, FRAME_HEADER_BYTES)
    except (OSError, ValueError) as err:
        reason = (f'no answer within {timeout_s:g} s' if isinstance(err, TimeoutError)
                  else getattr(err, 'strerror', None) or str(err))
        raise ClusterError(f'cannot reach Ray at {address}: {reason}; {hint}') from None
    if len(header) < FRAME_HEADER_BYTES or header[3] != HTTP2_SETTINGS:
        raise ClusterError(f'what answers at {address} is not a Ray head (no gRPC greeting); '
                           f'{hint}')


def _read_up_to(link: socket.socket, size: int) -> bytes:
    """Up to `size` bytes from `link`: fewer when the other side closes first."""
    received = b''
    while len(received) < size:
        chunk = link.recv(size - len(received))
        if not chunk:
            break
        received += chunk
    return received


def run_tasks(function: Callable[..., Any], jobs: Sequence[tuple], *,
              resources: Callable[[int], Resources] | Resources = Resources(),
              on_result: Callable[[int, Any], None], shared: Sequence[Any] = (),
              max_in_flight: int | None = None) -> None:
    """Run `function(*shared, *jobs[i])` as one Ray task per job, inside `ray_session`.

    Args:
        function: a module-level function (Ray ships it by reference to the workers).
        jobs: the per-task arguments.
        resources: one request for all, or a function of the job's index.
        on_result: called with (index, result) in the calling process as tasks finish.
        shared: large arguments common to every task, put in the object store once.
        max_in_flight: most tasks submitted at a time (default: all at once; Ray queues
            them until a worker is free).

    A task's exception is raised here (as its own type); tasks still queued are cancelled.
    """
    import ray
    remote = ray.remote(function)
    shared_refs = [ray.put(value) for value in shared]
    queue = list(range(len(jobs)))[::-1]
    pending: dict = {}
    limit = max_in_flight or len(jobs)
    try:
        while queue or pending:
            while queue and len(pending) < limit:
                index = queue.pop()
                need = resources(index) if callable(resources) else resources
                ref = remote.options(num_cpus=need.cpus, num_gpus=need.gpus).remote(
                    *shared_refs, *jobs[index])
                pending[ref] = index
            done, _ = ray.wait(list(pending), num_returns=1)
            for ref in done:
                on_result(pending.pop(ref), ray.get(ref))
    finally:
        for ref in pending:
            ray.cancel(ref, force=True)
