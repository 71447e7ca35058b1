# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""A Foxglove WebSocket client for the live view's tests and benchmark.

It speaks the `foxglove.sdk.v1` subprotocol as Foxglove does: waits for the channels to be
advertised, subscribes to each, and collects the binary messageData frames (opcode 1:
subscription id, log time, payload).
"""

from __future__ import annotations

import asyncio
from collections.abc import Callable
import json
import time

MESSAGE_DATA = 1  # opcode of a binary messageData frame
PAYLOAD_AT = 13  # opcode (1) + subscription id (4) + log time (8)


async def subscribe_all(port: int, seconds: float, *, channels_expected: int = 1,
                        ready: Callable[[], None] | None = None
                        ) -> tuple[dict[str, dict], list[tuple[dict, bytes]]]:
    """Subscribe to every channel of the server on `port`; collect for `seconds`.

    Args:
        port: the server's port on localhost (retried for 10 s while it starts).
        seconds: how long to collect after subscribing.
        channels_expected: advertised channels to wait for before subscribing.
        ready: called once subscribed (to publish what the test expects to see).

    Returns:
        The advertised channels by topic, and each (channel, payload) received in order.
    """
    import websockets

    for attempt in range(50):
        try:
            connection = await websockets.connect(f'ws://127.0.0.1:{port}',
                                                  subprotocols=['foxglove.sdk.v1'])
            break
        except OSError:
            if attempt == 49:
                raise
            await asyncio.sleep(0.2)
    async with connection:
        channels: dict[str, dict] = {}
        while len(channels) < channels_expected:
            message = json.loads(await asyncio.wait_for(connection.recv(), 10))
            if message['op'] == 'advertise':
                channels.update({c['topic']: c for c in message['channels']})
        by_id = {c['id']: c for c in channels.values()}
        await connection.send(json.dumps({'op': 'subscribe', 'subscriptions': [
            {'id': c['id'], 'channelId': c['id']} for c in channels.values()]}))
        if ready is not None:
            await asyncio.sleep(0.5)  # the server takes the subscription
            ready()
        received: list[tuple[dict, bytes]] = []
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            try:
                data = await asyncio.wait_for(connection.recv(), 0.2)
            except TimeoutError:
                continue
            if isinstance(data, bytes) and data[0] == MESSAGE_DATA:
                received.append((by_id[int.from_bytes(data[1:5], 'little')],
                                 data[PAYLOAD_AT:]))
    return channels, received
