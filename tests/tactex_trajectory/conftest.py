# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Fixtures of the sweep tests: the uneven scene's surface and pathways probed on it."""

import math

import numpy as np
import pytest

from tactex_sim.scene import load_scene, resolve_scene
from tactex_trajectory.simulated_sweeps import probe_like_pathway

# Where the bridge and the demo start the arm (joint1..joint4, gripper).
START_JOINTS = np.array([0.0, -0.3, 0.3, 1.2, 0.0])
SCENE = load_scene(resolve_scene('uneven_texture'))
SURFACE = SCENE.surface


NORMAL_SD = math.radians(2.0)
# A short pathway probed at x = 0.14-0.16 m (on the rising flank of the uneven plate) by
# probe_node in the simulator, and where the arm rested after probing it (joint1..joint4,
# gripper): the servos held a goal 2.6 mrad above at joints 2 and 3 (their sag), so a
# sweep's trajectory, planned from the measured joints, steps the arm by SAG_STEP (0.9 mm
# at the edge) as it arrives.
FLANK_POINTS = np.array([[0.13933, 0.0, 0.00988], [0.14966, 0.0, 0.01083],
                         [0.15995, 0.0, 0.01373]])
FLANK_NORMALS = np.array([[0.0332, 0.0010, 0.9994], [-0.1620, -0.0027, 0.9868],
                          [-0.2912, -0.0045, 0.9567]])
FLANK_REST = np.array([0.0011, -0.1689, 0.0994, 1.5386, 0.0])
SAG_STEP = np.array([0.0, 0.0026, 0.0026, 0.0002])


def wave_pathway(seed=0, *, step=0.01, start=0.085, end=0.22, position_sd=0.001,
                 normal_sd=NORMAL_SD):
    """Contacts on the uneven scene's wave, with probe-like noise."""
    return probe_like_pathway(SURFACE, start, end, step, np.random.default_rng(seed),
                              position_sd_m=position_sd, normal_sd_rad=normal_sd)


def truth_normals(x):
    """Outward normals (3-vectors) of the wave at world x."""
    slope = SURFACE.slope(np.asarray(x, dtype=float))
    normals = np.stack([-slope, np.zeros_like(slope), np.ones_like(slope)], axis=-1)
    return normals / np.linalg.norm(normals, axis=-1, keepdims=True)


@pytest.fixture(scope='module')
def clean_pathway():
    return wave_pathway(position_sd=0.0, normal_sd=0.0)
