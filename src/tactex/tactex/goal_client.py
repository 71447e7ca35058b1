# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""One action goal from the command line: the server, a progress bar, cancel on Ctrl-C.

`tactex probe`, `tactex sweep` and `tactex identify` send their goal through `send_goal` as
`ros2 action send_goal --feedback` would: it waits for the server (an error naming the
namespace when none answers), sends the goal again while the node refuses it (nodes
refuse until the arm and sensor are heard), shows the feedback as a tqdm bar on stderr,
and on a stop signal cancels the goal, waits for the node to finish it (the node lifts
the sensor off first) and raises the signal on. A goal still running after `--timeout` is
canceled the same way; the error says how it really ended.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
import sys
import threading
import time

from action_msgs.msg import GoalStatus
from action_msgs.srv import CancelGoal
from rclpy.executors import SingleThreadedExecutor
from tqdm import tqdm

from tactex.errors import CommandError
from tactex_common.goals import GoalSender
from tactex_common.stopping import Stopped

# Seconds to wait for a goal's answer before sending it again (tactex_common.goals).
ANSWER_S = 5.0
# Seconds a node may take to finish a canceled goal (the sensor is lifted off first).
CANCEL_S = 30.0
POLL_S = 0.1
STATUS_NAMES = {GoalStatus.STATUS_SUCCEEDED: 'succeeded', GoalStatus.STATUS_CANCELED:
                'canceled', GoalStatus.STATUS_ABORTED: 'aborted'}


@dataclass(frozen=True)
class Progress:
    """What the bar shows of one feedback message: done of total, and a short state."""

    done: float
    total: float
    state: str


@contextmanager
def spinning(executor: SingleThreadedExecutor) -> Iterator[None]:
    """Spin `executor` in a thread for the block (goal answers arrive meanwhile)."""
    thread = threading.Thread(target=executor.spin, daemon=True)
    thread.start()
    try:
        yield
    finally:
        executor.shutdown(timeout_sec=2.0)
        thread.join(timeout=5.0)


def wait_until(condition: Callable[[], bool], timeout_s: float) -> bool:
    """Poll `condition` until it holds (True) or `timeout_s` passes (False)."""
    deadline = time.monotonic() + timeout_s
    while not condition():
        if time.monotonic() > deadline:
            return False
        time.sleep(POLL_S / 2)
    return True


def accepted_handle(sender: GoalSender, goal, timeout_s: float, what: str,
                    alive: Callable[[], bool] = lambda: True, feedback=None):
    """Send `goal` (again while refused or unanswered) until accepted; its goal handle.

    CommandError naming `what` when it was not answered, or still refused, after
    `timeout_s`, or when `alive()` turned false.
    """
    deadline = time.monotonic() + timeout_s
    refused = False
    while True:
        handle = sender.answer(goal, feedback, answer_s=ANSWER_S,
                               timeout_s=max(0.0, deadline - time.monotonic()), alive=alive)
        if handle is not None and handle.accepted:
            return handle
        if not alive():
            raise CommandError(f'{what}: a node stopped; the node logs say why')
        refused = refused or handle is not None
        if time.monotonic() > deadline:
            if refused:
                raise CommandError(
                    f'{what}: the goal was refused for {timeout_s:g} s (a goal is running, or '
                    'the node has not heard the arm and the sensor: see `tactex status` and '
                    'the node log)')
            raise CommandError(f'{what}: the goal was not answered within {timeout_s:g} s; '
                               'the node logs say why')
        time.sleep(1.0)


def shown_on(bar: tqdm | None, shown: Progress, what: str, unit: str) -> tqdm:
    """`bar` (made at the first feedback, when the total is known) showing `shown`."""
    if bar is None:
        bar = tqdm(desc=what, total=shown.total, unit=unit, file=sys.stderr, mininterval=0.5,
                   dynamic_ncols=True, bar_format='{desc}: {percentage:3.0f}%|{bar}| '
                   '{n:.0f}/{total:.0f} {unit} [{elapsed}<{remaining}{postfix}]')
    if (bar.total, bar.n, bar.postfix) != (shown.total, shown.done, shown.state):
        bar.total, bar.n = shown.total, shown.done
        bar.set_postfix_str(shown.state)  # redrawn on a change only: logs stay short
    return bar


def canceled_end(handle, result, timeout_s: float = CANCEL_S) -> str:
    """Cancel the goal of `handle`, wait for its `result` future; how the goal ended.

    'it was canceled' only when the node ended it canceled; otherwise how it ended (with
    the node's reason when its result carries a `message`), that the node refused the
    cancel, or that it did not end the goal within `timeout_s`.
    """
    cancel = handle.cancel_goal_async()

    def refused() -> bool:
        return cancel.done() and cancel.result().return_code == CancelGoal.Response.ERROR_REJECTED
    wait_until(lambda: result.done() or refused(), timeout_s)
    if not result.done():
        if refused():
            return 'the node refused to cancel it: it may still be running'
        return (f'the node did not end it within {timeout_s:g} s of the cancel; the node log '
                'says why')
    ended = result.result()
    if ended.status == GoalStatus.STATUS_CANCELED:
        return 'it was canceled'
    message = getattr(ended.result, 'message', '')
    return (f'asked to cancel, it ended {STATUS_NAMES.get(ended.status, ended.status)}'
            + (f' ({message})' if message else ''))


def send_goal(node, executor, action_type, action_name: str, goal, *, what: str,
              server_timeout_s: float, timeout_s: float,
              progress: Callable[[object], Progress], unit: str, launch: str = ''):
    """Send one goal, show its feedback, return (status name, result message).

    `launch` is what the no-server error suggests after `tactex launch` (default
    '`what` sim:=true').

    Raises:
        CommandError: no server within `server_timeout_s`; not accepted in that time;
            no result within `timeout_s` after acceptance (the goal is canceled first, and
            the error says how it ended).
        Stopped: a stop signal came; the goal was canceled first (and its end waited for).
    """
    sender = GoalSender(node, action_type, action_name)
    latest: list[object] = []
    with spinning(executor):
        if not sender.client.wait_for_server(timeout_sec=server_timeout_s):
            raise CommandError(
                f'no {what} action server on {action_name} within {server_timeout_s:g} s: is '
                f'its node running (`tactex launch {launch or f"{what} sim:=true"}`, or on '
                'the arm without sim:=true), under that --namespace, ROS_DOMAIN_ID and '
                'discovery range?')
        handle = accepted_handle(sender, goal, server_timeout_s, what,
                                 feedback=lambda message: latest.append(message.feedback))
        result = handle.get_result_async()
        bar = None
        try:
            deadline = time.monotonic() + timeout_s
            while not result.done():
                if time.monotonic() > deadline:
                    if bar is not None:
                        bar.close()
                    raise CommandError(f'the {what} goal did not finish within {timeout_s:g} s '
                                       f'(--timeout); {canceled_end(handle, result)}')
                if latest:
                    bar = shown_on(bar, progress(latest[-1]), what, unit)
                time.sleep(POLL_S)
        except Stopped:
            if bar is not None:
                bar.close()
            print(f'{what}: canceling the goal', file=sys.stderr, flush=True)
            handle.cancel_goal_async()
            if wait_until(result.done, CANCEL_S):
                ended = result.result()
                print(f'{what}: the goal ended {STATUS_NAMES.get(ended.status, ended.status)}'
                      + (f' ({ended.result.message})' if ended.result.message else ''),
                      file=sys.stderr)
            else:
                print(f'{what}: the node did not end the goal within {CANCEL_S:g} s',
                      file=sys.stderr)
            raise
        answer = result.result()
        if latest:  # the last feedback may come just before the result
            bar = shown_on(bar, progress(latest[-1]), what, unit)
        if bar is not None:
            if answer.status == GoalStatus.STATUS_SUCCEEDED:
                bar.n = bar.total
            bar.close()
    return STATUS_NAMES.get(answer.status, f'status {answer.status}'), answer.result
