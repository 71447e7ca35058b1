# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The simulator's hard cases: impacts, cell boundaries, the press limit, silence, repeats."""

import dataclasses
import math

import mujoco
import numpy as np
import pytest
from rosbags.highlevel import AnyReader
from test_scene import SCENES

from tactex_common import topics
from tactex_description.kinematics import inverse_kinematics
from tactex_sensor.messages import TYPESTORE
from tactex_sim.recording import SweepBag
from tactex_sim.scene import load_scene, parse_scene
from tactex_sim.sweep import plan_sweep, play, SweepParameters
from tactex_sim.textures import TEXTURES
from tactex_sim.world import World

SCENE = {p.stem: load_scene(p) for p in SCENES}


def pose_at(scene, x, depth, offset=0.5):
    """Joints putting the edge `depth` into the surface at x (negative: above it)."""
    surface = scene.surface
    slope = float(surface.slope(x))
    normal = surface.normal(x)
    point = np.array([x, float(surface.height(x))]) - depth * normal
    result = inverse_kinematics([point[0], 0.0, point[1]], math.pi / 2 - math.atan(slope)
                                - offset)
    assert result.reachable, result.detail
    return np.append(result.solutions[0], 0.0)


def run(world, seconds):
    samples = []
    while world.time_s < seconds:
        samples.append(world.next_sample())
    return samples


def test_resting_sensor_reads_gravity_and_nan_where_unsimulated():
    scene = dataclasses.replace(SCENE['probe'], effects=('contact', 'compliance'))
    world = World(scene)
    world.place_arm(pose_at(scene, 0.15, -0.03))
    sample = run(world, 0.5)[-1]
    assert abs(np.linalg.norm(sample.accel) - 9.81) < 0.05
    assert np.all(np.isnan(sample.mag)) and math.isnan(sample.pressure)


@pytest.mark.parametrize('name', sorted(SCENE))
def test_bag_stamps_of_every_scene_are_uniform_to_a_microsecond(name, tmp_path):
    # The physics step divides the sensor period: 350 Hz on 2 ms steps came out every
    # 2 or 4 ms, 120 Hz every 8 or 10 ms.
    scene = SCENE[name]
    world = World(scene, patch_texture='wood' if scene.patches else None)
    world.place_arm(pose_at(scene, 0.15, -0.03))
    assert world.model.opt.timestep <= scene.timestep_s
    with SweepBag(tmp_path / 'bag', {'label': 'wood'}, time_offset_ns=10**12) as bag:
        for _ in range(int(0.4 * scene.sensor_rate_hz)):
            bag.add(world.next_sample(), world.joint_positions(), world.joint_velocities(),
                    sliding=False)
    with AnyReader([tmp_path / 'bag'], default_typestore=TYPESTORE) as reader:
        imu = [c for c in reader.connections if c.topic == f'/{topics.IMU_RAW}']
        stamps = np.array([
            (lambda s: s.sec * 10**9 + s.nanosec)(reader.deserialize(raw, c.msgtype).header.stamp)
            for c, _, raw in reader.messages(connections=imu)], dtype=np.int64)
    assert stamps.size == int(0.4 * scene.sensor_rate_hz)
    period_ns = 1e9 / scene.sensor_rate_hz
    assert np.abs(np.diff(stamps) - period_ns).max() <= 1000
    assert abs(world.time_s - (stamps.size - 1) / scene.sensor_rate_hz) < 1e-9


def test_fast_impact_stays_finite_with_bounded_penetration():
    scene = SCENE['uneven_texture']
    world = World(scene, patch_texture='wood')
    world.place_arm(pose_at(scene, 0.15, -0.04))
    world.controller = lambda t: pose_at(scene, 0.15, 0.01)  # slam 5 cm in one step
    samples = run(world, 1.0)
    assert all(np.all(np.isfinite(s.accel)) and np.all(np.isfinite(s.gyro)) for s in samples)
    assert np.all(np.isfinite(world.data.qpos))
    surface = scene.surface
    deepest = min(s.truth.edge_position[2] - float(surface.height(s.truth.edge_position[0]))
                  for s in samples)
    assert deepest > -0.008  # penetration stays within the compliant travel + a margin


def test_sliding_across_heightfield_cells_is_smooth():
    scene = SCENE['probe']
    parameters = SweepParameters(0.10, 0.015, 0.0015, 0.5, 0.0, 1.0, 0.0)
    plan = plan_sweep(scene, parameters, duration_s=2.0)
    world = World(scene)
    world.place_arm(plan.joints[0])
    world.controller = plan.targets
    samples = [s for s in run(world, plan.times_s[-1])
               if plan.slide_start_s + 0.3 < s.time_s < plan.slide_end_s]
    cell = scene.surface.size_m[0] / (scene.surface.cells[0] - 1)
    travelled = samples[-1].truth.edge_position[0] - samples[0].truth.edge_position[0]
    assert travelled > 40 * cell  # crossed many cells
    assert all(s.truth.contact.touching for s in samples)
    accel_steps = np.abs(np.diff([s.accel for s in samples], axis=0))
    assert accel_steps.max() < 2.0  # no jolts at cell edges


@pytest.mark.slow
def test_the_plates_cells_put_no_line_into_the_spectrum():
    # A smooth plate sampled too coarsely makes the edge cross facets at speed / cell: at
    # 0.5 mm cells a 30 Hz line stood 50-200 times above the noise floor in every texture.
    scene = SCENE['uneven_texture']
    smooth = dataclasses.replace(scene, effects=tuple(e for e in scene.effects if e != 'texture'))
    parameters = SweepParameters.draw(smooth, np.random.default_rng(3))
    world = World(smooth, seed=3, texture_heading_rad=parameters.heading_rad)
    samples = []
    play(world, plan_sweep(smooth, parameters), samples.append)
    sliding = [s for s in samples if s.truth.contact.touching]
    assert len(sliding) > 600
    from scipy.signal import welch
    for channel in ('gyro', 'accel'):
        values = np.array([getattr(s, channel) for s in sliding])
        frequency, power = welch(values - values.mean(axis=0), fs=scene.sensor_rate_hz,
                                 nperseg=256, axis=0)
        band = frequency > 20.0  # above the sweep's own motion, up to Nyquist
        line_over_floor = power[band].max(axis=0) / np.median(power[band], axis=0)
        assert line_over_floor.max() < 10.0, (channel, line_over_floor)


def test_sensor_pressed_to_its_prismatic_limit_holds():
    scene = SCENE['probe']
    world = World(scene)
    world.place_arm(pose_at(scene, 0.15, 0.02, offset=0.0))
    run(world, 1.0)
    press = world.data.qpos[world.model.joint('sensor_press').qposadr[0]]
    low = world.model.jnt_range[world.model.joint('sensor_press').id][0]
    assert press >= low - 0.002 and np.all(np.isfinite(world.data.qpos))


def test_zero_velocity_contact_has_no_texture_vibration():
    scene = SCENE['uneven_texture']
    still = dataclasses.replace(scene, effects=('contact', 'compliance', 'texture'))
    world = World(still, patch_texture='ridged polymer')
    world.place_arm(pose_at(scene, 0.15, 0.0015))
    settled = run(world, 3.0)[-60:]  # the edge barely creeps (below the sliding speed)
    assert settled[-1].truth.contact.touching
    accel = np.array([s.accel for s in settled])
    # Sliding over these ridges vibrates by about 0.1 m/s^2 (next test); still, nothing.
    assert np.ptp(accel, axis=0).max() < 1e-3


def test_sliding_over_a_texture_adds_vibration_within_what_physics_allows():
    scene = SCENE['uneven_texture']
    parameters = SweepParameters(0.10, 0.015, 0.0015, 0.5, 0.0, 0.0, 0.0)
    plan = plan_sweep(scene, parameters, duration_s=3.0)
    streams = {}
    for effects in (('contact', 'compliance', 'texture'), ('contact', 'compliance')):
        world = World(dataclasses.replace(scene, effects=effects), patch_texture='ridged polymer')
        world.place_arm(plan.joints[0])
        world.controller = plan.targets
        streams[len(effects)] = np.array([s.accel for s in run(world, plan.times_s[-1])
                                          if plan.slide_start_s + 0.5 < s.time_s
                                          < plan.slide_end_s])
    # Above 3 Hz (the texture's friction also tilts the body, slowly): the vibration.
    from scipy.signal import butter, sosfiltfilt
    high_pass = butter(4, 3.0, 'high', fs=scene.sensor_rate_hz, output='sos')
    texture, plain = (sosfiltfilt(high_pass, streams[n], axis=0) for n in (3, 2))
    rms = [float(np.sqrt(np.mean(x ** 2))) for x in (texture, plain)]
    # 1.8 mm ridges 190 um high at 15 mm/s through a 1.5 mm footprint: about 0.1 m/s^2.
    assert rms[0] > 1.5 * rms[1] and 0.03 < rms[0] < 1.0


def test_same_seed_gives_bit_identical_streams():
    scene = SCENE['uneven_texture']
    parameters = SweepParameters(0.10, 0.015, 0.0015, 0.5, 0.1, 1.0, 1.0)
    plan = plan_sweep(scene, parameters, duration_s=1.0)
    streams = []
    for _ in range(2):
        world = World(scene, seed=5, patch_texture='wood', texture_heading_rad=0.1)
        world.place_arm(plan.joints[0])
        world.controller = plan.targets
        streams.append(np.array([np.concatenate([s.accel, s.gyro, s.mag, [s.pressure]])
                                 for s in run(world, plan.times_s[-1])]))
    assert streams[0].tobytes() == streams[1].tobytes()
    other = World(scene, seed=6, patch_texture='wood')
    other.place_arm(plan.joints[0])
    assert not np.array_equal(run(other, 0.2)[-1].accel, streams[0][23, :3])


def test_changing_the_patch_texture_while_running_equals_starting_with_it():
    scene = SCENE['uneven_texture']
    parameters = SweepParameters(0.10, 0.015, 0.0015, 0.5, 0.1, 1.0, 1.0)
    plan = plan_sweep(scene, parameters, duration_s=1.0)
    streams = []
    for changed in (False, True):
        world = World(scene, seed=5, patch_texture='carpet wool' if changed else 'wood')
        world.place_arm(plan.joints[0])
        world.controller = plan.targets
        world.set_patch_texture('wood' if changed else None)  # None: the scene's, wood
        streams.append([(s.truth.texture, *s.accel) for s in run(world, plan.times_s[-1])])
    assert streams[0] == streams[1]
    assert {texture for texture, *_ in streams[0]} >= {'wood'}
    with pytest.raises(KeyError, match="unknown texture 'velvet'; known: .*wood"):
        world.set_patch_texture('velvet')


def test_an_unknown_patch_texture_is_refused_even_in_a_scene_without_patches():
    world = World(SCENE['probe'])
    assert not world.scene.patches
    with pytest.raises(KeyError, match="unknown texture 'velvet'; known: .*wood"):
        world.set_patch_texture('velvet')


def test_a_scene_without_contact_does_not_collide():
    scene = parse_scene({'name': 'ghost', 'seed': 1, 'effects': ['compliance'],
                         'surface': {'kind': 'flat'}})
    world = World(scene)
    assert world.model.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_CONTACT


def test_all_twelve_textures_are_named_as_in_the_original():
    assert len(TEXTURES) == 12
    assert {'brocade fabric', 'carpet wool', 'reptile-patterned leather'} <= set(TEXTURES)


def test_alike_textures_have_close_models():
    open_weave, tight = TEXTURES['open weave cotton'], TEXTURES['tight weave cotton']
    assert abs(open_weave.weave_period[0] - tight.weave_period[0]) <= 0.0003
    mesh_cotton, mesh_leather = TEXTURES['mesh cotton'], TEXTURES['mesh leather']
    assert abs(mesh_cotton.weave_period[0] - mesh_leather.weave_period[0]) <= 0.0003
    assert pytest.approx(mesh_cotton.weave_height, rel=0.2) == mesh_leather.weave_height


@pytest.mark.parametrize('name', ['probe', 'uneven_texture'])
def test_a_placed_arm_is_held_by_its_servos_so_its_first_sample_reads_gravity(name):
    # Placed with its joints still and no servo torque yet, the arm fell freely at first:
    # the accelerometer read about 0, and the attitude filter rejected that sample.
    world = World(SCENE[name])
    world.place_arm(world.joint_positions())
    first, second = world.next_sample(), world.next_sample()
    assert first.time_s == 0.0
    for sample in (first, second):
        assert np.linalg.norm(sample.accel) == pytest.approx(9.81, abs=0.3)
        assert np.linalg.norm(sample.gyro) < 0.05
