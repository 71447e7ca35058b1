# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex param`: list, get and set a running node's parameters without the ros2 CLI."""

from pathlib import Path
import signal
import subprocess
import sys

import pytest
from support.processes import stop

from tactex.launching.environment import ros_environment

pytestmark = [pytest.mark.integration, pytest.mark.ros]
BIN = Path(sys.executable).parent


def tactex(*argv: str) -> subprocess.CompletedProcess:
    return subprocess.run([str(BIN / 'tactex'), 'param', *argv], capture_output=True,
                          text=True, env=ros_environment(), timeout=60)


@pytest.fixture(scope='module')
def madgwick(tmp_path_factory):
    """madgwick_node under the namespace `left`, as `tactex launch` would run it."""
    log = open(tmp_path_factory.mktemp('param') / 'madgwick.log', 'w')
    node = subprocess.Popen([BIN / 'madgwick_node', '--ros-args', '-r', '__ns:=/left'],
                            env=ros_environment(), stderr=log)
    try:
        for _ in range(30):  # discovery takes a moment
            if tactex('list', '/left/madgwick_node', '--timeout', '2').returncode == 0:
                break
        yield node
    finally:
        stop([node], signal.SIGINT)
        log.close()


def test_list_get_and_set_speak_to_the_node_in_its_namespace(madgwick):
    listed = tactex('list', 'madgwick_node', '--namespace', 'left')
    assert listed.returncode == 0 and 'gain' in listed.stdout.split()
    assert tactex('get', '/left/madgwick_node', 'gain').stdout.strip() == '0.04'
    assert tactex('set', 'madgwick_node', 'gain', '1', '--namespace', 'left').stdout.strip() \
        == 'set /left/madgwick_node gain to 1.0'  # an integer where a double is: taken as one
    assert tactex('get', '/left/madgwick_node', 'gain').stdout.strip() == '1.0'


@pytest.mark.parametrize('argv, message', [
    (('set', '/left/madgwick_node', 'gain', 'abc'), 'refused gain = abc: Wrong parameter type'),
    (('set', '/left/madgwick_node', 'gain', '-5'), 'refused gain = -5'),
    (('get', '/left/madgwick_node', 'nope'), "has no parameter 'nope'; see `tactex param list"),
    (('get', 'madgwick_node', 'gain', '--timeout', '1'), 'no node /madgwick_node answers'),
])
def test_a_refused_value_an_unknown_name_or_a_missing_node_is_one_error_line(madgwick, argv,
                                                                              message):
    result = tactex(*argv)
    assert result.returncode == 1 and 'Traceback' not in result.stderr
    assert result.stderr.startswith('error:') and message in result.stderr, result.stderr
