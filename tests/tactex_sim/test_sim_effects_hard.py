# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Every simulation effect, with any options in its ranges, on any input the world makes."""

import math

from hypothesis import given, settings
from hypothesis import strategies as st
import mujoco
import numpy as np
import pytest
from support.hard_values import finite, vectors
from transforms3d.euler import euler2mat

from tactex_sim.effects import EFFECTS, Option, Reading
from tactex_sim.errors import SimError
from tactex_sim.inputs import Contact, Inputs
from tactex_sim.scene import load_scene, resolve_scene
from tactex_sim.textures import TEXTURES
from tactex_sim.world import PRESS_TRAVEL_M, World

pytestmark = pytest.mark.hard_case


def option_values(option: Option):
    """Any value the option accepts, its bounds included."""
    if option.choices:
        return st.sampled_from(option.choices)
    low = max(option.low, -1e6)
    high = min(option.high, 1e6)
    number = st.one_of(st.sampled_from([low, high]), st.floats(low, high))
    return st.tuples(*[number] * len(option.default)) if isinstance(
        option.default, tuple) else number


def unit_vectors():
    return vectors(st.floats(-1.0, 1.0)).filter(lambda v: np.linalg.norm(v) > 1e-3).map(
        lambda v: np.array(v) / np.linalg.norm(v))


@st.composite
def world_inputs(draw):
    """What the world can hand an effect: finite state, compression within the body.

    Contact points lie on the surface (a plate well within a kilometre); velocities and
    the sensor position are any finite values (a diverging arm).
    """
    touching = draw(st.booleans())
    force = draw(st.one_of(st.sampled_from([0.0, 1e300, 5e-324]), st.floats(0.0, 1e300)))
    contact = Contact(touching, np.array(draw(vectors(st.floats(-1e3, 1e3)))),
                      draw(unit_vectors()),
                      force) if touching else Contact(False, np.full(3, np.nan),
                                                      np.full(3, np.nan), 0.0)
    return Inputs(
        contact=contact, edge_velocity=np.array(draw(vectors(finite()))),
        texture=draw(st.one_of(st.none(), st.sampled_from(list(TEXTURES.values())))),
        sensor_rotation=euler2mat(*draw(vectors(st.floats(-math.pi, math.pi)))),
        sensor_position=np.array(draw(vectors(finite()))),
        sample_rate_hz=draw(st.floats(1.0, 2000.0)),
        sensor_filters_hz=draw(st.one_of(st.just((math.inf, math.inf)),
                                         st.tuples(st.floats(1.0, 1e4), st.floats(1.0, 1e4)))),
        compression_m=draw(st.floats(0.0, PRESS_TRAVEL_M)),
        time_s=draw(st.floats(0.0, 1e9)))


@pytest.mark.parametrize('name', list(EFFECTS))
@settings(max_examples=40)
@given(data=st.data())
def test_any_options_in_range_and_any_world_input_give_finite_channels(name, data):
    cls = EFFECTS[name]
    options = {key: data.draw(option_values(option), label=key)
               for key, option in cls.defaults.items()}
    effect = cls(np.random.default_rng(0), data.draw(st.floats(0.0, 10.0)), **options)
    for _ in range(data.draw(st.integers(1, 4))):  # state carries over between samples
        inputs = data.draw(world_inputs())
        reading = Reading(np.array(data.draw(vectors(st.floats(-1e3, 1e3)))),
                          np.array(data.draw(vectors(st.floats(-50.0, 50.0)))))
        reading.mag = np.array(data.draw(vectors(st.floats(-1e-2, 1e-2))))
        reading.pressure = data.draw(st.floats(0.0, 1e7))
        effect.apply(reading, inputs)
        for channel in cls.writes & {'accel', 'gyro', 'mag'}:
            assert np.all(np.isfinite(getattr(reading, channel))), channel
        for channel in cls.writes & {'pressure', 'temperature'}:
            assert math.isfinite(getattr(reading, channel)), channel


def test_a_diverged_physics_is_a_sim_error_not_a_silent_reset(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # MuJoCo logs the warning to MUJOCO_LOG.TXT here
    world = World(load_scene(resolve_scene('probe')))
    world.next_sample()
    world.data.qpos[0] = math.nan  # MuJoCo would reset the state and carry on
    with pytest.raises(SimError, match='diverged'):
        world.next_sample()
    assert world.data.warning[mujoco.mjtWarning.mjWARN_BADQPOS].number > 0


@pytest.mark.parametrize('target', [math.nan, math.inf])
def test_non_finite_controller_targets_are_a_sim_error(target):
    world = World(load_scene(resolve_scene('probe')))
    world.controller = lambda t: [target, 0.0, 0.0, 0.0, 0.0]
    world.next_sample()
    with pytest.raises(SimError, match='non-finite joint targets'):
        world.next_sample()
