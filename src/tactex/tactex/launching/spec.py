# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Launch files as plain data: the arguments and the node set both launch paths read.

Each `launch/<name>.launch.py` defines `LAUNCH = LaunchFile(...)`, a description of its
arguments and a function from the resolved arguments to its nodes. ROS 2 launch builds
its `LaunchDescription` from it (`tactex.launching.ros_description`), and `tactex launch`
runs the same nodes as supervised processes (`tactex.launching.supervisor`), so the two
cannot drift.

Parameter values given as strings are YAML-typed by both paths (`'1.0'` is a float,
`'true'` a bool), exactly as `ros2 launch` and `--ros-args -p` do.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
import importlib.util
import math
from pathlib import Path
from typing import Any

from tactex_common.naming import closest_name
from tactex_common.share import share_directory


class LaunchError(Exception):
    """A launch file or its arguments are wrong; the message says how to fix it."""


@dataclass(frozen=True)
class Argument:
    """A launch argument (`name:=value`)."""

    name: str
    default: str
    description: str
    choices: tuple[str, ...] = ()


@dataclass(frozen=True)
class NodeSpec:
    """One node to start.

    Args:
        package: the ament package of the executable.
        executable: its console-script name.
        name: the node name.
        parameters: YAML parameter files (paths) and dicts of parameter values, in order.
        remappings: (from, to) topic remappings.
        respawn: restart the node when it exits (the launcher waits `respawn_delay_s`).
        arguments: command-line arguments before the ROS arguments (e.g. rviz2's -d).
    """

    package: str
    executable: str
    name: str
    parameters: tuple[str | Mapping[str, Any], ...] = ()
    remappings: tuple[tuple[str, str], ...] = ()
    respawn: bool = False
    respawn_delay_s: float = 1.0
    arguments: tuple[str, ...] = ()


# Every launch file takes these; both launch paths apply them to every node.
COMMON_ARGUMENTS = (
    Argument('namespace', '', 'ROS namespace for every node (e.g. left_arm)'),
    Argument('discovery', 'localhost',
             'who may discover these nodes: this host only, or the whole subnet',
             ('localhost', 'subnet')),
    Argument('rviz', 'false', 'also start robot_state_publisher and RViz (full ROS 2 installs)',
             ('true', 'false')),
)
DISCOVERY_RANGE = {'localhost': 'LOCALHOST', 'subnet': 'SUBNET'}


@dataclass(frozen=True)
class LaunchFile:
    """What a launch file starts, as data.

    Args:
        description: one line for `tactex launch --list`.
        arguments: its own arguments (the common ones are added).
        nodes: resolved arguments -> the nodes to start.
    """

    description: str
    arguments: tuple[Argument, ...]
    nodes: Callable[[Mapping[str, str]], Sequence[NodeSpec]]
    all_arguments: tuple[Argument, ...] = field(init=False)

    def __post_init__(self) -> None:
        """Append the common arguments."""
        object.__setattr__(self, 'all_arguments', self.arguments + COMMON_ARGUMENTS)

    def resolve(self, overrides: Mapping[str, str]) -> dict[str, str]:
        """Defaults updated by `overrides`.

        Raises:
            LaunchError: an unknown argument or a value outside its choices.
        """
        known = {argument.name: argument for argument in self.all_arguments}
        unknown = sorted(set(overrides) - set(known))
        if unknown:
            hints = [f'{name!r}: did you mean {closest!r}?' for name in unknown
                     if (closest := closest_name(name, known))]
            hint = f' ({"; ".join(hints)})' if hints else ''
            raise LaunchError(f'unknown launch argument(s) {unknown}{hint}; this launch file '
                              f'takes: {", ".join(sorted(known))}')
        values = {name: argument.default for name, argument in known.items()}
        values.update(overrides)
        for name, value in values.items():
            choices = known[name].choices
            if choices and value not in choices:
                raise LaunchError(f'{name}:={value!r} is not one of {", ".join(choices)}')
        return values

    def node_specs(self, overrides: Mapping[str, str]) -> list[NodeSpec]:
        """The nodes to start for these argument values (and the viewer with rviz:=true)."""
        values = self.resolve(overrides)
        nodes = list(self.nodes(values))
        return nodes + visualisation_nodes() if is_true(values['rviz']) else nodes


    def node(self, name: str, overrides: Mapping[str, str]) -> NodeSpec:
        """The node called `name` of this launch file, for these argument values.

        Raises:
            LaunchError: it starts no node of that name.
        """
        nodes = {spec.name: spec for spec in self.node_specs(overrides)}
        if name not in nodes:
            raise LaunchError(f'no node {name!r} in this launch file; it starts '
                              f'{", ".join(nodes)}')
        return nodes[name]


def config_path(name: str) -> str:
    """Path of a parameter file of the tactex package's config/ folder."""
    return str(share_directory('tactex') / 'config' / name)


def visualisation_nodes() -> list[NodeSpec]:
    """robot_state_publisher on the generated URDF and RViz with config/tactex.rviz.

    For full ROS 2 installs (neither is on PyPI); launch files start them with rviz:=true.
    """
    urdf = share_directory('tactex_description') / 'urdf' / 'open_manipulator_x_tactile.urdf'
    return [NodeSpec('robot_state_publisher', 'robot_state_publisher', 'robot_state_publisher',
                     parameters=({'robot_description': urdf.read_text(encoding='utf-8')},)),
            NodeSpec('rviz2', 'rviz2', 'rviz2', arguments=('-d', config_path('tactex.rviz')))]


def is_true(value: str) -> bool:
    """A boolean launch argument ('true'/'false', as ros2 launch spells them).

    Raises:
        LaunchError: neither.
    """
    if value.lower() in ('true', '1', 'yes'):
        return True
    if value.lower() in ('false', '0', 'no'):
        return False
    raise LaunchError(f'expected true or false, got {value!r}')


def as_float(name: str, value: str) -> float:
    """A number argument as a float, so that `rate_factor:=3` reaches a DOUBLE parameter.

    Raises:
        LaunchError: not a finite number.
    """
    try:
        number = float(value)
    except ValueError:
        number = math.nan
    if not math.isfinite(number):
        raise LaunchError(f'{name}:={value!r} is not a finite number')
    return number


def robot_nodes(args: Mapping[str, str], **sim_overrides: str) -> list[NodeSpec]:
    """The robot of a launch file: MuJoCo with `sim:=true`, else the sensor and the arm.

    Reads the arguments `sim`, `scene` and `rate_factor` (simulated), `sensor_port` and
    `arm_port` (hardware); `sim_overrides` are more arguments of launch/sim.launch.py.
    """
    if is_true(args['sim']):
        return load_launch_file('sim').node_specs(
            {'scene': args['scene'], 'rate_factor': args['rate_factor'], **sim_overrides})
    return [*load_launch_file('sensor').node_specs({'port': args['sensor_port']}),
            *load_launch_file('arm').node_specs({'port': args['arm_port']})]


def launch_directory() -> Path:
    """The installed (or checked-out) launch/ folder of the tactex package."""
    return share_directory('tactex') / 'launch'


def load_launch_file(name_or_path: str) -> LaunchFile:
    """The `LAUNCH` of `launch/NAME.launch.py` (or of a path to a launch file).

    Raises:
        LaunchError: no such file, or it defines no LaunchFile called LAUNCH.
    """
    path = Path(name_or_path)
    if not path.suffix:
        path = launch_directory() / f'{name_or_path}.launch.py'
    if not path.is_file() or path.suffix != '.py':
        known = sorted(p.name.removesuffix('.launch.py')
                       for p in launch_directory().glob('*.launch.py'))
        raise LaunchError(f'no launch file {name_or_path!r} (a NAME or a .launch.py path); '
                          f'known: {", ".join(known)}')
    spec = importlib.util.spec_from_file_location(f'tactex_launch_{path.stem}', path)
    module = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(module)
    except Exception as err:  # noqa: BLE001 - a launch file is code; any failure is its fault
        raise LaunchError(f'{path} cannot be loaded: {type(err).__name__}: {err}') from None
    launch = getattr(module, 'LAUNCH', None)
    if not isinstance(launch, LaunchFile):
        raise LaunchError(f'{path} defines no LAUNCH = LaunchFile(...)')
    return launch
