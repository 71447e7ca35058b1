# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The nodes a generated ROS 2 launch description starts, without starting them.

`started_nodes` walks a description the way `ros2 launch` executes it: arguments given
on the command line, then each action visited in order, conditions evaluated, includes
loaded, scopes pushed and popped. With ROS 2 launch installed it drives the real
launch and launch_ros actions; without (PyPI has neither), `stand_in_modules` provides
stand-ins written from their documented behaviour, so the comparison with `tactex
launch` runs on every machine. Each node comes back as (package, executable, name,
namespace, parameters), a parameter dict as the node would receive it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import importlib.util
import os
from pathlib import Path
import types

import yaml


def yaml_typed(value):
    """A one-line text value as ros2 launch and `--ros-args -p` type it."""
    if isinstance(value, str) and value and '\n' not in value:
        return yaml.safe_load(value)
    return value


def launch_installed() -> bool:
    """Whether ROS 2 launch (launch_ros) can be imported here."""
    return importlib.util.find_spec('launch_ros') is not None


def load_description(path: Path):
    """`generate_launch_description()` of a launch file."""
    spec = importlib.util.spec_from_file_location(f'described_{path.stem}', path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.generate_launch_description()


def started_by_ros_launch(description, arguments: dict[str, str]) -> list[tuple]:
    """The nodes the real ROS 2 launch would start (needs launch and launch_ros)."""
    from launch import LaunchContext
    from launch_ros.actions import Node

    context = LaunchContext()
    context.launch_configurations.update(arguments)
    nodes = []

    def visit(entity) -> None:
        if isinstance(entity, Node):
            if entity.condition is None or entity.condition.evaluate(context):
                entity._perform_substitutions(context)
                namespace, _, name = entity.node_name.rpartition('/')
                parameters = []
                for path, _ in entity._Node__expanded_parameter_arguments:
                    if Path(path).name.startswith('launch_params_'):  # a dict, dumped
                        (dumped,) = yaml.safe_load(Path(path).read_text()).values()
                        parameters.append(dumped['ros__parameters'])
                        Path(path).unlink()
                    else:
                        parameters.append(path)
                if namespace == Node.UNSPECIFIED_NODE_NAMESPACE:
                    namespace = ''
                nodes.append((entity.node_package, entity.node_executable, name,
                              namespace.strip('/'), parameters))
            return
        for sub_entity in entity.visit(context) or []:
            visit(sub_entity)

    visit(description)
    return nodes


# Stand-ins of the launch and launch_ros classes ros_description uses.

@dataclass
class _Context:
    configurations: dict
    namespace: str = ''
    environment: dict = field(default_factory=dict)
    nodes: list = field(default_factory=list)

    @property
    def launch_configurations(self) -> dict:
        return self.configurations


def _perform(value, context: _Context) -> str:
    return value if isinstance(value, str) else value.perform(context)


def _truth(text: str) -> bool:
    if text.lower() in ('true', '1'):
        return True
    if text.lower() in ('false', '0'):
        return False
    raise ValueError(f'condition {text!r} is neither true nor false')


class LaunchConfiguration:
    def __init__(self, name):
        self.name = name

    def perform(self, context):
        return context.configurations[self.name]


class EqualsSubstitution:
    negated = False

    def __init__(self, left, right):
        self.left, self.right = left, right

    def perform(self, context):
        same = _perform(self.left, context) == _perform(self.right, context)
        return 'true' if same != self.negated else 'false'


class NotEqualsSubstitution(EqualsSubstitution):
    negated = True


class IfElseSubstitution:
    def __init__(self, condition, if_value='', else_value=''):
        self.condition, self.if_value, self.else_value = condition, if_value, else_value

    def perform(self, context):
        chosen = self.if_value if _truth(_perform(self.condition, context)) else self.else_value
        return _perform(chosen, context)


class IfCondition:
    expected = True

    def __init__(self, predicate):
        self.predicate = predicate

    def evaluate(self, context):
        return _truth(_perform(self.predicate, context)) == self.expected


class UnlessCondition(IfCondition):
    expected = False


class _Action:
    def __init__(self, condition=None):
        self.condition = condition

    def run(self, context):
        if self.condition is None or self.condition.evaluate(context):
            self.execute(context)


class DeclareLaunchArgument(_Action):
    def __init__(self, name, *, description='', default_value=None, choices=None, **kwargs):
        super().__init__(**kwargs)
        self.name, self.default, self.choices = name, default_value, choices

    def execute(self, context):
        if self.name not in context.configurations:
            if self.default is None:
                raise ValueError(f'missing required argument {self.name!r}')
            context.configurations[self.name] = self.default
        if self.choices and context.configurations[self.name] not in self.choices:
            raise ValueError(f'{self.name} is not one of {self.choices}')


class SetEnvironmentVariable(_Action):
    def __init__(self, name, value, **kwargs):
        super().__init__(**kwargs)
        self.name, self.value = name, value

    def execute(self, context):
        context.environment[self.name] = _perform(self.value, context)


class PushROSNamespace(_Action):
    def __init__(self, namespace, **kwargs):
        super().__init__(**kwargs)
        self.namespace = namespace

    def execute(self, context):
        pushed = _perform(self.namespace, context).strip('/')
        context.namespace = '/'.join(p for p in (context.namespace, pushed) if p)


class GroupAction(_Action):
    def __init__(self, actions, *, scoped=True, **kwargs):
        super().__init__(**kwargs)
        self.actions, self.scoped = list(actions), scoped

    def execute(self, context):
        saved = (dict(context.configurations), context.namespace, dict(context.environment))
        for action in self.actions:
            action.run(context)
        if self.scoped:
            context.configurations, context.namespace, context.environment = (
                saved[0], saved[1], saved[2])


class OpaqueFunction(_Action):
    def __init__(self, *, function, args=(), **kwargs):
        super().__init__(**kwargs)
        self.function, self.args = function, list(args)

    def execute(self, context):
        for action in self.function(context, *self.args) or []:
            action.run(context)


class PythonLaunchDescriptionSource:
    def __init__(self, path):
        self.path = Path(path)


class IncludeLaunchDescription(_Action):
    def __init__(self, source, *, launch_arguments=(), **kwargs):
        super().__init__(**kwargs)
        self.source, self.arguments = source, list(launch_arguments)

    def execute(self, context):
        for name, value in self.arguments:
            context.configurations[name] = _perform(value, context)
        load_description(self.source.path).run(context)


class LaunchDescription(GroupAction):
    def __init__(self, entities):
        super().__init__(entities, scoped=False)


class ParameterValue:
    def __init__(self, value, *, value_type=None):
        self.value, self.value_type = value, value_type

    def typed(self, context):
        text = _perform(self.value, context)
        if self.value_type is str:
            return text
        if self.value_type is float:
            return float(text)
        return _truth(text) if self.value_type is bool else yaml_typed(text)


class Node(_Action):
    def __init__(self, *, package, executable, name, parameters=(), remappings=(),
                 arguments=(), respawn=False, respawn_delay=None, output=None, **kwargs):
        super().__init__(**kwargs)
        self.package, self.executable, self.name = package, executable, name
        self.parameters = list(parameters)

    def execute(self, context):
        def value(item):
            if isinstance(item, ParameterValue):
                return item.typed(context)
            return item if isinstance(item, (bool, int, float)) else yaml_typed(
                _perform(item, context))
        parameters = [item if isinstance(item, str) else
                      {name: value(v) for name, v in item.items()} for item in self.parameters]
        context.nodes.append((self.package, self.executable, self.name, context.namespace,
                              parameters))


def stand_in_modules() -> dict[str, types.ModuleType]:
    """Modules named as launch's and launch_ros's, holding the stand-ins above."""
    contents = {
        'launch': [LaunchDescription],
        'launch.actions': [DeclareLaunchArgument, GroupAction, IncludeLaunchDescription,
                           OpaqueFunction, SetEnvironmentVariable],
        'launch.conditions': [IfCondition, UnlessCondition],
        'launch.launch_description_sources': [PythonLaunchDescriptionSource],
        'launch.substitutions': [EqualsSubstitution, IfElseSubstitution, LaunchConfiguration,
                                 NotEqualsSubstitution],
        'launch_ros': [],
        'launch_ros.actions': [Node, PushROSNamespace],
        'launch_ros.parameter_descriptions': [ParameterValue]}
    modules = {}
    for name, classes in contents.items():
        module = types.ModuleType(name)
        for cls in classes:
            setattr(module, cls.__name__, cls)
        modules[name] = module
    return modules


def started_by_stand_ins(description, arguments: dict[str, str]) -> list[tuple]:
    """The nodes the stand-ins start for this description."""
    context = _Context(dict(arguments), environment=dict(os.environ))
    description.run(context)
    return context.nodes
