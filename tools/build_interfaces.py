# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Build the ament_cmake interface package tactex_msgs into a virtual environment.

`make test` and `make demo` run this after installing requirements.txt: the ROS 2
wheels there (ament_cmake, the rosidl generators, rclpy) make the virtual environment a
ROS prefix of its own: libraries in `<venv>/lib`, which the `ros_wheels_bootstrapper`
puts on the library path of every Python started from the venv, resources in
`<venv>/share`, Python packages in site-packages. tactex_msgs is installed the same way
(exactly as the `ros-std-msgs` wheel lays out std_msgs), so rclpy and rmw_fastrtps find
its Python classes and C typesupport libraries without LD_LIBRARY_PATH set by hand.

Steps:
1. Check the tools: cmake >= 3.20, a C and a C++ compiler, make and the Python headers;
   a missing one stops the build with a message naming it.
2. Point the exported CMake targets of the installed message wheels at this Python.
   The wheels were built elsewhere and their `export_*__rosidl_generator_pyExport.cmake`
   files name the build host's Python and NumPy include directories (for example
   /opt/python/cp311-cp311/include/python3.11), which CMake refuses as non-existent
   paths. Only such non-existent entries, and only inside the venv, are rewritten.
3. Configure, build and install with plain CMake (no colcon needed); the build tree
   lives in `<venv>/build/tactex_msgs`. Files that an earlier build installed are
   removed first, so a renamed or deleted interface leaves nothing stale behind.

On a full ROS 2 install none of this is needed: `colcon build` builds tactex_msgs.
"""

from __future__ import annotations

import argparse
from pathlib import Path
import re
import shutil
import subprocess
import sys
import sysconfig

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = 'tactex_msgs'
MIN_CMAKE = (3, 20)
_INCLUDE_DIRECTORIES = re.compile(r'(INTERFACE_INCLUDE_DIRECTORIES\s+")([^"]*)(")')


class BuildError(Exception):
    """The interface package cannot be built; the message says what is missing."""


def check_tools() -> str:
    """Return the cmake executable after checking every tool the build needs.

    Raises:
        BuildError: naming the first missing tool and how to get it.
    """
    cmake = shutil.which('cmake')
    if cmake is None:
        raise BuildError('cmake not found on PATH: install CMake >= 3.20 '
                         '(Debian: apt-get install cmake)')
    version = subprocess.run([cmake, '--version'], capture_output=True, text=True).stdout
    match = re.search(r'(\d+)\.(\d+)', version)
    if match is None or tuple(int(g) for g in match.groups()) < MIN_CMAKE:
        raise BuildError(f'cmake at {cmake} is too old ({version.splitlines()[0]!r}): '
                         'tactex_msgs needs CMake >= 3.20')
    for names, tool, package in ((('cc', 'gcc', 'clang'), 'C compiler', 'gcc'),
                                 (('c++', 'g++', 'clang++'), 'C++ compiler', 'g++'),
                                 (('make',), 'make', 'make')):
        if not any(shutil.which(name) for name in names):
            raise BuildError(f'{tool} not found on PATH (tried {", ".join(names)}): '
                             f'install one (Debian: apt-get install {package})')
    headers = Path(sysconfig.get_paths()['include']) / 'Python.h'
    if not headers.is_file():
        raise BuildError(f'Python headers not found ({headers} is missing): install the '
                         'development files of this Python (Debian: apt-get install '
                         'python3-dev)')
    return cmake


def _replacement(entry: str, python_include: str, numpy_include: str) -> str:
    """The existing directory standing in for a non-existent include directory."""
    if Path(entry).exists():
        return entry
    if re.search(r'/include/python3\.\d+$', entry):
        return python_include
    if entry.endswith('/numpy/_core/include') or entry.endswith('/numpy/core/include'):
        return numpy_include
    return entry


def relocate_exported_targets(prefix: Path) -> list[Path]:
    """Rewrite the wheel build host's Python include directories in `prefix`'s CMake files.

    Args:
        prefix: the virtual environment (only files under `prefix/share/*/cmake` change).

    Returns:
        The files rewritten (none on a second call).
    """
    import numpy
    python_include = sysconfig.get_paths()['include']
    numpy_include = numpy.get_include()
    changed = []
    for path in sorted(prefix.glob('share/*/cmake/*.cmake')):
        text = path.read_text(encoding='utf-8')
        if 'INTERFACE_INCLUDE_DIRECTORIES' not in text:
            continue

        def fix(match: re.Match) -> str:
            entries = [_replacement(e, python_include, numpy_include)
                       for e in match.group(2).split(';')]
            return match.group(1) + ';'.join(entries) + match.group(3)

        new_text = _INCLUDE_DIRECTORIES.sub(fix, text)
        if new_text != text:
            path.write_text(new_text, encoding='utf-8')
            changed.append(path)
    return changed


def remove_previous_install(build_dir: Path, prefix: Path) -> int:
    """Delete the files an earlier build installed into `prefix`; return how many."""
    manifest = build_dir / 'install_manifest.txt'
    if not manifest.is_file():
        return 0
    removed = 0
    for line in manifest.read_text(encoding='utf-8').splitlines():
        path = Path(line)
        if path.is_relative_to(prefix) and (path.is_file() or path.is_symlink()):
            path.unlink()
            removed += 1
    return removed


def build(prefix: Path, *, jobs: int = 2) -> None:
    """Configure, build and install tactex_msgs into `prefix`.

    Raises:
        BuildError: a tool is missing or a build step failed.
    """
    cmake = check_tools()
    relocate_exported_targets(prefix)
    source = ROOT / 'src' / PACKAGE
    build_dir = prefix / 'build' / PACKAGE
    remove_previous_install(build_dir, prefix)
    python = Path(sys.executable)
    steps = [
        [cmake, '-S', str(source), '-B', str(build_dir), '-G', 'Unix Makefiles',
         f'-DCMAKE_PREFIX_PATH={prefix}', f'-DCMAKE_INSTALL_PREFIX={prefix}',
         f'-DPython3_EXECUTABLE={python}', '-DCMAKE_BUILD_TYPE=Release',
         '-DBUILD_TESTING=OFF', '--log-level=WARNING'],
        [cmake, '--build', str(build_dir), '--parallel', str(jobs)],
        [cmake, '--install', str(build_dir)],
    ]
    for step in steps:
        result = subprocess.run(step, capture_output=True, text=True)
        if result.returncode != 0:
            output = (result.stdout + result.stderr)[-6000:]
            raise BuildError(f'{" ".join(step[:2])} ... failed (exit {result.returncode}):'
                             f'\n{output}')


def main(argv: list[str] | None = None) -> int:
    """Build tactex_msgs into the venv of the running Python (or --prefix); exit code."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--prefix', type=Path, default=Path(sys.prefix),
                        help='the virtual environment to install into (default: this one)')
    parser.add_argument('--jobs', type=int, default=2, help='parallel compile jobs')
    args = parser.parse_args(argv)
    try:
        build(args.prefix.resolve(), jobs=args.jobs)
    except BuildError as err:
        print(f'error: cannot build {PACKAGE}: {err}', file=sys.stderr)
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main())
