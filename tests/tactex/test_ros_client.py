# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The client commands' ROS node: their command line is never read as ROS arguments."""

import sys

from std_msgs.msg import String

from tactex.ros_client import client_node


def test_a_value_with_colon_equals_on_the_command_line_is_no_remap_rule(monkeypatch, capfd):
    # `tactex bag play --remap OLD:=NEW` or `--wait-for a:=b`: rcl would take these from
    # sys.argv as global remap rules (and warn) if the client passed it on.
    monkeypatch.setattr(sys, 'argv', ['tactex', 'bag', 'play', 'chatter:=elsewhere',
                                      '__node:=renamed'])
    with client_node('tactex_test_client') as (node, _executor):
        assert node.get_name() == 'tactex_test_client'
        assert node.create_publisher(String, 'chatter', 1).topic_name == '/chatter'
    assert 'remap' not in capfd.readouterr().err
