# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Launch files as plain data: the arguments and the entities both launch paths read.

Each `launch/<name>.launch.py` defines `LAUNCH = LaunchFile(...)`: its arguments and its
entities, in the words of ROS 2 launch. A `NodeSpec` is a Node, an `Include` an
IncludeLaunchDescription, a `Group` a GroupAction; `If`/`Unless` are IfCondition and
UnlessCondition; a parameter or include value may be an argument's (`Arg`, a
LaunchConfiguration) or a comparison of one (`Equals`, `IfElse`). ROS 2 launch gets the
same tree as launch actions (`tactex.launching.ros_description`), and `tactex launch`
evaluates it to the nodes it supervises (`tactex.launching.supervisor`), so the two
cannot drift (tests/tactex/test_launcher.py runs both on every launch file).

Parameter values given as strings are YAML-typed by both paths (`'1.0'` is a float,
`'true'` a bool), exactly as `ros2 launch` and `--ros-args -p` do.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
import importlib.util
import math
from pathlib import Path
from typing import Literal

from tactex_common.naming import closest_name
from tactex_common.share import share_directory


class LaunchError(Exception):
    """A launch file or its arguments are wrong; the message says how to fix it."""


@dataclass(frozen=True)
class Argument:
    """A launch argument (`name:=value`): DeclareLaunchArgument.

    Args:
        name: its name.
        default: its value when not given; None makes it required.
        description: one line for `--list` and `ros2 launch --show-args`.
        choices: the values it may take (a `bool` argument takes true and false).
        kind: what a node parameter set from it is: `text` (YAML-typed, as ros2 launch
            types a LaunchConfiguration), `float` or `bool`.
    """

    name: str
    default: str | None
    description: str
    choices: tuple[str, ...] = ()
    kind: Literal['text', 'float', 'bool'] = 'text'

    def __post_init__(self) -> None:
        """A bool argument takes true and false."""
        if self.kind == 'bool' and not self.choices:
            object.__setattr__(self, 'choices', ('true', 'false'))


@dataclass(frozen=True)
class Arg:
    """The value of a launch argument: LaunchConfiguration(name)."""

    name: str


@dataclass(frozen=True)
class Equals:
    """Whether argument `name` is `text`: EqualsSubstitution (NotEqualsSubstitution)."""

    name: str
    text: str
    negated: bool = False


def not_equals(name: str, text: str) -> Equals:
    """Whether argument `name` is not `text` (`not_equals('checkpoint', '')`: one is given)."""
    return Equals(name, text, negated=True)


@dataclass(frozen=True)
class IfElse:
    """`if_true` when bool argument `name` is true, else `if_false`: IfElseSubstitution."""

    name: str
    if_true: str
    if_false: str


Value = str | float | bool | Arg | Equals | IfElse


@dataclass(frozen=True)
class If:
    """Start an entity when `test` (a bool argument or a comparison) holds: IfCondition."""

    test: Arg | Equals


@dataclass(frozen=True)
class Unless:
    """Start an entity unless `test` holds: UnlessCondition."""

    test: Arg | Equals


Condition = If | Unless


@dataclass(frozen=True)
class NodeSpec:
    """One node to start: launch_ros's Node.

    Args:
        package: the ament package of the executable.
        executable: its console-script name.
        name: the node name.
        parameters: YAML parameter files (paths) and dicts of parameter values, in order;
            a value may be an argument's (`Arg`) or a comparison of one (`Equals`).
        remappings: (from, to) topic remappings.
        respawn: restart the node when it exits (the launcher waits `respawn_delay_s`).
        arguments: command-line arguments before the ROS arguments (e.g. rviz2's -d).
        condition: start it only when this holds.
    """

    package: str
    executable: str
    name: str
    parameters: tuple[str | Mapping[str, Value], ...] = ()
    remappings: tuple[tuple[str, str], ...] = ()
    respawn: bool = False
    respawn_delay_s: float = 1.0
    arguments: tuple[str, ...] = ()
    condition: Condition | None = None


@dataclass(frozen=True)
class Include:
    """Another launch file with these argument values: IncludeLaunchDescription.

    Args:
        name: the launch file, `launch/NAME.launch.py`.
        arguments: its argument values; those not given take its defaults (not the
            including file's values of the same name, so an include reads alike in both
            launch paths). Its nodes share the including file's namespace and discovery.
        condition: include it only when this holds.
    """

    name: str
    arguments: Mapping[str, Value] = field(default_factory=dict)
    condition: Condition | None = None

    def given(self) -> dict[str, Value]:
        """Every value it hands over: the common arguments' (`INCLUDED_COMMON`), then its own."""
        return {**INCLUDED_COMMON, **self.arguments}


@dataclass(frozen=True)
class Group:
    """Entities that share a condition: GroupAction."""

    entities: tuple[Entity, ...]
    condition: Condition | None = None


Entity = NodeSpec | Include | Group

# Every launch file takes these; both launch paths apply them to every node.
COMMON_ARGUMENTS = (
    Argument('namespace', '', 'ROS namespace for every node (e.g. left_arm)'),
    Argument('discovery', 'localhost',
             'who may discover these nodes: this host only, or the whole subnet',
             ('localhost', 'subnet')),
    Argument('rviz', 'false', 'also start robot_state_publisher and RViz (full ROS 2 installs)',
             kind='bool'),
    Argument('checks', 'true', "run tactex doctor's checks of the hardware nodes' ports, "
             'stream and servos before starting them; stop with the fixes when one fails',
             kind='bool'),
)
DISCOVERY_RANGE = {'localhost': 'LOCALHOST', 'subnet': 'SUBNET'}
# What an included file gets for the common arguments: the includer applies them once.
INCLUDED_COMMON = {'namespace': '', 'discovery': Arg('discovery'), 'rviz': 'false',
                   'checks': 'false'}


@dataclass(frozen=True)
class LaunchFile:
    """What a launch file starts, as data.

    Args:
        description: one line for `tactex launch --list`.
        arguments: its own arguments (the common ones are added).
        entities: its nodes, includes and groups, in start order.
    """

    description: str
    arguments: tuple[Argument, ...]
    entities: tuple[Entity, ...]
    all_arguments: tuple[Argument, ...] = field(init=False)

    def __post_init__(self) -> None:
        """Append the common arguments."""
        object.__setattr__(self, 'all_arguments', self.arguments + COMMON_ARGUMENTS)

    def argument(self, name: str) -> Argument:
        """The argument called `name`.

        Raises:
            LaunchError: this launch file takes none of that name.
        """
        for argument in self.all_arguments:
            if argument.name == name:
                return argument
        raise LaunchError(f'this launch file takes no argument {name!r}')

    def resolve(self, overrides: Mapping[str, str]) -> dict[str, str]:
        """Defaults updated by `overrides`.

        Raises:
            LaunchError: an unknown argument, a required one missing, a value outside its
                choices or a float argument that is not a finite number.
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
            argument = known[name]
            if argument.default is None and not value:
                raise LaunchError(f'{name}:=... is required: {argument.description}')
            if argument.choices and value not in argument.choices:
                raise LaunchError(f'{name}:={value!r} is not one of {", ".join(argument.choices)}')
            if argument.kind == 'float':
                as_float(name, value)
        return values

    def every_entity(self) -> tuple[Entity, ...]:
        """Its entities, then the viewer group that `rviz:=true` starts."""
        simulated = Arg('sim') if any(a.name == 'sim' for a in self.all_arguments) else False
        return (*self.entities, Group(tuple(visualisation_nodes(simulated)), If(Arg('rviz'))))

    def node_specs(self, overrides: Mapping[str, str]) -> list[NodeSpec]:
        """The nodes to start for these argument values, with their parameter values."""
        values = self.resolve(overrides)
        return _started(self.every_entity(), self, values)

    def evaluate(self, value: Value, values: Mapping[str, str]) -> str | float | bool:
        """A parameter or argument value for these resolved argument `values`."""
        if isinstance(value, Arg):
            text, kind = values[value.name], self.argument(value.name).kind
            return as_float(value.name, text) if kind == 'float' else (
                is_true(text) if kind == 'bool' else text)
        if isinstance(value, Equals):
            return (values[value.name] == value.text) != value.negated
        if isinstance(value, IfElse):
            return value.if_true if is_true(values[value.name]) else value.if_false
        return value

    def holds(self, condition: Condition | None, values: Mapping[str, str]) -> bool:
        """Whether an entity with this condition starts."""
        if condition is None:
            return True
        test = bool(self.evaluate(condition.test, values))
        return test if isinstance(condition, If) else not test

    def included_arguments(self, include: Include,
                           values: Mapping[str, str]) -> dict[str, str]:
        """The argument values `include` hands its launch file, as text."""
        return {name: as_text(self.evaluate(value, values))
                for name, value in include.given().items()}


def _started(entities: Sequence[Entity], launch: LaunchFile,
             values: Mapping[str, str]) -> list[NodeSpec]:
    nodes = []
    for entity in entities:
        if not launch.holds(entity.condition, values):
            continue
        if isinstance(entity, Group):
            nodes += _started(entity.entities, launch, values)
        elif isinstance(entity, Include):
            included = load_launch_file(entity.name)
            nodes += included.node_specs(launch.included_arguments(entity, values))
        else:
            parameters = tuple(p if isinstance(p, str) else
                               {k: launch.evaluate(v, values) for k, v in p.items()}
                               for p in entity.parameters)
            nodes.append(replace(entity, parameters=parameters, condition=None))
    return nodes


def as_text(value: str | float | bool) -> str:
    """A value as a launch argument spells it (`true`, `3.0`, text as it is)."""
    if isinstance(value, bool):
        return 'true' if value else 'false'
    return str(value)


def config_path(name: str) -> str:
    """Path of a parameter file of the tactex package's config/ folder."""
    return str(share_directory('tactex') / 'config' / name)


# /tf and /tf_static are absolute in robot_state_publisher and RViz; relative, each
# namespace (namespace:=left_arm) has its own transforms, and the root namespace keeps /tf.
TF_IN_NAMESPACE = (('/tf', 'tf'), ('/tf_static', 'tf_static'))


def visualisation_nodes(simulated: Value = False) -> list[NodeSpec]:
    """robot_state_publisher on the generated URDF and RViz with config/tactex.rviz.

    For full ROS 2 installs (neither is on PyPI); launch files start them with rviz:=true.
    `simulated` (a launch file's `sim` argument) puts both on the simulator's clock, as
    the messages they show are stamped. Both use the namespace's tf (`TF_IN_NAMESPACE`).
    """
    urdf = share_directory('tactex_description') / 'urdf' / 'open_manipulator_x_tactile.urdf'
    clock = {'use_sim_time': simulated}
    return [NodeSpec('robot_state_publisher', 'robot_state_publisher', 'robot_state_publisher',
                     parameters=({'robot_description': urdf.read_text(encoding='utf-8'),
                                  **clock},), remappings=TF_IN_NAMESPACE),
            NodeSpec('rviz2', 'rviz2', 'rviz2', arguments=('-d', config_path('tactex.rviz')),
                     parameters=(clock,), remappings=TF_IN_NAMESPACE)]


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


def robot_arguments(scene: str, *, optional: bool = True) -> tuple[Argument, ...]:
    """robot.launch.py's arguments (`scene` its default here), and `robot` when optional."""
    robot = tuple(replace(a, default=scene) if a.name == 'scene' else a
                  for a in load_launch_file('robot').arguments)
    return (*robot, Argument('robot', 'true', 'also start the robot (launch/robot.launch.py); '
                             'false: it runs already', kind='bool')) if optional else robot


def include_robot(condition: Condition | None = None) -> Include:
    """robot.launch.py, handed the including file's values of its arguments."""
    return Include('robot', {a.name: Arg(a.name) for a in load_launch_file('robot').arguments},
                   condition)


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
