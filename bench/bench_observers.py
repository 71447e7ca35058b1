# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What watching costs the nodes: teensy_node's latency at 350 Hz with observers beside it.

The latency is bench_sensor_node's (frame written to the emulator's pty -> Imu received,
p50/p99 over the last 9 s of 12). It is measured, in one run on the same machine, with
nothing beside the node (the reference), with the Foxglove live view (`tactex view`)
and a WebSocket client subscribed to every channel, and with `tactex status` and
`tactex watch` running.
Three rounds, the conditions interleaved (a p99 of 9 s moves by tenths of a ms from run
to run on 2 shared cores); prints each condition's median p99, its range and its ratio
to the reference's. Targets: the view adds under 1 ms to the p99, status and watch
nothing beyond the reference's own spread.
"""

from __future__ import annotations

import asyncio
from contextlib import contextmanager
from pathlib import Path
import socket
import subprocess
import sys
import tempfile
import time

from bench_sensor_node import node_latencies, RATE_HZ
import numpy as np

from tactex.launching.environment import ros_environment

BIN = Path(sys.executable).parent
ROUNDS = 3


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(('127.0.0.1', 0))
        return probe.getsockname()[1]


@contextmanager
def processes(*argvs: list[str]):
    """Run the commands for the block (their output discarded); stop them after."""
    running = [subprocess.Popen(argv, env=ros_environment(), stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL) for argv in argvs]
    try:
        time.sleep(3.0)  # discovery and start-up before the stream
        yield
    finally:
        for process in running:
            process.terminate()
            process.wait(timeout=10)


@contextmanager
def live_view(received: list[int]):
    """`tactex view` and a WebSocket client (a process of its own) subscribed to everything."""
    port = free_port()
    with processes([str(BIN / 'tactex'), 'view', '--port', str(port)]):
        listener = subprocess.Popen([sys.executable, __file__, '--client', str(port)],
                                    stdout=subprocess.PIPE, text=True)
        time.sleep(1.0)
        yield
        received[0] = int(listener.communicate(timeout=60)[0].split()[-1])


def main() -> None:
    """Measure each condition ROUNDS times, interleaved, and print one table."""
    received = [0]
    conditions = {
        'nothing beside (reference)': lambda: processes(),
        'tactex view + a subscribed client': lambda: live_view(received),
        'tactex status + tactex watch': lambda: processes(
            [str(BIN / 'tactex'), 'status', '--duration', '3600'], [str(BIN / 'tactex'), 'watch'])}
    p50: dict[str, list[float]] = {label: [] for label in conditions}
    p99: dict[str, list[float]] = {label: [] for label in conditions}
    with tempfile.TemporaryDirectory() as folder:
        for round_ in range(ROUNDS):
            for index, (label, beside) in enumerate(conditions.items()):
                latencies, _frames, _messages = node_latencies(
                    Path(folder) / f'teensy{round_}_{index}', beside)
                p50[label].append(float(np.percentile(latencies, 50)))
                p99[label].append(float(np.percentile(latencies, 99)))
    reference = float(np.median(p99['nothing beside (reference)']))
    print(f'teensy_node at {RATE_HZ:.0f} Hz, frame written -> Imu received, last 9 s of 12 '
          f'per run; {ROUNDS} rounds, conditions interleaved; medians over the rounds; the '
          f"view's client received {received[0]} messages in its last run")
    print(f'{"beside the node":<36}{"p50 ms":>8}{"p99 ms":>8}{"p99 range ms":>15}'
          f'{"p99 / ref":>10}{"+p99 ms":>9}')
    for label in conditions:
        median = float(np.median(p99[label]))
        print(f'{label:<36}{np.median(p50[label]):>8.3f}{median:>8.3f}'
              f'{min(p99[label]):>8.2f}-{max(p99[label]):<6.2f}{median / reference:>9.2f}x'
              f'{median - reference:>+9.3f}')
    added = float(np.median(p99['tactex view + a subscribed client'])) - reference
    spread = max(p99['nothing beside (reference)']) - min(p99['nothing beside (reference)'])
    print(f'the view adds {added:+.3f} ms to the median p99 (target < 1 ms: '
          f'{"met" if added < 1.0 else "NOT met"}); the reference p99 itself spans '
          f'{spread:.3f} ms across the rounds')


if __name__ == '__main__':
    if sys.argv[1:2] == ['--client']:  # the view's client, in a process of its own
        sys.path.insert(0, str(Path(__file__).resolve().parents[1] / 'tests'))
        from support.foxglove_client import subscribe_all
        print(len(asyncio.run(subscribe_all(int(sys.argv[2]), 14.0))[1]))
    else:
        main()
