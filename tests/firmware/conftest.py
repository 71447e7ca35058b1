# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Fixtures of the firmware tests: host builds of the framing, the sensor maths and the sketch."""

from firmware_build import compile_cpp, CPP, FIRMWARE, FIRMWARE_SOURCES, MOCK, SKETCH
import pytest


def _program(tmp_path_factory, name, sources, include):
    program = tmp_path_factory.mktemp('firmware') / name
    compile_cpp(sources, include=include, output=program)
    return program


@pytest.fixture(scope='session')
def frame_tool(tmp_path_factory):
    """The firmware's framing code behind a command line (cpp/frame_tool.cpp)."""
    return _program(tmp_path_factory, 'frame_tool',
                    [CPP / 'frame_tool.cpp', FIRMWARE / 'tactex_frame.cpp'], [FIRMWARE])


@pytest.fixture(scope='session')
def sensor_tool(tmp_path_factory):
    """The firmware's sensor maths behind a command line (cpp/sensor_tool.cpp)."""
    return _program(tmp_path_factory, 'sensor_tool',
                    [CPP / 'sensor_tool.cpp', FIRMWARE / 'tactex_sensors.cpp'], [FIRMWARE])


@pytest.fixture(scope='session')
def sketch_sim(tmp_path_factory):
    """The sketch, compiled against the Arduino mock, inside a simulator of chips and host."""
    return _program(tmp_path_factory, 'sketch_sim',
                    [SKETCH, *FIRMWARE_SOURCES, MOCK / 'mock_arduino.cpp', CPP / 'sketch_sim.cpp'],
                    [MOCK, FIRMWARE])
