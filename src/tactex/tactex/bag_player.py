# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex bag play` on rclpy: recordings published at their recorded timing.

The messages and their instants come from `tactex.bag_playback`; here each is published
as raw CDR (`publish_raw`, never decoded) when its instant comes, on a reliable publisher
(a reliable publisher also reaches best-effort subscribers; the recording's metadata is
latched, as the recorder's is). With `clock`, /clock carries the log time (before every
non-sensor message and at `CLOCK_HZ`), so nodes with use_sim_time see the recording's
time, as under `ros2 bag play --clock`. How late each publish was is kept.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
import gc
import importlib
import itertools
from pathlib import Path
from queue import Queue
import sys
import threading
import time

from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock

from tactex.bag_playback import Lateness, messages, Outgoing, PlayOptions, topics_of
from tactex.ros_client import client_node
from tactex_common import topics

CLOCK_HZ = 100.0
READ_AHEAD = 4096  # messages read before they are due
GIL_SWITCH_INTERVAL_S = 0.0005  # how soon the reader thread yields to a due publish
WAIT_POLL_S = 0.05  # how often the subscribers of --wait-for topics are counted
WAIT_TIMEOUT_S = 30.0  # the longest wait for them, unless told
SENSOR_TYPES = ('sensor_msgs/msg/Imu', 'sensor_msgs/msg/MagneticField',
                'sensor_msgs/msg/FluidPressure', 'sensor_msgs/msg/Temperature',
                'sensor_msgs/msg/JointState')
PLAYED = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE)
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)


def message_class(msgtype: str):
    """The rclpy class of 'pkg/msg/Name' (None when the package is not installed)."""
    package, _, name = msgtype.split('/')
    try:
        return getattr(importlib.import_module(f'{package}.msg'), name)
    except (ImportError, AttributeError):
        return None


class NoSubscriberError(Exception):
    """A topic to wait for is not played, or no subscriber matched it in time."""


def wait_for_subscribers(publishers: dict, names: Sequence[str], timeout_s: float) -> None:
    """Return once each named topic's publisher has a matched subscription.

    The middleware's own count of matched subscriptions (no spinning needed): a node that
    subscribed gets the first message. Names are as published (remapped, namespaced); a
    name without a leading '/' is taken from the root.

    Raises:
        NoSubscriberError: a name that is not played, or one unmatched after `timeout_s`.
    """
    wanted = ['/' + name.strip('/') for name in names]
    unknown = [name for name in wanted if name not in publishers]
    if unknown:
        played = ', '.join(sorted(publishers)) or 'none'
        raise NoSubscriberError(f'{", ".join(unknown)} not played; the played topics are '
                                f'{played}')
    deadline = time.monotonic() + timeout_s
    while True:
        waiting = [name for name in wanted if publishers[name].get_subscription_count() == 0]
        if not waiting:
            return
        if time.monotonic() >= deadline:
            raise NoSubscriberError(f'no subscriber to {", ".join(waiting)} within '
                                    f'{timeout_s:g} s; start the node that reads it first, '
                                    'or give a longer --wait-timeout')
        time.sleep(WAIT_POLL_S)


def play(paths: Sequence[Path], options: PlayOptions, *, loop: bool = False,
         clock: bool = False, delay_s: float = 1.0, wait_for: Sequence[str] = (),
         wait_timeout_s: float = WAIT_TIMEOUT_S, said: Callable[[str], None] = print,
         progress: Callable[[float], None] | None = None) -> dict:
    """Publish the recordings one after another (again and again with `loop`).

    Args:
        paths: recordings (see `tactex_classify.data.sources`).
        options: what of them is played, under which names, how fast.
        loop: start again after the last until a stop signal.
        clock: publish /clock with the recorded time.
        delay_s: wait this long after creating the publishers (discovery), as
            `ros2 bag play --delay` (after `wait_for`'s subscribers matched, if any).
        wait_for: topics (as published; /clock too with `clock`) that must each have a
            subscriber before the first message (`wait_for_subscribers`).
        wait_timeout_s: the longest wait for them.
        said: told about topics that cannot be played.
        progress: called with the seconds of recording played, twice a second.

    Returns:
        The lateness summary, with 'passes' (recordings played through) and 'stopped'
        (the stop signal's name, '' when played to the end).

    Raises:
        NoSubscriberError: a topic of `wait_for` not played, or without a subscriber.
    """
    lateness, passes = Lateness(), 0
    with client_node('tactex_bag_play') as (node, _executor):
        publishers = {}
        for topic, msgtype in topics_of(paths, options).items():
            kind = message_class(msgtype)
            if kind is None:
                said(f'warning: {topic} not played: {msgtype} is not installed here')
                continue
            latched = topic.endswith(topics.RECORDING_METADATA)
            publishers[topic] = node.create_publisher(kind, topic, LATCHED if latched
                                                      else PLAYED)
        clock_publisher = node.create_publisher(Clock, '/clock', PLAYED) if clock else None
        waited_on = {**publishers, '/clock': clock_publisher} if clock else publishers
        # What the imports and rclpy built stays: the garbage collector's full passes over
        # it paused playback for 100 ms and more.
        gc.freeze()
        sys.setswitchinterval(GIL_SWITCH_INTERVAL_S)
        stopped = ''
        try:
            wait_for_subscribers(waited_on, wait_for, wait_timeout_s)
            time.sleep(delay_s)
            while True:
                for path in paths:
                    _play_one(path, options, publishers, clock_publisher, lateness, said,
                              progress)
                    passes += 1
                if not loop:
                    break
        except KeyboardInterrupt as stop:  # Ctrl-C or a stop signal: report what was played
            stopped = str(stop) or 'SIGINT'
    return {**lateness.summary(), 'passes': passes, 'stopped': stopped}


def _play_one(path: Path, options: PlayOptions, publishers: dict, clock_publisher,
              lateness: Lateness, said, progress) -> None:
    source = messages(path, options, skipped=lambda why: said(f'warning: {why}'))
    first = next(source, None)  # the recording opened before its clock starts
    if first is None:
        return
    started = time.monotonic()
    next_clock = next_report = 0.0
    for outgoing in _read_ahead(itertools.chain([first], source)):
        publisher = publishers.get(outgoing.topic)
        if publisher is None:
            continue
        _wait_until(started + outgoing.due_s)
        now = time.monotonic() - started
        if clock_publisher is not None and (
                now >= next_clock or outgoing.msgtype not in SENSOR_TYPES):
            _publish_clock(clock_publisher, outgoing)
            next_clock = now + 1.0 / CLOCK_HZ
        publisher.publish(outgoing.data)
        lateness.add(time.monotonic() - started - outgoing.due_s)
        if progress is not None and now >= next_report:
            progress(outgoing.due_s * options.rate_factor)
            next_report = now + 0.5


def _read_ahead(source: Iterator[Outgoing]) -> Iterator[Outgoing]:
    """The messages of `source`, read by a thread of their own up to READ_AHEAD ahead.

    Reading a message takes tens of microseconds and a new chunk of the bag tens of
    milliseconds: done beside the publishing, neither delays a message that is due (the
    reader yields the interpreter within GIL_SWITCH_INTERVAL_S when a publish is due).
    """
    queue: Queue = Queue(maxsize=READ_AHEAD)
    end = object()

    def read() -> None:
        try:
            for outgoing in source:
                queue.put(outgoing)
        except Exception as err:  # noqa: BLE001 - handed to the publishing thread
            queue.put(err)
        queue.put(end)

    threading.Thread(target=read, name='bag-reader', daemon=True).start()
    while (item := queue.get()) is not end:
        if isinstance(item, Exception):
            raise item
        yield item


def _wait_until(instant: float) -> None:
    """Sleep until `instant` (time.monotonic); a stop signal ends the sleep."""
    remaining = instant - time.monotonic()
    if remaining > 0:
        time.sleep(remaining)


def _publish_clock(publisher, outgoing: Outgoing) -> None:
    message = Clock()
    message.clock.sec, message.clock.nanosec = divmod(outgoing.log_ns, 1_000_000_000)
    publisher.publish(message)
