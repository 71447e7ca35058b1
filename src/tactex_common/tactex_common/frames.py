# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Frame names of the design contract (REP-105): one source for nodes, models and files."""

WORLD = 'world'  # the simulator's fixed frame, parent of base_link
BASE = 'base_link'  # the arm's base: pathways, contacts, sweep plans
SENSOR = 'sensor_link'  # the MARG chip: IMU samples, the compliant body's attitude
EDGE = 'sensor_edge'  # the face rim point that slides in a sweep: the tool of a sweep
