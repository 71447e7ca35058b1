# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The checked-in URDF is the generator's output and agrees with the geometry module."""

from xml.etree import ElementTree as ET

import pytest

from tactex.cli import main
from tactex_common.share import share_directory
from tactex_description.geometry import COMPLIANT_JOINT_NAMES, JointKind, OPEN_MANIPULATOR_X
from tactex_description.urdf import build_urdf

URDF_PATH = share_directory('tactex_description') / 'urdf' / 'open_manipulator_x_tactile.urdf'
DESIGN_FRAMES = ('world', 'base_link', 'link1', 'link2', 'link3', 'link4', 'link5',
                 'sensor_mount', 'sensor_link', 'sensor_edge')


@pytest.fixture(scope='module')
def urdf():
    return ET.parse(URDF_PATH).getroot()


def test_checked_in_urdf_is_the_generated_one():
    assert URDF_PATH.read_text(encoding='utf-8') == build_urdf(), 'run `make urdf`'


def test_check_command_detects_a_stale_urdf(tmp_path, capsys):
    stale = tmp_path / 'robot.urdf'
    stale.write_text(build_urdf().replace('joint3', 'elbow'), encoding='utf-8')
    assert main(['description', '--check-urdf', str(stale)]) == 1
    assert 'stale' in capsys.readouterr().err
    assert main(['description', '--check-urdf', str(URDF_PATH)]) == 0


def test_urdf_has_every_design_frame(urdf):
    links = {link.get('name') for link in urdf.iter('link')}
    assert set(DESIGN_FRAMES) <= links


def test_urdf_joint_limits_are_identical_to_the_geometry_module(urdf):
    joints = {joint.get('name'): joint for joint in urdf.iter('joint')}
    moving = [j for j in OPEN_MANIPULATOR_X.joints if j.kind is not JointKind.FIXED]
    assert {j.name for j in OPEN_MANIPULATOR_X.joints} == set(joints)
    for joint in moving:
        limit = joints[joint.name].find('limit')
        assert float(limit.get('lower')) == joint.lower
        assert float(limit.get('upper')) == joint.upper
        assert float(limit.get('velocity')) == joint.velocity
        assert float(limit.get('effort')) == joint.effort
        assert joints[joint.name].get('type') == joint.kind.value


def test_compliant_joints_are_three_revolute_and_one_prismatic(urdf):
    joints = {joint.get('name'): joint.get('type') for joint in urdf.iter('joint')}
    assert [joints[n] for n in COMPLIANT_JOINT_NAMES] == ['revolute', 'revolute', 'revolute',
                                                        'prismatic']
