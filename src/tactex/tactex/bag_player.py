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

from collections import deque
from collections.abc import Callable, Iterator, Sequence
import importlib
import itertools
from pathlib import Path
import time

from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock

from tactex.bag_playback import Lateness, messages, Outgoing, PlayOptions, topics_of
from tactex.ros_client import client_node
from tactex_common import topics

CLOCK_HZ = 100.0
READ_AHEAD = 4096  # messages read before they are due
SPARE_S = 0.001  # stop reading ahead this long before the next message is due
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


def play(paths: Sequence[Path], options: PlayOptions, *, loop: bool = False,
         clock: bool = False, delay_s: float = 1.0, said: Callable[[str], None] = print,
         progress: Callable[[float], None] | None = None) -> dict:
    """Publish the recordings one after another (again and again with `loop`).

    Args:
        paths: recordings (see `tactex_classify.data.sources`).
        options: what of them is played, under which names, how fast.
        loop: start again after the last until a stop signal.
        clock: publish /clock with the recorded time.
        delay_s: wait this long after creating the publishers (discovery), as
            `ros2 bag play --delay`.
        said: told about topics that cannot be played.
        progress: called with the seconds of recording played, twice a second.

    Returns:
        The lateness summary, with 'passes' (recordings played through).
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
        time.sleep(delay_s)
        while True:
            for path in paths:
                _play_one(path, options, publishers, clock_publisher, lateness, said,
                          progress)
                passes += 1
            if not loop:
                break
    return {**lateness.summary(), 'passes': passes}


def _play_one(path: Path, options: PlayOptions, publishers: dict, clock_publisher,
              lateness: Lateness, said, progress) -> None:
    source = messages(path, options, skipped=lambda why: said(f'warning: {why}'))
    first = next(source, None)  # the recording opened before its clock starts
    if first is None:
        return
    started = time.monotonic()
    next_clock = next_report = 0.0
    for outgoing in _read_ahead(itertools.chain([first], source), started):
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


def _read_ahead(source: Iterator[Outgoing], started: float) -> Iterator[Outgoing]:
    """The messages of `source`, read ahead (up to READ_AHEAD) while the next is not due.

    Reading and converting a message takes tens of microseconds: done in the time spent
    waiting anyway, it is not added to the lateness of the messages due together.
    """
    queue: deque[Outgoing] = deque()
    for first in source:
        queue.append(first)
        while queue:
            due = started + queue[0].due_s - SPARE_S
            while len(queue) < READ_AHEAD and time.monotonic() < due:
                following = next(source, None)
                if following is None:
                    break
                queue.append(following)
            yield queue.popleft()


def _wait_until(instant: float) -> None:
    """Sleep until `instant` (time.monotonic); a stop signal ends the sleep."""
    remaining = instant - time.monotonic()
    if remaining > 0:
        time.sleep(remaining)


def _publish_clock(publisher, outgoing: Outgoing) -> None:
    message = Clock()
    message.clock.sec, message.clock.nanosec = divmod(outgoing.log_ns, 1_000_000_000)
    publisher.publish(message)
