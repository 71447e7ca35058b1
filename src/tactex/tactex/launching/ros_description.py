# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""ROS 2 launch from a `LaunchFile`: what each launch file's generate_launch_description returns.

Needs the `launch` and `launch_ros` packages of a full ROS 2 install; `tactex launch`
runs the same node set where they are not installed.
"""

from __future__ import annotations

from launch import LaunchContext, LaunchDescription
from launch.actions import (
    DeclareLaunchArgument,
    GroupAction,
    OpaqueFunction,
    SetEnvironmentVariable,
)
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node, PushRosNamespace
from launch_ros.parameter_descriptions import ParameterValue

from tactex.launching.spec import DISCOVERY_RANGE, LaunchFile


def launch_description(launch: LaunchFile) -> LaunchDescription:
    """Declare the arguments, then start the node set they select."""
    declared = [DeclareLaunchArgument(a.name, default_value=a.default, description=a.description,
                                      **({'choices': list(a.choices)} if a.choices else {}))
                for a in launch.all_arguments]
    return LaunchDescription([*declared, OpaqueFunction(function=_nodes, args=[launch])])


def _typed(parameters):
    """Text of several lines (a URDF) stays text; one-line strings are YAML-typed."""
    if isinstance(parameters, str):
        return parameters
    return {name: ParameterValue(value, value_type=str)
            if isinstance(value, str) and '\n' in value else value
            for name, value in parameters.items()}


def _nodes(context: LaunchContext, launch: LaunchFile) -> list:
    values = {a.name: LaunchConfiguration(a.name).perform(context)
              for a in launch.all_arguments}
    nodes = [Node(package=spec.package, executable=spec.executable, name=spec.name,
                  parameters=[_typed(p) for p in spec.parameters],
                  remappings=list(spec.remappings), arguments=list(spec.arguments),
                  respawn=spec.respawn, respawn_delay=spec.respawn_delay_s, output='screen')
             for spec in launch.node_specs(values)]
    actions = [SetEnvironmentVariable('ROS_AUTOMATIC_DISCOVERY_RANGE',
                                      DISCOVERY_RANGE[values['discovery']])]
    if values['namespace']:
        actions.append(PushRosNamespace(values['namespace']))
    return [GroupAction([*actions, *nodes])]
