# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What watching costs the nodes: teensy_node's latency at 350 Hz with observers beside it.

The latency is bench_sensor_node's (frame written to the emulator's pty -> Imu received,
p50/p99 over the last 9 s of 12). It is measured, in one run on the same machine, with
nothing beside the node (the reference, at the start and again at the end, to show the
run's own spread), with the Foxglove live view (`tactex view`) and a WebSocket client
subscribed to every channel, and with `tactex status` and `tactex watch` running.
Prints each p99 and its ratio to the reference's; the targets: the view adds under 1 ms
to the p99, status and watch nothing beyond the spread.
"""

from __future__ import annotations

import asyncio
from contextlib import contextmanager
import json
from pathlib import Path
import socket
import subprocess
import sys
import tempfile
import threading
import time

from bench_sensor_node import node_latencies, RATE_HZ
import numpy as np

from tactex.launching.environment import ros_environment

BIN = Path(sys.executable).parent


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
    """`tactex view` and a WebSocket client subscribed to every channel (counts messages)."""
    import websockets
    port = free_port()
    done = threading.Event()

    async def client() -> None:
        for _ in range(50):  # the server starts beside us
            try:
                connection = await websockets.connect(f'ws://127.0.0.1:{port}',
                                                      subprotocols=['foxglove.sdk.v1'])
                break
            except OSError:
                await asyncio.sleep(0.2)
        async with connection:
            channels = []
            while not channels:
                message = json.loads(await connection.recv())
                channels = message.get('channels', []) if message['op'] == 'advertise' else []
            await connection.send(json.dumps({'op': 'subscribe', 'subscriptions': [
                {'id': c['id'], 'channelId': c['id']} for c in channels]}))
            while not done.is_set():
                try:
                    data = await asyncio.wait_for(connection.recv(), 0.2)
                except TimeoutError:
                    continue
                received[0] += isinstance(data, bytes)

    thread = threading.Thread(target=lambda: asyncio.run(client()), daemon=True)
    with processes([str(BIN / 'tactex'), 'view', '--port', str(port)]):
        thread.start()
        time.sleep(1.0)
        yield
        done.set()
        thread.join(timeout=5)


def main() -> None:
    """Measure each condition in turn and print one table."""
    received = [0]
    conditions = [
        ('nothing beside (reference)', lambda: processes()),
        ('tactex view + a subscribed client', lambda: live_view(received)),
        ('tactex status + tactex watch',
         lambda: processes([str(BIN / 'tactex'), 'status', '--duration', '3600'],
                           [str(BIN / 'tactex'), 'watch'])),
        ('nothing beside (again, the spread)', lambda: processes())]
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for index, (label, beside) in enumerate(conditions):
            latencies, frames, messages = node_latencies(Path(folder) / f'teensy{index}',
                                                         beside)
            rows.append((label, latencies, frames, messages))
    reference = np.percentile(rows[0][1], 99)
    print(f'teensy_node at {RATE_HZ:.0f} Hz, frame written -> Imu received, last 9 s of 12 '
          f"per condition; the view's client received {received[0]} messages")
    print(f'{"beside the node":<38}{"p50 ms":>8}{"p99 ms":>8}{"p99 / ref":>10}{"+p99 ms":>9}')
    for label, latencies, _frames, _messages in rows:
        p99 = np.percentile(latencies, 99)
        print(f'{label:<38}{np.percentile(latencies, 50):>8.3f}{p99:>8.3f}'
              f'{p99 / reference:>9.2f}x{p99 - reference:>+9.3f}')
    view_added = np.percentile(rows[1][1], 99) - reference
    print(f'the view adds {view_added:+.3f} ms to the p99 (target < 1 ms: '
          f'{"met" if view_added < 1.0 else "NOT met"})')


if __name__ == '__main__':
    main()
