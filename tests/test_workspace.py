# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The workspace's own rules: package layout, pure cores, lint, headers, well-formed XML."""

import ast
from pathlib import Path
import re
import subprocess
import sys
from xml.etree import ElementTree as ET

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = sorted(p.name for p in (ROOT / 'src').iterdir() if (p / 'package.xml').is_file())
EXPECTED_PACKAGES = ['tactex', 'tactex_classify', 'tactex_common', 'tactex_description',
                     'tactex_driver', 'tactex_msgs', 'tactex_probe', 'tactex_sensor', 'tactex_sim',
                     'tactex_trajectory']
INTERFACE_PACKAGES = ['tactex_msgs']
PYTHON_PACKAGES = [p for p in EXPECTED_PACKAGES if p not in INTERFACE_PACKAGES]
PYTHON_FILES = sorted(p for folder in ('src', 'tests', 'bench', 'launch', 'tools')
                      for p in (ROOT / folder).rglob('*.py') if '.egg-info' not in str(p))
LAUNCH_FILES = sorted((ROOT / 'launch').glob('*.launch.py'))


# Modules that may import rclpy and ROS message packages: the nodes and the ROS helpers.
# Everything else under src/ is a pure module (no ROS install needed to import it).
ROS_FACING = frozenset({
    'tactex.bag_player',
    'tactex.demo.session',
    'tactex.goal_client',
    'tactex.launching.ros_description',
    'tactex.ros_client',
    'tactex.soak.session',
    'tactex.view.server',
    'tactex.view.view_node',
    'tactex_common.goals',
    'tactex_common.ros',
    'tactex_common.serving',
    'tactex_common.ticks',
    'tactex_classify.online.classifier_node',
    'tactex_classify.identification.identify_node',
    'tactex_classify.identification.movement_goals',
    'tactex_classify.online.tactile_topics',
    'tactex_classify.recording.recorder_node',
    'tactex_driver.arm_driver_node',
    'tactex_probe.messages',
    'tactex_probe.probe_node',
    'tactex_sensor.madgwick_node',
    'tactex_sensor.teensy_node',
    'tactex_sim.mujoco_bridge_node',
    'tactex_trajectory.sweep_node',
})
# Layers, bottom first: a package imports only packages of a lower layer (and itself).
LAYERS = {'tactex_common': 0, 'tactex_msgs': 0, 'tactex_description': 1, 'tactex_sensor': 2,
          'tactex_driver': 2, 'tactex_sim': 3, 'tactex_probe': 4, 'tactex_classify': 4,
          'tactex_trajectory': 5, 'tactex': 6}
# Top-level modules whose presence means ROS was imported (rclpy, generated interfaces).
ROS_MODULE = re.compile(r'^(rclpy|rosidl_.*|.*_(msgs|srvs|interfaces))$')


def _module_name(path: Path) -> str:
    package_root = path.relative_to(ROOT / 'src').parts[0]
    return '.'.join(path.relative_to(ROOT / 'src' / package_root).with_suffix('').parts)


SOURCE_MODULES = {_module_name(p): p for p in (ROOT / 'src').glob('*/*/**/*.py')
                  if p.name != 'setup.py' and '.egg-info' not in str(p)}
PURE_MODULES = sorted(name for name in SOURCE_MODULES
                      if name not in ROS_FACING and not name.endswith('__main__'))


def _imports(path: Path) -> set[str]:
    """Every module a source file imports (absolute names), at any depth in the file."""
    names = set()
    for node in ast.walk(ast.parse(path.read_text(encoding='utf-8'))):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            names.add(node.module)
            names.update(f'{node.module}.{alias.name}' for alias in node.names)
    return names


def test_every_package_of_the_design_exists():
    assert PACKAGES == EXPECTED_PACKAGES


def _manifest(package: str, build_type: str) -> ET.Element:
    """The package's package.xml (format 3, named after its folder, of `build_type`)."""
    manifest = ET.parse(ROOT / 'src' / package / 'package.xml').getroot()
    assert manifest.get('format') == '3'
    assert manifest.findtext('name') == package
    assert manifest.find('export').findtext('build_type') == build_type
    return manifest


@pytest.mark.parametrize('package', PYTHON_PACKAGES)
def test_package_is_ament_python_format_3(package):
    folder = ROOT / 'src' / package
    _manifest(package, 'ament_python')
    assert (folder / 'resource' / package).is_file()
    assert f'script_dir=$base/lib/{package}' in (folder / 'setup.cfg').read_text()
    assert (folder / package / '__init__.py').is_file()


@pytest.mark.parametrize('package', INTERFACE_PACKAGES)
def test_interface_package_is_ament_cmake_format_3(package):
    manifest = _manifest(package, 'ament_cmake')
    assert manifest.findtext('member_of_group') == 'rosidl_interface_packages'
    buildtool = {e.text for e in manifest.findall('buildtool_depend')}
    assert {'ament_cmake', 'rosidl_default_generators'} <= buildtool
    assert 'rosidl_default_runtime' in {e.text for e in manifest.findall('exec_depend')}
    assert not (ROOT / 'src' / package / 'setup.py').exists()


@pytest.mark.parametrize('package', INTERFACE_PACKAGES)
def test_every_interface_file_is_generated(package):
    folder = ROOT / 'src' / package
    files = sorted(str(p.relative_to(folder)) for kind in ('msg', 'srv', 'action')
                   for p in (folder / kind).glob(f'*.{kind}'))
    listed = re.search(r'rosidl_generate_interfaces\(\$\{PROJECT_NAME\}(.*?)\)',
                       (folder / 'CMakeLists.txt').read_text(), re.DOTALL).group(1)
    assert files and files == sorted(re.findall(r'\b(?:msg|srv|action)/\w+\.\w+', listed))


@pytest.mark.parametrize('package', EXPECTED_PACKAGES)
def test_manifest_passes_catkin_pkg_validation(package):
    # What colcon, rosdep and ament_cmake read it with (it checks the maintainer e-mail).
    from catkin_pkg.package import parse_package
    parse_package(ROOT / 'src' / package / 'package.xml').validate()


def test_every_interface_and_cmake_file_has_the_copyright_header():
    files = [p for folder in (ROOT / 'src').iterdir() for pattern in
             ('msg/*.msg', 'srv/*.srv', 'action/*.action', 'CMakeLists.txt')
             for p in folder.glob(pattern)]
    assert files
    missing = [str(p.relative_to(ROOT)) for p in files
               if not p.read_text(encoding='utf-8').startswith('# Copyright ')
               or 'SPDX-License-Identifier: Apache-2.0' not in p.read_text(encoding='utf-8')]
    assert not missing


def test_every_ros_facing_module_exists():
    assert ROS_FACING <= set(SOURCE_MODULES)


@pytest.mark.parametrize('module', PURE_MODULES)
def test_pure_module_imports_no_ros(module):
    code = (f'import importlib, re, sys; importlib.import_module({module!r}); '
            f'found = sorted(m for m in sys.modules if re.match({ROS_MODULE.pattern!r}, m)); '
            'print(found); sys.exit(1 if found else 0)')
    result = subprocess.run([sys.executable, '-c', code], capture_output=True, text=True)
    assert result.returncode == 0, f'{module} imports ROS: {result.stdout}{result.stderr[-2000:]}'


def test_packages_import_only_lower_layers():
    upward = []
    for name, path in SOURCE_MODULES.items():
        package = name.split('.')[0]
        for imported in _imports(path):
            other = imported.split('.')[0]
            if other in LAYERS and other != package and LAYERS[other] >= LAYERS[package]:
                upward.append(f'{name} imports {imported}')
    assert not upward


# tactex_classify's subpackages, lowest first: each imports only from those before it.
CLASSIFY_LAYERS = ('errors', 'exports', 'models', 'data', 'recording', 'training', 'online',
                   'evaluation', 'identification')


def test_classify_subpackages_import_only_those_below():
    upward = []
    for name, path in SOURCE_MODULES.items():
        parts = name.split('.')
        if parts[0] != 'tactex_classify' or len(parts) < 3:
            continue
        level = CLASSIFY_LAYERS.index(parts[1])
        for imported in _imports(path):
            other = imported.split('.')
            if other[0] == 'tactex_classify' and len(other) > 1 and other[1] != parts[1] \
                    and CLASSIFY_LAYERS.index(other[1]) > level:
                upward.append(f'{name} imports {imported}')
    assert not upward


def _module_imports(name: str) -> set[str]:
    """The workspace modules a source module imports, lazily or not (a package: its __init__)."""
    found = set()
    for imported in _imports(SOURCE_MODULES[name]):
        for candidate in (imported, f'{imported}.__init__'):
            if candidate in SOURCE_MODULES and candidate != name:
                found.add(candidate)
    return found


def test_no_import_cycle():
    # A cycle that a lazy import dodges at run time is still a cycle for the reader.
    graph = {name: _module_imports(name) for name in SOURCE_MODULES}
    cycles, state = [], {}

    def visit(name: str, path: list[str]) -> None:
        state[name] = 'open'
        for imported in sorted(graph[name]):
            if state.get(imported) == 'open':
                cycles.append(' -> '.join(path[path.index(imported):] + [imported]))
            elif imported not in state:
                visit(imported, path + [imported])
        state[name] = 'done'
    for name in sorted(graph):
        if name not in state:
            visit(name, [name])
    assert not cycles


def test_no_node_module_is_imported_by_another_module():
    # ROS-facing helpers that are not nodes (the launch builder, the demo's client, the
    # client commands' rclpy helper) may be imported, lazily, by the command that uses them.
    nodes = {name for name in ROS_FACING if name.endswith('_node')}
    offending = [f'{name} imports {imported}' for name, path in SOURCE_MODULES.items()
                 for imported in _imports(path)
                 if imported in nodes or (imported == 'tactex_common.ros'
                                          and name not in ROS_FACING)]
    assert not offending


def test_ruff_finds_nothing():
    result = subprocess.run([sys.executable, '-m', 'ruff', 'check', '--no-cache', str(ROOT)],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr


def test_no_source_file_passes_500_lines_unless_its_docstring_says_why():
    long = [f'{path.relative_to(ROOT)} ({count} lines)' for path in SOURCE_MODULES.values()
            if (count := len(path.read_text(encoding='utf-8').splitlines())) > 500
            and 'longer than 500 lines' not in (ast.get_docstring(ast.parse(
                path.read_text(encoding='utf-8'))) or '').lower()]
    assert not long


def test_every_python_file_has_the_copyright_header():
    missing = [str(p.relative_to(ROOT)) for p in PYTHON_FILES
               if not p.read_text(encoding='utf-8').startswith('# Copyright ')
               or 'SPDX-License-Identifier: Apache-2.0' not in p.read_text(encoding='utf-8')]
    assert not missing


def test_every_xml_file_is_well_formed():
    xml_files = [p for p in ROOT.rglob('*') if p.suffix in ('.xml', '.urdf', '.xacro')
                 and '.venv' not in p.parts and p.is_file()]
    assert xml_files
    for path in xml_files:
        ET.parse(path)


def test_every_module_has_a_one_line_docstring():
    for path in PYTHON_FILES:
        text = path.read_text(encoding='utf-8')
        body = text.split('\n', 2)[2].lstrip()
        assert body.startswith('"""'), f'{path.relative_to(ROOT)} has no module docstring'


def test_the_tests_mirror_the_packages():
    """One folder of tests per package (plus the firmware), helpers in tests/support/.

    Hard cases and end-to-end tests are marked (`hard_case`, `integration`), not put
    in folders of their own; at the top only the workspace's own rules, results and docs.
    """
    tests = ROOT / 'tests'
    folders = {p.name for p in tests.iterdir() if p.is_dir() and p.name != '__pycache__'}
    assert folders == {*PACKAGES, 'firmware', 'support'}
    top = {p.name for p in tests.glob('*.py')}
    assert top == {'conftest.py', 'test_workspace.py', 'test_results.py', 'test_docs.py'}
    helpers = [str(p.relative_to(tests)) for p in tests.rglob('*.py')
               if not p.name.startswith('test_') and p.name not in ('conftest.py',)
               and p.parent.name not in ('support', 'firmware')]
    assert not helpers
    hard = [p.name for p in tests.rglob('test_*_hard.py')
            if 'pytest.mark.hard_case' not in p.read_text(encoding='utf-8')]
    assert not hard


def test_launch_files_compile_and_define_a_description():
    assert LAUNCH_FILES
    for path in LAUNCH_FILES:
        source = path.read_text(encoding='utf-8')
        compile(source, str(path), 'exec')
        assert 'def generate_launch_description()' in source, path.name


# How a third-party import is declared in package.xml (rosdep keys; *-pip where the
# library is only on PyPI, as rosdep names them).
ROSDEP_KEYS = {'numpy': 'python3-numpy', 'scipy': 'python3-scipy', 'sklearn': 'python3-sklearn',
               'pandas': 'python3-pandas', 'matplotlib': 'python3-matplotlib',
               'serial': 'python3-serial', 'transforms3d': 'python3-transforms3d',
               'numba': 'python3-numba', 'rosbags': 'python3-rosbags-pip',
               'mujoco': 'python3-mujoco-pip', 'torch': 'python3-pytorch-pip',
               'ray': 'python3-ray-pip', 'skops': 'python3-skops-pip', 'onnx': 'python3-onnx-pip',
               'onnxruntime': 'python3-onnxruntime-pip', 'skl2onnx': 'python3-skl2onnx-pip',
               'tqdm': 'python3-tqdm', 'yaml': 'python3-yaml',
               'foxglove': 'python3-foxglove-sdk-pip', 'mcap': 'python3-mcap-pip',
               'lz4': 'python3-lz4', 'adjustText': 'python3-adjusttext-pip'}
STANDARD_LIBRARY = sys.stdlib_module_names | {'__future__'}


@pytest.mark.parametrize('package', EXPECTED_PACKAGES)
def test_package_xml_declares_every_import(package):
    declared = {element.text for element in
                ET.parse(ROOT / 'src' / package / 'package.xml').getroot()
                if element.tag in ('exec_depend', 'depend')}
    needed = set()
    for name, path in SOURCE_MODULES.items():
        if name.split('.')[0] != package:
            continue
        for imported in _imports(path):
            top = imported.split('.')[0]
            if top not in STANDARD_LIBRARY and top != package:
                needed.add(ROSDEP_KEYS.get(top, top))
    assert needed <= declared, f'undeclared in package.xml: {sorted(needed - declared)}'
