# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Node parameters: a refused value, at start or at run time, and a name no node declares.

At start (from -p or --params-file) a value a node refuses is one error line naming the
node, the parameter, the value and what is allowed, exit code 1 and no traceback. At run
time set_parameters refuses it with the reason. A given name the node does not declare
(a typo) is one warning naming the closest declared name.
"""

from pathlib import Path
import re
import signal
import subprocess
import sys

import pytest
from support.processes import wait_for

from tactex.launching.environment import ros_environment

pytestmark = [pytest.mark.integration, pytest.mark.ros]
BIN = Path(sys.executable).parent
# A hang guard, not a timing claim.
START_GUARD_S = 60

# (executable, -p arguments, the one error line, as a regex)
REFUSED_AT_START = [
    ('madgwick_node', ['gain:=-1.0'], r'madgwick_node: parameter gain:=-1\.0 is out of range; '
                                      r'allowed: a float from 0\.0 to 10\.0$'),
    ('probe_node', ['control_rate_hz:=0.0'], r'probe_node: parameter control_rate_hz:=0\.0 is '
                                             r'out of range; allowed: a float from 5\.0 to 500'),
    ('sweep_node', ['descent_speed:=-1.0'], r'sweep_node: parameter descent_speed:=-1\.0 is out '
                                            r'of range; allowed: a float from 1e-09 to 0\.1'),
    ('madgwick_node', ['gain:=fast'], r"madgwick_node: parameter gain:='fast' is text; "
                                      r'allowed: a float from 0\.0 to 10\.0'),
    ('probe_node', ['control_rate_hz:=0'], r'probe_node: parameter control_rate_hz:=0 is an '
                                           r'integer; allowed: a float from 5\.0'),
    ('madgwick_node', ['gain:=.nan'], r'gain:=nan is out of range'),
    ('mujoco_bridge', ['rate_factor:=-2.0'], r'mujoco_bridge: parameter rate_factor:=-2\.0 is '
                                             r'out of range; allowed: a float from 0\.0 to 1000'),
    ('mujoco_bridge', ['scene:=no_such_scene'], r"mujoco_bridge: parameter "
                                                r"scene:='no_such_scene' is refused; allowed: a "
                                                r'scene .*no scene file'),
    ('mujoco_bridge', ['patch_texture:=velvet'], r"patch_texture:='velvet' is refused; allowed: "
                                                 r"'' or a texture \(unknown texture 'velvet'; "
                                                 r'known: brocade fabric'),
    ('madgwick_node', ['world_frame:=ned'], r"world_frame:='ned' is refused; allowed: 'enu'"),
    ('probe_node', ['method:=sideways'], r'allowed: tip_then_face or face_only$'),
    ('arm_driver', ['torque_on_exit:=drop'], r'arm_driver: .* allowed: hold or release$'),
    ('arm_driver', ['servo_ids:=[1, 2]'], r'servo_ids:=\[1, 2\] is refused; allowed: 5 IDs'),
    # NaN would reach the servos as profile velocity 0: no limit at all.
    ('arm_driver', ['profile_velocity:=.nan'], r'profile_velocity:=nan is out of range; '
                                               r'allowed: a float from 0\.02\d* to 24\.5'),
    ('arm_driver', ['gripper_m_per_rad:=.inf'], r'gripper_m_per_rad:=inf is out of range'),
    ('arm_driver', ['max_backoff_s:=-1.0'], r'max_backoff_s:=-1\.0 is out of range'),
    ('arm_driver', ['baud:=123'], r'baud:=123 is refused; allowed: 9600, 57600, '),
    ('arm_driver', ['servo_ids:=[11, 12, 13, 14, 300]'], r'allowed: distinct IDs from 0 to 252$'),
    ('arm_driver', ['operating_modes:=[3, 3, 3, 3, 16]'], r'allowed: modes that hold a '
                                                          r'position: 3 or 5$'),
    ('recorder_node', ['output:=/tmp/never', 'split_s:=.nan'], r'split_s:=nan is out of range'),
    ('mujoco_bridge', ['initial_joints:=[0.0, -0.3, .nan, 1.2, 0.0]'],
     r'initial_joints:=.* is refused; allowed: joint1 from -2\.82743 to 2\.82743, '),
    ('teensy_node', ['baud:=0'], r'teensy_node: parameter baud:=0 is out of range'),
    ('probe_node', ['goal.start:=[0.1, .nan, 0.0]'], r'goal\.start:=.* is refused; allowed: '
                                                     r'start must be 3 finite numbers'),
    ('probe_node', ['goal.direction:=[1.0, 1.0, 0.0]'], r'goal\.direction:=.* is refused; '
                                                        r'allowed: direction must be a unit'),
    ('recorder_node', [], r"recorder_node: parameter output:='' is refused"),
    ('recorder_node', ['output:=/tmp/never', 'metadata:=not json'], r'allowed: a JSON object$'),
    ('teensy_node', ['diagnostics_period_s:=0.0'], r'teensy_node: parameter '
                                                   r'diagnostics_period_s:=0\.0 is out of range'),
    ('identify_node', ['settle_s:=-1.0'], r'identify_node: parameter settle_s:=-1\.0 is out of '
                                          r'range; allowed: a float from 0\.0 to 60'),
    ('classifier_node', ['threshold:=5.0'], r'classifier_node: parameter threshold:=5\.0 is out '
                                            r'of range; allowed: a float from 0\.0 to 1\.0$'),
    ('classifier_node', ['stall_s:=0.0'], r'classifier_node: parameter stall_s:=0\.0 is out of '
                                          r'range'),
]


def _run(command: list[str], log: Path) -> subprocess.Popen:
    with open(log, 'w') as out:
        return subprocess.Popen(command, env=ros_environment(), stdin=subprocess.DEVNULL,
                                stdout=out, stderr=subprocess.STDOUT)


def _refused(command: list[str], tmp_path: Path) -> str:
    """Run a node that must refuse its start; its only output line."""
    log = tmp_path / 'node.log'
    process = _run(command, log)
    try:
        code = process.wait(timeout=START_GUARD_S)
    finally:
        process.kill()
    output = log.read_text()
    assert code == 1, output
    assert len(output.splitlines()) == 1 and output.startswith('error: '), output
    return output.strip()


@pytest.mark.parametrize(('node', 'parameters', 'line'), REFUSED_AT_START,
                         ids=[f'{n} {" ".join(p)}' for n, p, _ in REFUSED_AT_START])
def test_a_refused_value_at_start_is_one_error_line_and_exit_1(tmp_path, node, parameters,
                                                                line):
    command = [str(BIN / node), '--ros-args', *(a for p in parameters for a in ('-p', p))]
    assert re.search(line, _refused(command, tmp_path))


def test_a_refused_value_from_a_parameter_file_is_the_same_one_line(tmp_path):
    params = tmp_path / 'params.yaml'
    params.write_text('/**/madgwick_node:\n  ros__parameters:\n    gain: -1.0\n')
    output = _refused([str(BIN / 'madgwick_node'), '--ros-args', '--params-file', str(params)],
                      tmp_path)
    assert output.endswith('parameter gain:=-1.0 is out of range; allowed: a float from 0.0 '
                           'to 10.0')


@pytest.mark.parametrize('given', [['-p', 'gian:=0.2'], ['--params-file', '{file}']],
                         ids=['-p', '--params-file'])
def test_a_parameter_no_node_declares_is_one_warning_naming_the_closest(tmp_path, given):
    params = tmp_path / 'params.yaml'
    params.write_text('/**/madgwick_node:\n  ros__parameters:\n    gian: 0.2\n')
    log = tmp_path / 'node.log'
    command = [str(BIN / 'madgwick_node'), '--ros-args',
               *(part.format(file=params) for part in given)]
    process = _run(command, log)
    try:
        assert wait_for(lambda: 'gian' in log.read_text(), START_GUARD_S), log.read_text()
        process.send_signal(signal.SIGTERM)
        assert process.wait(timeout=START_GUARD_S) == 0
    finally:
        process.kill()
    warnings = [line for line in log.read_text().splitlines() if 'gian' in line]
    assert len(warnings) == 1, log.read_text()
    assert warnings[0].startswith('[WARN]')
    assert warnings[0].endswith("unknown parameter 'gian' ignored; did you mean 'gain'?")


@pytest.fixture
def nodes(ros_context, tmp_path):
    """Every node that runs without a model, destroyed after the test."""
    made = _nodes(ros_context, tmp_path)
    yield made
    for node in made:
        node.destroy_node()


def _nodes(context, tmp_path):
    from rclpy.parameter import Parameter

    from tactex_classify.recording.recorder_node import RecorderNode
    from tactex_driver.arm_driver_node import ArmDriverNode
    from tactex_probe.probe_node import ProbeNode
    from tactex_sensor.madgwick_node import MadgwickNode
    from tactex_sensor.teensy_node import TeensyNode
    from tactex_sim.mujoco_bridge_node import MujocoBridgeNode
    from tactex_trajectory.sweep_node import SweepNode
    port = [Parameter('port', value=str(tmp_path / 'no_device'))]
    return [MadgwickNode(context=context), MujocoBridgeNode(context=context),
            ProbeNode(context=context), SweepNode(context=context),
            ArmDriverNode(context=context, parameter_overrides=port),
            TeensyNode(context=context, parameter_overrides=port),
            RecorderNode(context=context, parameter_overrides=[
                Parameter('output', value=str(tmp_path / 'recording'))])]


# Tunable text parameters, which their node's on-set callback checks, with a bad value.
CHECKED_BY_CALLBACK = {('mujoco_bridge', 'patch_texture'): 'velvet',
                       ('mujoco_bridge', 'fault'): 'meltdown'}
# Read-only numbers a node checks at start beyond what a range can say (REFUSED_AT_START).
CHECKED_AT_START = {('arm_driver', 'baud'), ('arm_driver', 'servo_ids'),
                    ('arm_driver', 'operating_modes'), ('mujoco_bridge', 'initial_joints'),
                    ('probe_node', 'goal.start'), ('probe_node', 'goal.direction')}


def _bad_values(node, name: str) -> list:
    """Values `name` must refuse: one of a wrong type, and one out of its range or rules."""
    from rcl_interfaces.msg import ParameterType
    descriptor = node.describe_parameter(name)
    wrong_type = 'text' if descriptor.type != ParameterType.PARAMETER_STRING else 1.5
    ranges = [*descriptor.floating_point_range, *descriptor.integer_range]
    beyond = [type(r.to_value)(r.to_value * 2 + 1) for r in ranges]
    callback = [CHECKED_BY_CALLBACK[(node.get_name(), name)]] if (
        node.get_name(), name) in CHECKED_BY_CALLBACK else []
    return [wrong_type, *beyond, *callback]


def test_every_tunable_parameter_and_every_number_has_a_range_or_a_check(nodes):
    from rcl_interfaces.msg import ParameterType as Type
    untyped = {Type.PARAMETER_BOOL}  # a bool has no range
    numbers = {Type.PARAMETER_DOUBLE, Type.PARAMETER_INTEGER, Type.PARAMETER_DOUBLE_ARRAY,
               Type.PARAMETER_INTEGER_ARRAY}
    for node in nodes:
        for name in node.list_parameters([], 0).names:
            descriptor = node.describe_parameter(name)
            if descriptor.type in untyped or (descriptor.read_only
                                              and descriptor.type not in numbers):
                continue
            checked = (descriptor.floating_point_range or descriptor.integer_range
                       or (node.get_name(), name) in CHECKED_BY_CALLBACK.keys()
                       | CHECKED_AT_START)
            assert checked, f'{node.get_name()}: {name} is unchecked'


def test_every_node_publishes_diagnostics_on_the_absolute_topic(nodes):
    for node in nodes:
        published = {(p.topic_name, p.msg_type.__name__) for p in node.publishers}
        assert ('/diagnostics', 'DiagnosticArray') in published, node.get_name()


def test_set_parameters_at_run_time_refuses_a_bad_value_with_the_reason(nodes):
    from rclpy.parameter import Parameter
    refused = 0
    for node in nodes:
        for name in node.list_parameters([], 0).names:
            if node.describe_parameter(name).read_only:
                continue
            before = node.get_parameter(name).value
            for value in _bad_values(node, name):
                result, = node.set_parameters([Parameter(name, value=value)])
                assert not result.successful, (node.get_name(), name, value)
                assert result.reason, (node.get_name(), name, value)
                assert node.get_parameter(name).value == before
                refused += 1
    assert refused >= 9  # gain, mag_timeout_s, patch_texture, fault, use_sim_time...


def test_the_madgwick_gain_out_of_range_at_run_time_names_the_range(ros_context):
    from rclpy.parameter import Parameter

    from tactex_sensor.madgwick_node import MadgwickNode
    node = MadgwickNode(context=ros_context)
    result, = node.set_parameters([Parameter('gain', value=-1.0)])
    node.destroy_node()
    assert not result.successful
    assert result.reason == 'Parameter gain out of range Min: 0.0, Max: 10.0, value: -1.0'


def test_spin_turns_a_refused_value_into_exit_1_and_warns_of_unknown_names(capfd):
    from rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor

    from tactex_common.ros import spin, TactexNode, warn_unknown_parameters

    class Tiny(TactexNode):
        def __init__(self):
            super().__init__('spin_parameter_test')
            self.declare_parameter('gain', 0.5, ParameterDescriptor(
                floating_point_range=[FloatingPointRange(from_value=0.0, to_value=1.0)]))
            assert warn_unknown_parameters(self) == ['gian']
            raise KeyboardInterrupt  # constructed: the test is done

    with pytest.raises(SystemExit) as exit_:
        spin(Tiny, ['--ros-args', '-p', 'gain:=2.0'])
    assert exit_.value.code == 1
    assert capfd.readouterr().err == ('error: spin_parameter_test: parameter gain:=2.0 is out '
                                      'of range; allowed: a float from 0.0 to 1.0\n')
    with pytest.raises(KeyboardInterrupt):
        spin(Tiny, ['--ros-args', '-p', 'gian:=0.2'])


@pytest.mark.parametrize('node', ['identify_node', 'sweep_node'])
def test_a_malformed_ros_argument_is_an_error_line_and_exit_1(tmp_path, node):
    log = tmp_path / 'node.log'
    process = _run([str(BIN / node), '--ros-args', '-p', 'bundle:='], log)
    try:
        code = process.wait(timeout=START_GUARD_S)
    finally:
        process.kill()
    output = log.read_text()
    assert code == 1 and 'Traceback' not in output, output
    assert output.splitlines()[-1].startswith("error: failed to initialize rcl: Couldn't parse "
                                              "parameter override rule: '-p bundle:='"), output
