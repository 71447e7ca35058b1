# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Frame names of the design contract (base_link as REP-105 names it), one source for code.

The parameter files and viewer layouts under config/ spell them too; a test holds them to
these.
"""

WORLD = 'world'  # the simulator's fixed frame, parent of base_link
BASE = 'base_link'  # the arm's base: pathways, contacts, sweep plans
SENSOR = 'sensor_link'  # the MARG chip: IMU samples, the compliant body's attitude
EDGE = 'sensor_edge'  # the face rim point that slides in a sweep: the tool of a sweep
