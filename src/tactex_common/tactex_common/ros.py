# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""ROS-facing helpers every tactex node shares: QoS profiles, the node base and `main`.

This module imports rclpy; only nodes (and the launcher) import it.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
import importlib
import sys
import threading
from typing import Any

from builtin_interfaces.msg import Time
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor, ParameterType
import rclpy
from rclpy.exceptions import (
    InvalidParameterTypeException,
    InvalidParameterValueException,
    ParameterException,
)
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.impl.implementation_singleton import rclpy_implementation
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    qos_profile_sensor_data,
    QoSProfile,
    ReliabilityPolicy,
)
from rclpy.signals import SignalHandlerOptions

from tactex_common.errors import NodeParameterError
from tactex_common.naming import closest_name
from tactex_common.stopping import on_stop_signals
from tactex_common.topics import diagnostic_name

# Sensor streams: best effort, keep last 5 (a late sample is worth less than a new one).
SENSOR_DATA = qos_profile_sensor_data
# Commands and events: reliable, keep last 10.
COMMAND = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.VOLATILE, history=HistoryPolicy.KEEP_LAST)
# Latched state (the pathway, the robot description): a late subscriber gets the last one.
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL,
                     history=HistoryPolicy.KEEP_LAST)
# Recording subscriptions by the kind of their topic (tactex_classify.recording.recorder's
# RECORDED_TOPICS): sensor streams best effort with a deep queue, so a busy moment of the
# recorder drops nothing a recording keeps.
RECORDING = {'sensor': QoSProfile(depth=500, reliability=ReliabilityPolicy.BEST_EFFORT,
                                  durability=DurabilityPolicy.VOLATILE,
                                  history=HistoryPolicy.KEEP_LAST),
             'command': COMMAND, 'latched': LATCHED}
# How often the main thread of a node looks for a stop signal (s).
STOP_CHECK_S = 0.1
# The range of every node's diagnostics_period_s (s).
DIAGNOSTICS_PERIOD_RANGE = FloatingPointRange(from_value=0.05, to_value=60.0)
# A parameter type as an error line says it.
TYPE_WORDS = {ParameterType.PARAMETER_BOOL: 'true or false',
              ParameterType.PARAMETER_INTEGER: 'an integer',
              ParameterType.PARAMETER_DOUBLE: 'a float',
              ParameterType.PARAMETER_STRING: 'text',
              ParameterType.PARAMETER_BYTE_ARRAY: 'a list of bytes',
              ParameterType.PARAMETER_BOOL_ARRAY: 'a list of true or false',
              ParameterType.PARAMETER_INTEGER_ARRAY: 'a list of integers',
              ParameterType.PARAMETER_DOUBLE_ARRAY: 'a list of floats',
              ParameterType.PARAMETER_STRING_ARRAY: 'a list of texts'}


class TactexNode(Node):
    """The base of every tactex node: a parameter value it refuses is one NodeParameterError.

    rclpy refuses a value (from --params-file or -p) that breaks the type or the range of a
    declared parameter with an exception naming neither the node nor what is allowed;
    this base names both, and `spin` turns it into one error line and exit code 1.
    """

    def declare_parameter(self, name: str, value: Any = None,
                          descriptor: ParameterDescriptor | None = None,
                          ignore_override: bool = False) -> Parameter:
        """Declare as rclpy does; a given value it refuses raises NodeParameterError."""
        descriptor = ParameterDescriptor() if descriptor is None else descriptor
        try:
            return super().declare_parameter(name, value, descriptor, ignore_override)
        except (InvalidParameterTypeException, InvalidParameterValueException) as err:
            # The given values: rclpy has no public accessor for them (Kilted).
            given = self._parameter_overrides.get(name)
            if given is None:  # the node's own default is refused: a bug, not bad input
                raise
            problem = (f'is {_type_words(given.value)}'
                       if isinstance(err, InvalidParameterTypeException) else 'is out of range')
            raise self._refusal(name, given.value, problem, allowed(descriptor)) from None

    def publish_diagnostics(self, publisher, level: bytes, task: str, message: str,
                            values: Mapping[str, object], hardware_id: str = '') -> None:
        """Publish the node's one DiagnosticStatus, its values as text, stamped now.

        The status is named `diagnostic_name(node, task)`: two systems in two namespaces
        publish on the one /diagnostics without taking each other's place.
        """
        status = DiagnosticStatus(
            level=level, name=diagnostic_name(self.get_fully_qualified_name(), task),
            message=message, hardware_id=hardware_id,
            values=[KeyValue(key=key, value=str(value)) for key, value in values.items()])
        array = DiagnosticArray(status=[status])
        array.header.stamp = self.get_clock().now().to_msg()
        publisher.publish(array)

    def refused_parameter(self, name: str, allowed_values: str) -> NodeParameterError:
        """The error to raise for declared parameter `name`, whose value the node refuses."""
        return self._refusal(name, self.get_parameter(name).value, 'is refused', allowed_values)

    def _refusal(self, name: str, value: Any, problem: str,
                 allowed_values: str) -> NodeParameterError:
        """The error; the node, refused in its constructor, is destroyed as a plain rclpy node.

        rclpy destroys the nodes of a context at shutdown, with their own destroy_node,
        which expects a node whose constructor finished.
        """
        error = NodeParameterError(f'{self.get_name()}: parameter {name}:={value!r} {problem}; '
                                   f'allowed: {allowed_values}')
        Node.destroy_node(self)
        return error


def allowed(descriptor: ParameterDescriptor) -> str:
    """What a parameter of this descriptor may be: its type and range ('a float from 0 to 10')."""
    words = TYPE_WORDS.get(descriptor.type, 'a value of its type')
    for bounds in (*descriptor.floating_point_range, *descriptor.integer_range):
        step = f' in steps of {bounds.step}' if bounds.step not in (0, 1) else ''
        words += f' from {bounds.from_value} to {bounds.to_value}{step}'
    return words


def _type_words(value: Any) -> str:
    return TYPE_WORDS.get(Parameter.Type.from_parameter_value(value).value, 'unset')


def warn_unknown_parameters(node: Node) -> list[str]:
    """Warn once for each parameter given to `node` that it does not declare (a typo?).

    rcl hands a node the values of --params-file and -p under any name; rclpy ignores the
    names nobody declares. Each gets one warning naming the closest declared name.

    Returns:
        the unknown names, sorted.
    """
    declared = node.list_parameters([], 0).names  # 0: every depth
    # The given values: rclpy has no public accessor for them (Kilted).
    unknown = sorted(set(node._parameter_overrides) - set(declared))
    for name in unknown:
        closest = closest_name(name, declared)
        hint = f'did you mean {closest!r}?' if closest else 'no parameter of it is close'
        node.get_logger().warning(f'unknown parameter {name!r} ignored; {hint}')
    return unknown


def spin(make_node: Callable[[], Node], args: list[str] | None = None) -> None:
    """Create the node and spin it on one thread until SIGINT, SIGTERM, SIGHUP or shutdown.

    One thread keeps up with the streams where rclpy's multi-threaded executor falls
    behind on two cores; an action whose goal waits on other callbacks awaits them from
    a coroutine execute callback instead of blocking a thread.

    The executor spins on a thread of its own while the main thread waits for a stop
    signal (Python runs signal handlers only there, and a wait set does not wake for
    them); on one it lets the spinning thread finish, shuts the executor down, then
    destroys the node and shuts rclpy down, in that order. rclpy's own handlers are off:
    they shut the context down under running callbacks (RCLError tracebacks) or raise
    KeyboardInterrupt inside one, and they ignore SIGHUP and an inherited ignored SIGINT
    (tactex_common.stopping).

    A parameter value the node refuses at construction is one `error:` line on stderr and
    SystemExit(1), no traceback; each given parameter it does not declare, one warning.

    Args:
        make_node: builds the node (after rclpy.init).
        args: command-line arguments (ROS arguments included).
    """
    stop = threading.Event()
    try:
        rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    except rclpy_implementation.RCLError as err:  # malformed --ros-args (`-p name:=`)
        print(f'error: {err}; see the ROS 2 argument syntax (-p name:=value)',
              file=sys.stderr)
        raise SystemExit(1) from None
    node = None
    with on_stop_signals(lambda _signum: stop.set()):
        try:
            try:
                node = make_node()
            except (NodeParameterError, ParameterException) as err:
                # ParameterException: a node not built on TactexNode, in rclpy's words.
                print(f'error: {err}', file=sys.stderr)
                raise SystemExit(1) from None
            warn_unknown_parameters(node)
            executor = SingleThreadedExecutor()
            executor.add_node(node)
            failures: list[BaseException] = []
            spinner = threading.Thread(target=_spin_until_shutdown,
                                       args=(executor, stop, failures), name='executor')
            spinner.start()
            while not stop.wait(STOP_CHECK_S):
                pass
            spinner.join()  # within STOP_CHECK_S: it waits no longer than that at a time
            executor.shutdown(timeout_sec=STOP_CHECK_S)
            if failures:  # a callback raised: the node fails as if it had spun here
                raise failures[0]
        finally:
            if node is not None:
                node.destroy_node()
            rclpy.try_shutdown()


def _spin_until_shutdown(executor: SingleThreadedExecutor, stop: threading.Event,
                         failures: list[BaseException]) -> None:
    """Spin `executor` until `stop` or shutdown, keeping what a callback raised; then set `stop`.

    Each wait lasts at most STOP_CHECK_S: shutting the executor down while this thread is
    entering a wait could leave it waiting on nothing (a node with no traffic would never
    wake), so the main thread joins this one first and shuts the executor down after.
    """
    try:
        while not stop.is_set() and executor.context.ok():
            executor.spin_once(timeout_sec=STOP_CHECK_S)
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


def time_message(stamp_ns: int) -> Time:
    """A builtin_interfaces/Time of `stamp_ns` nanoseconds."""
    sec, nanosec = divmod(int(stamp_ns), 1_000_000_000)
    return Time(sec=sec, nanosec=nanosec)
