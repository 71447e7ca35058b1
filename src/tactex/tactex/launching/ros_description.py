# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""ROS 2 launch from a `LaunchFile`: its entities as launch and launch_ros actions.

What each launch file's generate_launch_description returns, built the way nav2's launch
files are: DeclareLaunchArgument for every argument, one GroupAction that sets the
discovery range and pushes the namespace, then a Node, an IncludeLaunchDescription (in
its own scoped GroupAction) or a GroupAction per entity, with IfCondition/UnlessCondition
and LaunchConfiguration, EqualsSubstitution, NotEqualsSubstitution and IfElseSubstitution
for the values. `ros2 launch --print-description` shows that tree. Needs the `launch` and
`launch_ros` packages of a full ROS 2 install (Jazzy or newer); `tactex launch` runs the
same entities where they are not installed.
"""

from __future__ import annotations

import sys

from launch import LaunchDescription
from launch.actions import (
    DeclareLaunchArgument,
    GroupAction,
    IncludeLaunchDescription,
    OpaqueFunction,
    SetEnvironmentVariable,
)
from launch.conditions import IfCondition, UnlessCondition
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch.substitutions import (
    EqualsSubstitution,
    IfElseSubstitution,
    LaunchConfiguration,
    NotEqualsSubstitution,
)
from launch_ros.actions import Node, PushROSNamespace
from launch_ros.parameter_descriptions import ParameterValue

from tactex.launching.spec import (
    Arg,
    as_text,
    Condition,
    DISCOVERY_RANGE,
    Entity,
    Equals,
    Group,
    If,
    IfElse,
    Include,
    launch_directory,
    LaunchFile,
    load_launch_file,
    not_equals,
    Value,
)


def launch_description(launch: LaunchFile) -> LaunchDescription:
    """Declare the arguments, then the discovery range, the namespace and the entities."""
    declared = [DeclareLaunchArgument(
        a.name, description=a.description,
        **({'default_value': a.default} if a.default is not None else {}),
        **({'choices': list(a.choices)} if a.choices else {})) for a in launch.all_arguments]
    discovery = [SetEnvironmentVariable('ROS_AUTOMATIC_DISCOVERY_RANGE', ros_range,
                                        condition=_condition(If(Equals('discovery', choice))))
                 for choice, ros_range in DISCOVERY_RANGE.items()]
    namespace = PushROSNamespace(LaunchConfiguration('namespace'),
                                 condition=_condition(If(not_equals('namespace', ''))))
    entities = [_action(entity, launch) for entity in launch.every_entity()]
    checks = OpaqueFunction(function=_hardware_ready, args=[launch],
                            condition=IfCondition(LaunchConfiguration('checks')))
    return LaunchDescription([*declared, checks,
                              GroupAction([*discovery, namespace, *entities])])


def _hardware_ready(context, launch: LaunchFile) -> list:
    """Before any node starts: the hardware nodes' bring-up checks, as `tactex launch` runs them.

    A failed check prints the fixes and ends the launch (launch reports the exception's
    line and exits 1) before a node is started.
    """
    from tactex.bringup import not_ready_lines
    values = {argument.name: context.launch_configurations.get(argument.name, argument.default)
              for argument in launch.all_arguments}
    report = not_ready_lines(launch.node_specs(values))
    if report:
        print(*report[:-1], sep='\n', file=sys.stderr, flush=True)
        raise RuntimeError(report[-1].removeprefix('error: '))
    return []


def _substitution(value: Value):
    """A value as launch substitutes it (include arguments, conditions)."""
    if isinstance(value, Arg):
        return LaunchConfiguration(value.name)
    if isinstance(value, Equals):
        compare = NotEqualsSubstitution if value.negated else EqualsSubstitution
        return compare(LaunchConfiguration(value.name), value.text)
    if isinstance(value, IfElse):
        return IfElseSubstitution(LaunchConfiguration(value.name), value.if_true,
                                  value.if_false)
    return as_text(value)


def _parameter(value: Value, launch: LaunchFile):
    """A parameter value, typed as `tactex launch` types it."""
    if isinstance(value, Arg):
        kind = launch.argument(value.name).kind
        return (LaunchConfiguration(value.name) if kind == 'text' else
                ParameterValue(LaunchConfiguration(value.name),
                               value_type=float if kind == 'float' else bool))
    if isinstance(value, Equals):
        return ParameterValue(_substitution(value), value_type=bool)
    if isinstance(value, IfElse):
        return _substitution(value)
    if isinstance(value, str) and '\n' in value:  # text of several lines (a URDF) stays text
        return ParameterValue(value, value_type=str)
    return value


def _condition(condition: Condition | None):
    if condition is None:
        return None
    kind = IfCondition if isinstance(condition, If) else UnlessCondition
    return kind(_substitution(condition.test))


def _included_arguments(include: Include) -> list[tuple]:
    """Every argument of the included file: the given values, else its own defaults.

    Passing the defaults too keeps the includer's values of the same names out of it
    (ROS 2 launch would let them through), as `tactex launch` does.
    """
    given = include.given()
    arguments = []
    for argument in load_launch_file(include.name).all_arguments:
        if argument.name in given:
            arguments.append((argument.name, _substitution(given[argument.name])))
        elif argument.default is not None:
            arguments.append((argument.name, argument.default))
    return arguments


def _action(entity: Entity, launch: LaunchFile):
    condition = _condition(entity.condition)
    if isinstance(entity, Group):
        return GroupAction([_action(e, launch) for e in entity.entities], condition=condition)
    if isinstance(entity, Include):
        source = PythonLaunchDescriptionSource(
            str(launch_directory() / f'{entity.name}.launch.py'))
        return GroupAction([IncludeLaunchDescription(
            source, launch_arguments=_included_arguments(entity))], condition=condition)
    return Node(package=entity.package, executable=entity.executable, name=entity.name,
                parameters=[p if isinstance(p, str) else
                            {k: _parameter(v, launch) for k, v in p.items()}
                            for p in entity.parameters],
                remappings=list(entity.remappings), arguments=list(entity.arguments),
                respawn=entity.respawn, respawn_delay=entity.respawn_delay_s,
                output='screen', condition=condition)
