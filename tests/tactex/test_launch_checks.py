# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Every launch argument is checked before any node starts (tactex.launching.arguments).

The bad value of each argument, through `tactex launch`, is in badinputs.py; here: that
no argument goes unchecked, that the defaults pass, that the namespace rule is ROS's, and
that a refused movement file is one error line whatever the YAML parser had to say.
"""

import re

import pytest
from support.badinputs import MOVEMENT_FILES

from tactex.cli import main
from tactex.launching.arguments import check_arguments, CHECKS, NAMESPACE_MAX_LENGTH
from tactex.launching.spec import launch_directory, LaunchError, load_launch_file

LAUNCH_NAMES = sorted(p.name.removesuffix('.launch.py')
                      for p in launch_directory().glob('*.launch.py'))


@pytest.mark.parametrize('name', LAUNCH_NAMES)
def test_every_argument_has_choices_or_a_check(name):
    unchecked = [argument.name for argument in load_launch_file(name).all_arguments
                 if not argument.choices and argument.name not in CHECKS]
    assert not unchecked


@pytest.mark.parametrize('name', LAUNCH_NAMES)
def test_the_defaults_of_every_launch_file_pass_their_checks(name, tmp_path, monkeypatch):
    monkeypatch.setenv('HOME', str(tmp_path))  # pathway_file and recording_root lie in it
    monkeypatch.chdir(tmp_path)
    launch = load_launch_file(name)
    required = {a.name: 'given' for a in launch.all_arguments if a.default is None}
    values = launch.resolve(required)
    for argument in launch.all_arguments:
        if argument.name not in required and argument.name in CHECKS:
            CHECKS[argument.name](argument.name, values[argument.name])


NAMESPACES = ['', 'left_arm', '/left_arm', 'left_arm/', 'robots/left_arm', '_private', 'a1',
              'left-arm', '1arm', 'robots//left', 'robots/1', 'left arm', '~', 'a.b', 'ä',
              'x' * (NAMESPACE_MAX_LENGTH - 1), 'x' * NAMESPACE_MAX_LENGTH]


@pytest.mark.ros
@pytest.mark.parametrize('namespace', NAMESPACES, ids=[n[:20] or "''" for n in NAMESPACES])
def test_the_namespace_rule_is_the_one_of_ros(namespace):
    from rclpy.exceptions import InvalidNamespaceException
    from rclpy.validate_namespace import validate_namespace
    try:
        validate_namespace('/' + namespace.strip('/') if namespace.strip('/') else '/')
        valid = True
    except InvalidNamespaceException:
        valid = False
    launch = load_launch_file('sim')
    values = launch.resolve({'namespace': namespace})
    if valid:
        check_arguments(launch, values)
    else:
        with pytest.raises(LaunchError, match=r'namespace:=.* is not a ROS namespace'):
            check_arguments(launch, values)


@pytest.mark.parametrize('name, match', [
    ('unclosed.yaml', r"not a YAML movement file: line 3, column 1: expected ',' or '}'"),
    ('laughs.yaml', 'line 1, column 13: a movement file takes no anchors or aliases'),
    ('twice.yaml', "line 2, column 1: key 'window' is given twice"),
])
def test_a_refused_movement_file_is_one_error_line(name, match, tmp_path, capsys):
    (tmp_path / 'bundle').mkdir()
    (tmp_path / 'bundle' / 'bundle.json').write_text('{}')
    (tmp_path / name).write_text(MOVEMENT_FILES[name])
    code = main(['launch', '--print', 'identify', f'bundle:={tmp_path / "bundle"}',
                 f'movements:={tmp_path / name}'])
    err = capsys.readouterr().err
    assert code == 1 and err.count('\n') == 1 and 'Traceback' not in err
    assert err.startswith(f"error: movements:='{tmp_path / name}': ")
    assert re.search(match, err), err
