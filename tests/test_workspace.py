# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The workspace's own rules: package layout, pure cores, lint, headers, well-formed XML."""

from pathlib import Path
import subprocess
import sys
from xml.etree import ElementTree as ET

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = sorted(p.name for p in (ROOT / 'src').iterdir() if (p / 'package.xml').is_file())
EXPECTED_PACKAGES = ['tactex', 'tactex_classify', 'tactex_common', 'tactex_description',
                     'tactex_driver', 'tactex_probe', 'tactex_sensor', 'tactex_sim',
                     'tactex_trajectory']
PYTHON_FILES = sorted(p for folder in ('src', 'tests', 'bench', 'launch')
                      for p in (ROOT / folder).rglob('*.py') if '.egg-info' not in str(p))
LAUNCH_FILES = sorted((ROOT / 'launch').glob('*.launch.py'))


def _is_adapter(path: Path) -> bool:
    """Nodes, launch files and the launcher may import rclpy; nothing else may."""
    name = path.name
    return name.endswith('_node.py') or name.endswith('.launch.py') or name == 'launcher.py'


def test_every_package_of_the_design_exists():
    assert PACKAGES == EXPECTED_PACKAGES


@pytest.mark.parametrize('package', EXPECTED_PACKAGES)
def test_package_is_ament_python_format_3(package):
    folder = ROOT / 'src' / package
    manifest = ET.parse(folder / 'package.xml').getroot()
    assert manifest.get('format') == '3'
    assert manifest.findtext('name') == package
    assert manifest.find('export').findtext('build_type') == 'ament_python'
    assert (folder / 'resource' / package).is_file()
    assert f'script_dir=$base/lib/{package}' in (folder / 'setup.cfg').read_text()
    assert (folder / package / '__init__.py').is_file()


@pytest.mark.parametrize('module', sorted(
    '.'.join(p.relative_to(ROOT / 'src' / p.relative_to(ROOT / 'src').parts[0])
             .with_suffix('').parts)
    for p in (ROOT / 'src').glob('*/*/**/*.py')
    if not _is_adapter(p) and p.name not in ('__main__.py', 'setup.py')))
def test_pure_module_does_not_import_rclpy(module):
    code = (f'import importlib, sys; importlib.import_module({module!r}); '
            "sys.exit(1 if 'rclpy' in sys.modules else 0)")
    result = subprocess.run([sys.executable, '-c', code], capture_output=True, text=True)
    assert result.returncode == 0, f'{module} imports rclpy\n{result.stderr[-2000:]}'


def test_ruff_finds_nothing():
    result = subprocess.run([sys.executable, '-m', 'ruff', 'check', '--no-cache', str(ROOT)],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr


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


def test_launch_files_compile_and_define_a_description():
    assert LAUNCH_FILES
    for path in LAUNCH_FILES:
        source = path.read_text(encoding='utf-8')
        compile(source, str(path), 'exec')
        assert 'def generate_launch_description()' in source, path.name
