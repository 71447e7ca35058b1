# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex status`: every running node's diagnostics in one table, without the ros2 CLI."""

from pathlib import Path
import re
import subprocess
import sys

import pytest
from support.processes import stop

from tactex.commands.status import table
from tactex.launching.environment import ros_environment

BIN = Path(sys.executable).parent


def test_the_table_lists_each_status_by_name_with_its_level_message_and_values():
    lines = table({'b: node': (2, 'broken', {'rate_hz': '0.0'}),
                   'a: node': (0, 'fine', {'rate_hz': '120.0', 'drops': '0'})})
    assert lines[2].split() == ['a:', 'node', 'OK', 'fine']
    assert lines[3].split() == ['rate_hz=120.0,', 'drops=0']
    assert lines[4].split()[2:4] == ['ERROR', 'broken']
    assert table({}) == []


@pytest.mark.integration
@pytest.mark.ros
def test_status_shows_the_running_nodes_and_says_when_none_answers(tmp_path):
    env = ros_environment()
    nodes = [subprocess.Popen([BIN / 'teensy_node', '--ros-args', '-r', '__ns:=/left', '-p',
                               f'port:={tmp_path / "ttyNONE"}'], env=env,
                              stderr=subprocess.DEVNULL),
             subprocess.Popen([BIN / 'madgwick_node', '--ros-args', '-r', '__ns:=/left'],
                              env=env, stderr=subprocess.DEVNULL)]
    try:
        shown = subprocess.run([BIN / 'tactex', 'status', '--namespace', 'left',
                                '--duration', '6'], capture_output=True, text=True, env=env,
                               timeout=60)
        elsewhere = subprocess.run([BIN / 'tactex', 'status', '--namespace', 'right',
                                    '--duration', '1'],
                                   capture_output=True, text=True, env=env, timeout=60)
    finally:
        stop(nodes)
    assert shown.returncode == 0, shown.stderr
    assert re.search(r'/left/teensy_node: teensy +ERROR  disconnected', shown.stdout)
    assert '/left/madgwick_node: madgwick' in shown.stdout and 'rejected_gyro=0' in shown.stdout
    assert elsewhere.returncode == 1
    assert elsewhere.stderr.startswith('error: no diagnostics on /diagnostics from nodes under '
                                       '/right within 1 s')
