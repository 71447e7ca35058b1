# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Compile the Teensy firmware's C++ with the host compiler and run the resulting programs."""

from __future__ import annotations

from pathlib import Path
import shutil
import subprocess

import pytest

ROOT = Path(__file__).resolve().parents[2]
FIRMWARE = ROOT / 'firmware' / 'teensy_tactile'
SKETCH = FIRMWARE / 'teensy_tactile.ino'
FIRMWARE_SOURCES = (FIRMWARE / 'tactex_frame.cpp', FIRMWARE / 'tactex_sensors.cpp')
CPP = Path(__file__).resolve().parent / 'cpp'
MOCK = CPP / 'arduino_mock'
CXXFLAGS = ('-std=c++17', '-Wall', '-Wextra', '-Werror')


def compiler() -> str:
    """Return the host C++ compiler, or skip the calling test when there is none."""
    found = shutil.which('g++') or shutil.which('c++')
    if found is None:
        pytest.skip('no C++ compiler (g++/c++) on PATH')
    return found


def compile_cpp(sources: list[Path], *, include: list[Path], flags: tuple[str, ...] = CXXFLAGS,
                output: Path | None = None) -> None:
    """Compile `sources` (an .ino as C++) into `output`, or only check them when it is None."""
    command = [compiler(), *flags, *(f'-I{folder}' for folder in include)]
    for source in sources:
        command += ['-x', 'c++', str(source), '-x', 'none'] if source.suffix == '.ino' \
            else [str(source)]
    command += ['-o', str(output)] if output else ['-fsyntax-only']
    result = subprocess.run(command, capture_output=True, text=True, check=False)
    assert result.returncode == 0, f'{" ".join(command)}\n{result.stderr}'


def run_sketch(program: Path, *args: str) -> tuple[bytes, dict[str, float]]:
    """Run the sketch simulator: the bytes the host received and the simulator's counters."""
    result = subprocess.run([str(program), *args], capture_output=True, check=False)
    stderr = result.stderr.decode()
    assert result.returncode == 0, stderr
    counters = {key: float(value) for key, _, value in
                (line.partition('=') for line in stderr.splitlines())}
    return result.stdout, counters
