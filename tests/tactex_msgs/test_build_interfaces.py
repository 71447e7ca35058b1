# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""tools/build_interfaces.py: a missing tool is named, the wheels' CMake files relocated."""

import importlib.util
from pathlib import Path
import shutil
import subprocess
import sys
import sysconfig

import numpy
import pytest

ROOT = Path(__file__).resolve().parents[2]
SPEC = importlib.util.spec_from_file_location('build_interfaces',
                                              ROOT / 'tools' / 'build_interfaces.py')
build_interfaces = importlib.util.module_from_spec(SPEC)
SPEC.loader.exec_module(build_interfaces)
HOST = ('/opt/python/cp311-cp311/include/python3.11;'
        '/opt/python/cp311-cp311/lib/python3.11/site-packages/numpy/_core/include')


def without(*missing, which=shutil.which):
    """A shutil.which that does not find the tools named."""
    return lambda name: None if name in missing else which(name)


@pytest.mark.parametrize(('missing', 'named'), [
    (('cmake',), 'cmake not found'),
    (('cc', 'gcc', 'clang'), 'C compiler not found'),
    (('c++', 'g++', 'clang++'), r'C\+\+ compiler not found'),
    (('make',), 'make not found'),
])
def test_a_missing_tool_is_named(monkeypatch, missing, named):
    monkeypatch.setattr(build_interfaces.shutil, 'which', without(*missing))
    with pytest.raises(build_interfaces.BuildError, match=named):
        build_interfaces.check_tools()


def test_an_old_cmake_is_refused(monkeypatch, tmp_path):
    fake = tmp_path / 'cmake'
    fake.write_text('#!/bin/sh\necho "cmake version 3.16.3"\n')
    fake.chmod(0o755)
    monkeypatch.setenv('PATH', f'{tmp_path}:/usr/bin:/bin')
    with pytest.raises(build_interfaces.BuildError, match=r'too old.*3\.16'):
        build_interfaces.check_tools()


def test_missing_python_headers_are_named(monkeypatch, tmp_path):
    monkeypatch.setattr(build_interfaces.sysconfig, 'get_paths', lambda: {'include': tmp_path})
    with pytest.raises(build_interfaces.BuildError, match=r'Python headers.*python3-dev'):
        build_interfaces.check_tools()


def test_the_command_exits_1_with_an_error_line(tmp_path):
    env = {'PATH': str(tmp_path)}  # nothing to be found
    result = subprocess.run([sys.executable, str(ROOT / 'tools' / 'build_interfaces.py'),
                             '--prefix', str(tmp_path)], capture_output=True, text=True,
                            env=env)
    assert result.returncode == 1
    assert result.stderr.startswith('error: cannot build tactex_msgs: cmake not found')


def test_host_include_directories_are_relocated_once(tmp_path):
    config = tmp_path / 'share' / 'std_msgs' / 'cmake' / 'export_pyExport.cmake'
    config.parent.mkdir(parents=True)
    config.write_text(f'set_target_properties(t PROPERTIES\n'
                      f'  INTERFACE_INCLUDE_DIRECTORIES "{HOST};{tmp_path}"\n)\n')
    assert build_interfaces.relocate_exported_targets(tmp_path) == [config]
    text = config.read_text()
    assert '/opt/python' not in text
    assert f'"{sysconfig.get_paths()["include"]};{numpy.get_include()};{tmp_path}"' in text
    assert build_interfaces.relocate_exported_targets(tmp_path) == []


def test_files_of_the_previous_install_are_removed(tmp_path):
    prefix, build = tmp_path / 'venv', tmp_path / 'venv' / 'build' / 'pkg'
    build.mkdir(parents=True)
    stale, outside = prefix / 'lib' / 'libold.so', tmp_path / 'keep.txt'
    stale.parent.mkdir()
    stale.write_text('')
    outside.write_text('')
    (build / 'install_manifest.txt').write_text(f'{stale}\n{outside}\n')
    assert build_interfaces.remove_previous_install(build, prefix) == 1
    assert not stale.exists() and outside.exists()
