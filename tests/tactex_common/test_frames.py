# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The frame names the config files spell are tactex_common.frames' names."""

import json
from pathlib import Path

import yaml

from tactex_common import frames

CONFIG = Path(__file__).parents[2] / 'config'


def _parameter(file: str, node: str, name: str):
    return yaml.safe_load((CONFIG / file).read_text())[f'/**/{node}']['ros__parameters'][name]


def test_the_nodes_frame_ids_are_the_sensor_and_the_edge():
    assert _parameter('sensor.yaml', 'teensy_node', 'frame_id') == frames.SENSOR
    assert _parameter('classify.yaml', 'classifier_node', 'frame_id') == frames.EDGE


def test_the_viewers_follow_the_arm_base():
    rviz = yaml.safe_load((CONFIG / 'tactex.rviz').read_text())
    assert rviz['Visualization Manager']['Global Options']['Fixed Frame'] == frames.BASE
    layout = (CONFIG / 'foxglove_layout.json').read_text()
    named = {value for key, value in _pairs(json.loads(layout)) if key in ('followTf',
                                                                             'frameId')}
    assert named == {frames.BASE}


def _pairs(tree):
    """Every (key, value) of a JSON tree."""
    if isinstance(tree, dict):
        for key, value in tree.items():
            yield key, value
            yield from _pairs(value)
    elif isinstance(tree, list):
        for value in tree:
            yield from _pairs(value)
