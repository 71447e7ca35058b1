# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The Sweep goal that makes one movement on a probed pathway (identify_node, benches, demo).

A tactex_msgs/Pathway's usable contacts become arrays, `pathway_part.movement_part`
cuts the movement's part from them, and the goal carries that part with the movement's
speed, press depth, tilt and name.
"""

from __future__ import annotations

import numpy as np

from tactex_classify.identification.pathway_part import movement_part
from tactex_description.movements import Movement
from tactex_msgs.action import Sweep
from tactex_msgs.msg import Contact, Pathway


def probed_arrays(pathway: Pathway) -> tuple[np.ndarray, np.ndarray]:
    """(N x 3 positions, N x 3 normals) of the pathway's contacts that found the surface."""
    probed = [c for c in pathway.contacts if c.status == Contact.STATUS_OK]
    points = np.array([[c.position.x, c.position.y, c.position.z] for c in probed])
    normals = np.array([[c.normal.x, c.normal.y, c.normal.z] for c in probed])
    return points.reshape(-1, 3), normals.reshape(-1, 3)


def part_message(pathway: Pathway, points: np.ndarray, normals: np.ndarray) -> Pathway:
    """A Pathway of `points` and `normals` (contacts in order) with `pathway`'s header."""
    part = Pathway(header=pathway.header)
    for point, normal in zip(points.tolist(), normals.tolist(), strict=True):
        contact = Contact(header=pathway.header, status=Contact.STATUS_OK, confidence=1.0)
        contact.position.x, contact.position.y, contact.position.z = point
        contact.normal.x, contact.normal.y, contact.normal.z = normal
        part.contacts.append(contact)
    return part


def movement_goal(pathway: Pathway, movement: Movement, ramp_acceleration_m_s2: float, *,
                  label: str = '', trial: int = 0, record: bool = False) -> Sweep.Goal:
    """The Sweep goal of `movement` on its part of `pathway`.

    Raises:
        ValueError: the pathway cannot hold the movement and its speed ramps.
    """
    points, normals = probed_arrays(pathway)
    part_points, part_normals = movement_part(points, normals, movement,
                                              ramp_acceleration_m_s2)
    return Sweep.Goal(pathway=part_message(pathway, part_points, part_normals),
                      sliding_speed=movement.speed_m_s, edge_offset_angle=movement.edge_tilt_rad,
                      press_depth=movement.press_depth_m, label=label, trial=trial,
                      record=record, movement=movement.name)
