# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""ROS-facing helpers every tactex node shares: QoS profiles and the node `main`.

This module imports rclpy; only nodes (and the launcher) import it.
"""

from __future__ import annotations

from collections.abc import Callable
import importlib
import threading

import rclpy
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    qos_profile_sensor_data,
    QoSProfile,
    ReliabilityPolicy,
)
from rclpy.signals import SignalHandlerOptions

from tactex_common.stopping import on_stop_signals

# Sensor streams: best effort, keep last 5 (a late sample is worth less than a new one).
SENSOR_DATA = qos_profile_sensor_data
# Commands and events: reliable, keep last 10.
COMMAND = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.VOLATILE, history=HistoryPolicy.KEEP_LAST)
# Latched state (the pathway, the robot description): a late subscriber gets the last one.
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL,
                     history=HistoryPolicy.KEEP_LAST)
# Recording subscriptions by the kind of their topic (tactex_classify.recorder's
# RECORDED_TOPICS): sensor streams best effort with a deep queue, so a busy moment of the
# recorder drops nothing a recording keeps.
RECORDING = {'sensor': QoSProfile(depth=500, reliability=ReliabilityPolicy.BEST_EFFORT,
                                  durability=DurabilityPolicy.VOLATILE,
                                  history=HistoryPolicy.KEEP_LAST),
             'command': COMMAND, 'latched': LATCHED}
# How often the main thread of a node looks for a stop signal (s).
STOP_CHECK_S = 0.1


def spin(make_node: Callable[[], Node], args: list[str] | None = None) -> None:
    """Create the node and spin it on one thread until SIGINT, SIGTERM, SIGHUP or shutdown.

    One thread keeps up with the streams where rclpy's multi-threaded executor falls
    behind on two cores; an action whose goal waits on other callbacks awaits them from
    a coroutine execute callback instead of blocking a thread.

    The executor spins on a thread of its own while the main thread waits for a stop
    signal (Python runs signal handlers only there, and a wait set does not wake for
    them); on one it shuts the executor down, then destroys the node and shuts rclpy
    down, in that order. rclpy's own handlers are off: they shut the context down under
    running callbacks (RCLError tracebacks) or raise KeyboardInterrupt inside one, and
    they ignore SIGHUP and an inherited ignored SIGINT (tactex_common.stopping).

    Args:
        make_node: builds the node (after rclpy.init).
        args: command-line arguments (ROS arguments included).
    """
    stop = threading.Event()
    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    node = None
    with on_stop_signals(lambda _signum: stop.set()):
        try:
            node = make_node()
            executor = SingleThreadedExecutor()
            executor.add_node(node)
            failures: list[BaseException] = []
            spinner = threading.Thread(target=_spin_until_shutdown,
                                       args=(executor, stop, failures), name='executor')
            spinner.start()
            while not stop.wait(STOP_CHECK_S):
                pass
            executor.shutdown(timeout_sec=STOP_CHECK_S)
            spinner.join()
            if failures:  # a callback raised: the node fails as if it had spun here
                raise failures[0]
        finally:
            if node is not None:
                node.destroy_node()
            rclpy.try_shutdown()


def _spin_until_shutdown(executor: SingleThreadedExecutor, stop: threading.Event,
                         failures: list[BaseException]) -> None:
    """Spin `executor` until it is shut down, keeping what a callback raised; then set `stop`."""
    try:
        executor.spin()
    except ExternalShutdownException:
        pass
    except BaseException as error:  # noqa: B036 - handed to the main thread, raised there
        failures.append(error)
    finally:
        stop.set()


def message_class(type_name: str) -> type:
    """The rclpy class of a message type named like 'sensor_msgs/msg/Imu'.

    Raises:
        ValueError: the name is not PACKAGE/msg/NAME.
        ImportError, AttributeError: no such package or message.
    """
    parts = type_name.split('/')
    if len(parts) != 3 or parts[1] != 'msg':
        raise ValueError(f'expected a message type like sensor_msgs/msg/Imu, got {type_name!r}')
    return getattr(importlib.import_module(f'{parts[0]}.msg'), parts[2])
