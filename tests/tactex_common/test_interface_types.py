# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""tactex_msgs for rosbags without ROS: every type, the same hashes as rosidl, clear errors."""

import json
import os
from pathlib import Path
import sys

import pytest

from tactex_common.interfaces import interface_directory, interface_types, typestore

ROOT = Path(__file__).resolve().parents[2]
SOURCE = ROOT / 'src' / 'tactex_msgs'
ACTION_TYPES = ('Goal', 'Result', 'Feedback', 'FeedbackMessage', 'SendGoal_Request',
                'SendGoal_Response', 'GetResult_Request', 'GetResult_Response')


def installed_share() -> Path:
    """The share directory the interface build installed (venv or colcon install)."""
    prefixes = [Path(sys.prefix)] + [
        Path(p) for p in os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep) if p]
    for prefix in prefixes:
        if (prefix / 'share' / 'tactex_msgs' / 'msg' / 'Contact.json').is_file():
            return prefix / 'share' / 'tactex_msgs'
    pytest.fail('tactex_msgs is not built: run `make test` (it builds it into .venv/)')


def test_every_message_and_action_type_is_registered():
    store = typestore()
    for name in ('Contact', 'Pathway', 'TextureEstimate'):
        assert f'tactex_msgs/msg/{name}' in store.types
    for action in ('Probe', 'Sweep'):
        for suffix in ACTION_TYPES:
            assert f'tactex_msgs/action/{action}_{suffix}' in store.types
    assert 'sensor_msgs/msg/Imu' in store.types  # the standard types stay


def test_constants_and_message_references_resolve():
    types = typestore().types
    assert types['tactex_msgs/msg/Contact'].STATUS_OK == 0
    assert types['tactex_msgs/msg/Contact'].STATUS_ESTIMATION_FAILED == 4
    assert types['tactex_msgs/action/Probe_Feedback'].PHASE_RETRACTING == 3
    fields = dict(interface_types()['tactex_msgs/action/Probe_Result'][1])
    assert fields['pathway'][1] == 'tactex_msgs/msg/Pathway'  # not .../action/Pathway


def test_hashes_equal_those_rosidl_generates():
    # Equal RIHS01 hashes: rosbags decodes exactly the types ROS 2 publishes.
    store = typestore()
    compared = 0
    for path in sorted(installed_share().glob('*/*.json')):
        for entry in json.loads(path.read_text())['type_hashes']:
            name = entry['type_name']
            if name.startswith('tactex_msgs/') and name in store.fielddefs:
                assert store.hash_rihs01(name) == entry['hash_string'], name
                compared += 1
    assert compared >= 3 + 2 * len(ACTION_TYPES)


def test_definitions_come_from_the_source_checkout_or_the_install():
    assert interface_directory() in (SOURCE, installed_share())
    assert set(interface_types(installed_share())) == set(interface_types(SOURCE))


def test_a_new_store_each_call_so_callers_may_add_types():
    first, second = typestore(), typestore()
    assert first is not second and first.types is not second.types


def test_missing_definitions_name_where_they_were_looked_for(tmp_path):
    with pytest.raises(FileNotFoundError, match='msg'):
        typestore(directory=tmp_path)


def test_an_action_without_three_sections_is_refused(tmp_path):
    (tmp_path / 'msg').mkdir()
    (tmp_path / 'action').mkdir()
    (tmp_path / 'action' / 'Bad.action').write_text('float64 a\n---\nfloat64 b\n')
    with pytest.raises(ValueError, match=r'Bad\.action.*3 sections'):
        interface_types(tmp_path)


def test_a_definition_that_does_not_parse_names_its_file(tmp_path):
    (tmp_path / 'msg').mkdir()
    (tmp_path / 'msg' / 'Broken.msg').write_text('flo@t a\n')
    with pytest.raises(ValueError, match=r'Broken\.msg'):
        interface_types(tmp_path)
