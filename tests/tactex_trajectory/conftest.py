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
