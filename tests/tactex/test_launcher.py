# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Launch files as data, and `tactex launch`: the node sets, supervision and clean shutdown."""

import io
import os
from pathlib import Path
import re
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
from support.processes import alive, wait_for
from support.ros_launch import (
    launch_installed,
    load_description,
    stand_in_modules,
    started_by_ros_launch,
    started_by_stand_ins,
    yaml_typed,
)

from tactex import bringup
from tactex.launching.spec import (
    launch_directory,
    LaunchError,
    load_launch_file,
    NodeSpec,
    TF_IN_NAMESPACE,
    visualisation_nodes,
)
from tactex.launching.supervisor import Launcher, node_command, run_launch

ROOT = Path(__file__).resolve().parents[2]
LAUNCH_NAMES = sorted(p.name.removesuffix('.launch.py') for p in launch_directory().glob(
    '*.launch.py'))
TACTEX = [str(Path(sys.executable).parent / 'tactex')]


def _console_scripts(package: str) -> set[str]:
    setup = (ROOT / 'src' / package / 'setup.py').read_text(encoding='utf-8')
    return set(re.findall(r"'(\w+) = ", setup))


# Arguments some launch files need to start at all; every file is checked with each set.
NEEDED = {'classify': {'checkpoint': '/run/model'}, 'identify': {'bundle': '/run/bundle'}}
VARIANTS = {'probe': [{'sim': 'true'}], 'sweep': [{'sim': 'true'}],
            'classify': [{'source': 'sim'}],
            'identify': [{'sim': 'true'}],
            'system': [{'sim': 'true'}, {'sim': 'true', 'checkpoint': '/run/model'},
                       {'checkpoint': '/run/model'}, {'sim': 'true', 'bundle': '/run/bundle'}]}


def _cases(variants: dict[str, list[dict]], plain: bool) -> list:
    return [pytest.param(name, {**NEEDED.get(name, {}), **variant},
                         id=' '.join([name, *(f'{k}:={v}' for k, v in variant.items())]))
            for name in LAUNCH_NAMES for variant in [{}] * plain + variants.get(name, [])]


CASES = _cases(VARIANTS, plain=True)
# What the ROS 2 translation must carry too: namespaces, the viewer, typed values.
ROS_CASES = _cases({
    'system': [{'sim': 'true', 'namespace': 'left_arm', 'rviz': 'true', 'rate_factor': '3',
                'checkpoint': '/run/model', 'threshold': '1', 'probe_on_start': 'true'},
               {'namespace': '/robots/left/', 'discovery': 'subnet', 'sensor_port': '/dev/a'}],
    'classify': [{'source': 'sim', 'robot': 'false', 'namespace': 'a'}],
    'probe': [{'robot': 'false', 'pathway_file': '/data/p.json'}],
    'sim': [{'patch_texture': 'wood', 'scene': '1.0'}]}, plain=False)


def test_every_launch_file_is_checked():
    assert set(LAUNCH_NAMES) >= {'arm', 'classify', 'probe', 'sensor', 'sim', 'sweep', 'system'}
    assert set(NEEDED) | set(VARIANTS) <= set(LAUNCH_NAMES)


@pytest.mark.parametrize(('name', 'arguments'), CASES)
def test_every_launch_file_declares_nodes_that_exist(name, arguments):
    launch = load_launch_file(name)
    nodes = launch.node_specs(arguments)
    assert nodes
    for spec in nodes:
        assert spec.executable in _console_scripts(spec.package), spec
        node_command(spec)  # the executable is installed


def _started_by_tactex_launch(name: str, arguments: dict[str, str]) -> list[tuple]:
    launch = load_launch_file(name)
    namespace = launch.resolve(arguments)['namespace'].strip('/')
    return [(spec.package, spec.executable, spec.name, namespace,
             [p if isinstance(p, str) else {k: yaml_typed(v) for k, v in p.items()}
              for p in spec.parameters]) for spec in launch.node_specs(arguments)]


def _started_by_ros2_launch(name: str, arguments: dict[str, str], monkeypatch) -> list[tuple]:
    """On ROS 2 launch where it is installed, else on its stand-ins (tests/support)."""
    path = launch_directory() / f'{name}.launch.py'
    if launch_installed():
        return started_by_ros_launch(load_description(path), arguments)
    for module_name, module in stand_in_modules().items():
        monkeypatch.setitem(sys.modules, module_name, module)
    monkeypatch.setitem(sys.modules, 'tactex.launching.ros_description', None)
    monkeypatch.delitem(sys.modules, 'tactex.launching.ros_description')
    return started_by_stand_ins(load_description(path), arguments)


@pytest.mark.parametrize(('name', 'arguments'), CASES + ROS_CASES)
def test_ros2_launch_starts_what_tactex_launch_starts(name, arguments, monkeypatch):
    """One source: the generated ROS 2 description starts the very nodes, named alike.

    Both check the hardware nodes they start first, with tactex doctor's checks, once.
    """
    checked = []
    monkeypatch.setattr(bringup, 'not_ready_lines',
                        lambda nodes: checked.append([spec.name for spec in nodes]) or [])
    started = _started_by_ros2_launch(name, arguments, monkeypatch)
    assert started == _started_by_tactex_launch(name, arguments)
    assert checked == [[node[2] for node in started]]


@pytest.mark.parametrize('checks', ['true', 'false'])
def test_ros2_launch_of_hardware_that_is_not_ready_starts_no_node_unless_told(
        monkeypatch, tmp_path, checks):
    arguments = {'sensor_port': str(tmp_path / 'ttyACM0'), 'arm_port': str(tmp_path / 'ttyUSB0'),
                 'checks': checks}
    if checks == 'true':
        with pytest.raises(RuntimeError, match=r'^the hardware is not ready .* checks:=false'):
            _started_by_ros2_launch('robot', arguments, monkeypatch)
    else:
        assert _started_by_ros2_launch('robot', arguments, monkeypatch)


def _names(name: str, **arguments: str) -> list[str]:
    return [spec.name for spec in load_launch_file(name).node_specs(arguments)]


def test_system_launch_starts_the_robot_probe_sweep_and_with_a_checkpoint_the_classifier():
    sim = ['mujoco_bridge', 'madgwick_node', 'probe_node', 'sweep_node']
    hardware = ['teensy_node', 'madgwick_node', 'arm_driver', 'probe_node', 'sweep_node']
    assert _names('system', sim='true') == sim
    assert _names('system', sim='true', checkpoint='/run/model') == [*sim, 'classifier_node']
    assert _names('system') == hardware
    assert _names('system', checkpoint='/run/model', rviz='true') == [
        *hardware, 'classifier_node', 'robot_state_publisher', 'rviz2']
    assert _names('system', sim='true', bundle='/run/bundle') == [*sim, 'identify_node']


def test_identify_launch_passes_the_bundle_the_movements_and_the_clock():
    spec, = load_launch_file('identify').node_specs({'bundle': '/run/bundle', 'sim': 'true'})
    given = {k: v for layer in spec.parameters if isinstance(layer, dict)
             for k, v in layer.items()}
    assert given['bundle'] == '/run/bundle' and given['use_sim_time'] in (True, 'true')
    assert given['movements'].endswith('config/movements.yaml')


@pytest.mark.parametrize('sim', ['true', 'false'])
def test_the_viewers_run_on_the_clock_their_messages_are_stamped_with(sim):
    arguments = {'sim': sim, 'view': 'true', 'rviz': 'true'}
    for spec in load_launch_file('robot').node_specs(arguments):
        if spec.name in ('view_node', 'robot_state_publisher', 'rviz2'):
            given = {k: v for layer in spec.parameters if isinstance(layer, dict)
                     for k, v in layer.items()}
            assert given['use_sim_time'] is (sim == 'true'), spec.name
    sensor = load_launch_file('sensor').node_specs({'rviz': 'true'})  # no sim argument
    assert all({'use_sim_time': False} in spec.parameters or spec.package != 'rviz2'
               for spec in sensor)


def test_system_launch_passes_its_arguments_to_the_launch_files_it_includes():
    arguments = {'sim': 'true', 'checkpoint': '/run/model', 'recording_root': '/data/bags',
                 'pathway_file': '/data/pathway.json', 'patch_texture': 'wood',
                 'rate_factor': '3', 'threshold': '1', 'runtime': 'onnxruntime'}
    nodes = {spec.name: spec for spec in load_launch_file('system').node_specs(arguments)}

    def parameters(name: str) -> dict:
        merged = {}
        for item in nodes[name].parameters:
            merged.update(item if isinstance(item, dict) else {})
        return merged
    assert parameters('mujoco_bridge') == {'scene': 'uneven_texture', 'rate_factor': 3.0,
                                           'patch_texture': 'wood'}
    assert parameters('probe_node')['pathway_file'] == '/data/pathway.json'
    assert parameters('sweep_node')['recording_root'] == '/data/bags'
    assert parameters('classifier_node') == {'checkpoint': '/run/model', 'threshold': 1.0,
                                             'runtime': 'onnxruntime', 'use_sim_time': True}
    assert all(parameters(name)['use_sim_time'] is True for name in
               ('madgwick_node', 'probe_node', 'sweep_node'))
    with pytest.raises(LaunchError, match="rate_factor:='fast' is not a finite number"):
        load_launch_file('system').node_specs({'sim': 'true', 'rate_factor': 'fast'})


def test_a_launch_file_without_its_robot_starts_only_its_own_node():
    assert _names('probe', robot='false') == ['probe_node']
    assert _names('sweep', robot='false', sim='true') == ['sweep_node']
    assert _names('classify', robot='false', checkpoint='/run/model') == ['classifier_node']
    assert _names('classify', source='sim', checkpoint='/run/model') == [
        'mujoco_bridge', 'classifier_node']


def test_a_required_argument_is_named_when_missing_or_empty():
    for given in ({}, {'checkpoint': ''}):
        with pytest.raises(LaunchError, match=r'checkpoint:=\.\.\. is required: checkpoint '
                                              r'folder \(RUN/model/ of tactex train\)'):
            load_launch_file('classify').node_specs(given)


def test_the_pathway_file_default_is_the_one_of_the_probe_parameters():
    configured = re.search(r'pathway_file: (\S+)', (ROOT / 'config' / 'probe.yaml').read_text(
        encoding='utf-8')).group(1)
    for name in ('probe', 'system'):
        assert load_launch_file(name).argument('pathway_file').default == configured


def test_an_include_hands_over_only_what_it_names():
    """The included file's other arguments keep its own defaults, not the includer's."""
    bridge = {spec.name: spec for spec in load_launch_file('classify').node_specs(
        {'checkpoint': '/run/model', 'source': 'sim'})}['mujoco_bridge']
    assert bridge.parameters[0]['scene'] == 'uneven_texture'
    probe_scene = {spec.name: spec for spec in load_launch_file('probe').node_specs(
        {'sim': 'true'})}['mujoco_bridge'].parameters[0]['scene']
    assert probe_scene == 'probe'


def test_unknown_arguments_and_bad_choices_are_refused_with_the_known_ones():
    launch = load_launch_file('sim')
    with pytest.raises(LaunchError, match='takes: checks, discovery, namespace, patch_texture, '
                                          'rate_factor, rviz, scene'):
        launch.resolve({'scen': 'probe'})
    with pytest.raises(LaunchError, match='localhost, subnet'):
        launch.resolve({'discovery': 'internet'})
    with pytest.raises(LaunchError, match='known: arm'):
        load_launch_file('nonexistent')


def test_node_command_applies_name_namespace_parameters_and_remappings():
    spec = NodeSpec('tactex_sensor', 'madgwick_node', 'filter',
                    parameters=('/x/sensor.yaml', {'gain': 0.2, 'use_mag': True,
                                                   'ids': [1, 2], 'frame': ''}),
                    remappings=(('tactile/imu/data', 'imu'),))
    command = node_command(spec, namespace='/left_arm/')
    assert command[1:] == ['--ros-args', '-r', '__node:=filter', '-r', '__ns:=/left_arm',
                           '--params-file', '/x/sensor.yaml', '-p', 'gain:=0.2',
                           '-p', 'use_mag:=true', '-p', 'ids:=[1, 2]', '-p', 'frame:=""',
                           '-r', 'tactile/imu/data:=imu']


def _pids(output: str) -> dict[str, int]:
    return {name: int(pid) for name, pid in
            re.findall(r'\[launch\] started (\S+) \(pid (\d+)\)', output)}


def _start_launch(*arguments: str, log: Path) -> subprocess.Popen:
    return subprocess.Popen(TACTEX + ['launch', *arguments], stdout=log.open('w'),
                            stderr=subprocess.STDOUT, env=dict(os.environ, PYTHONUNBUFFERED='1'))


@pytest.mark.ros
def test_sim_launch_runs_in_its_namespace_and_stops_cleanly_on_sigterm(ros_context, tmp_path):
    import rclpy
    from rclpy.qos import qos_profile_sensor_data
    from sensor_msgs.msg import Imu

    log = tmp_path / 'launch.log'
    launcher = _start_launch('sim', 'rate_factor:=2.0', 'namespace:=left_arm', log=log)
    node = rclpy.create_node('launch_probe', context=ros_context)
    filtered = []
    node.create_subscription(Imu, '/left_arm/tactile/imu/data', filtered.append,
                             qos_profile_sensor_data)
    executor = rclpy.executors.SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    deadline = time.monotonic() + 30
    while len(filtered) < 20 and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.05)
    node.destroy_node()
    assert len(filtered) >= 20, log.read_text()
    assert filtered[-1].orientation_covariance[0] != -1.0  # the filter's output, namespaced
    pids = _pids(log.read_text())
    assert set(pids) == {'mujoco_bridge', 'madgwick_node'}
    launcher.send_signal(signal.SIGTERM)
    assert launcher.wait(timeout=10) == 0
    assert not [name for name, pid in pids.items() if alive(pid)]


def _descendants(pid: int) -> set[int]:
    """Every process below `pid` in the process tree (children of all its threads)."""
    found, todo = set(), [pid]
    while todo:
        parent = todo.pop()
        for task in Path(f'/proc/{parent}/task').glob('*'):
            try:
                children = (task / 'children').read_text().split()
            except OSError:
                continue
            for child in map(int, children):
                if child not in found:
                    found.add(child)
                    todo.append(child)
    return found


@pytest.mark.ros
def test_killing_the_launcher_leaves_no_orphaned_process(tmp_path):
    log = tmp_path / 'launch.log'
    launcher = _start_launch('system', 'sim:=true', f'recording_root:={tmp_path}/bags',
                             f'pathway_file:={tmp_path}/pathway.json', log=log)
    assert wait_for(lambda: len(_pids(log.read_text())) == 4, 30), log.read_text()
    tree = _descendants(launcher.pid)
    assert set(_pids(log.read_text()).values()) <= tree
    launcher.kill()  # SIGKILL: the launcher cannot clean up; the kernel tells the nodes
    launcher.wait()
    assert wait_for(lambda: not any(alive(pid) for pid in tree), 10), \
        [open(f'/proc/{pid}/cmdline').read() for pid in tree if alive(pid)]


@pytest.mark.ros
@pytest.mark.slow
def test_probe_launch_in_simulation_broadcasts_contacts_with_the_surface_normals(tmp_path):
    from transforms3d.quaternions import quat2mat

    from tactex.demo.session import ProbeLine, SystemClient
    from tactex_sim.scene import load_scene, resolve_scene

    log = tmp_path / 'launch.log'
    launcher = _start_launch('probe', 'sim:=true', 'rate_factor:=0.5',
                             f'pathway_file:={tmp_path}/pathway.json', log=log)
    try:
        with SystemClient() as client:
            client.wait_ready(60, sweep=False, alive=lambda: launcher.poll() is None)
            result, pathway, contacts = client.probe(ProbeLine(0.185, 0.01, 0.01), 280,
                                                     alive=lambda: launcher.poll() is None)
    finally:
        launcher.send_signal(signal.SIGTERM)
        code = launcher.wait(timeout=15)
    assert code == 0, log.read_text()[-3000:]
    assert list(result.outcomes) == [0, 0], log.read_text()[-3000:]
    assert len(contacts.poses) == len(pathway.contacts) == 2
    surface = load_scene(resolve_scene('probe')).surface
    for pose in contacts.poses:  # the z axis of each pose is the outward normal
        q = pose.orientation
        normal = quat2mat([q.w, q.x, q.y, q.z])[:, 2]
        nx, nz = surface.normal(pose.position.x)
        assert np.degrees(np.arccos(min(1.0, nx * normal[0] + nz * normal[2]))) < 8.0
        assert abs(pose.position.z - surface.height(pose.position.x)) < 0.002
    assert not [pid for pid in _pids(log.read_text()).values() if alive(pid)]


@pytest.mark.ros
def test_a_node_that_fails_at_start_stops_the_others_cleanly_with_one_line():
    # The bridge and probe_node are still starting (or just up) when madgwick_node fails.
    refused = NodeSpec('tactex_sensor', 'madgwick_node', 'madgwick_node',
                       parameters=({'gain': -1.0},))
    nodes = [NodeSpec('tactex_sim', 'mujoco_bridge', 'mujoco_bridge'), refused,
             NodeSpec('tactex_probe', 'probe_node', 'probe_node')]
    out = io.StringIO()
    assert run_launch(nodes, {}, out=out) == 1
    output = out.getvalue()
    assert [line for line in output.splitlines() if 'error' in line] == [
        '[madgwick_node] error: madgwick_node: parameter gain:=-1.0 is out of range; allowed: '
        'a float from 0.0 to 10.0',
        '[launch] error: node madgwick_node exited with code 1; stopped the others']
    assert not any(trace in output for trace in ('Traceback', 'KeyboardInterrupt', 'RCLError'))
    assert not [name for name, pid in _pids(output).items() if alive(pid)]


@pytest.mark.parametrize('arguments', [['sim', 'rate_factor:=-1'],
                                       ['system', 'sim:=true', 'checkpoint:=/no/such/model']],
                         ids=['bad rate_factor', 'checkpoint that cannot load'])
def test_a_bad_launch_argument_starts_no_node(tmp_path, arguments):
    run = subprocess.run(TACTEX + ['launch', *arguments], capture_output=True, text=True,
                         timeout=60)
    assert run.returncode == 1
    assert run.stdout == ''
    assert len(run.stderr.splitlines()) == 1 and run.stderr.startswith('error: '), run.stderr


@pytest.mark.ros
def test_a_respawning_node_is_restarted(tmp_path):
    lines = []

    class Lines:
        def write(self, text):
            lines.append(text)

        def flush(self):
            pass

    dying = NodeSpec('tactex_sim', 'mujoco_bridge', 'bridge',
                     parameters=({'scene': 'no_such_scene'},), respawn=True,
                     respawn_delay_s=0.1)
    launcher = Launcher([dying], out=Lines())
    launcher.start()
    assert launcher.supervise(until=lambda: launcher.restarts('bridge') >= 2) == 0
    assert sum('respawning' in line for line in lines) >= 2


@pytest.mark.ros
def test_a_urdf_parameter_reaches_the_node_as_the_same_text():
    import rclpy
    publisher, viewer = visualisation_nodes()
    urdf = publisher.parameters[0]['robot_description']
    spec = NodeSpec('tactex_sensor', 'madgwick_node', 'x', parameters=(publisher.parameters[0],))
    arguments = node_command(spec)[node_command(spec).index('--ros-args'):]
    context = rclpy.context.Context()
    rclpy.init(args=arguments, context=context)
    try:
        node = rclpy.create_node('x', context=context,
                                 automatically_declare_parameters_from_overrides=True)
        assert node.get_parameter('robot_description').value == urdf
        node.destroy_node()
    finally:
        rclpy.shutdown(context=context)
    assert viewer.arguments[0] == '-d' and viewer.arguments[1].endswith('tactex.rviz')


@pytest.mark.ros
@pytest.mark.parametrize('namespace, resolved', [('left_arm', '/left_arm/tf'), ('', '/tf')])
def test_the_visualisation_nodes_use_the_namespace_tf(namespace, resolved):
    import rclpy
    from std_msgs.msg import Empty
    publisher, viewer = visualisation_nodes()
    assert publisher.remappings == viewer.remappings == TF_IN_NAMESPACE
    spec = NodeSpec('tactex_sensor', 'madgwick_node', 'x', remappings=publisher.remappings)
    command = node_command(spec, namespace)
    context = rclpy.context.Context()
    rclpy.init(args=command[command.index('--ros-args'):], context=context)
    try:
        node = rclpy.create_node('x', context=context)
        assert node.create_publisher(Empty, '/tf', 1).topic_name == resolved
        assert node.create_publisher(Empty, '/tf_static', 1).topic_name == resolved + '_static'
        node.destroy_node()
    finally:
        rclpy.shutdown(context=context)
