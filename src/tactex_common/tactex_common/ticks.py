# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Pauses of a goal's coroutine on one thread: the node's callbacks run while it waits.

An action whose goal waits on other callbacks (samples, another action's answers) runs
its execute callback as a coroutine on the node's single-threaded executor
(`tactex_common.ros.spin`); each `await ticks.pause()` lets the executor handle whatever
arrived until the next tick of a steady-clock timer, which runs only while started.
"""

from __future__ import annotations

from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from rclpy.task import Future


class Ticks:
    """A steady-clock timer of `period_s` whose ticks end the pauses waiting on it."""

    def __init__(self, node: Node, period_s: float) -> None:
        self._waiting: list[Future] = []
        self._timer = node.create_timer(period_s, self._on_tick, autostart=False,
                                        clock=Clock(clock_type=ClockType.STEADY_TIME))

    def start(self) -> None:
        """Tick from now on (while a goal runs)."""
        self._timer.reset()

    def stop(self) -> None:
        """Stop ticking (no goal runs)."""
        self._timer.cancel()

    def _on_tick(self) -> None:
        waiting, self._waiting = self._waiting, []
        for future in waiting:
            future.set_result(None)

    async def pause(self) -> None:
        """Let the node's callbacks run until the next tick."""
        future = Future()
        self._waiting.append(future)
        await future
