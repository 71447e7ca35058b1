# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex demo`: the part of the simulated pipeline that works today, run end to end.

Slice 1, the robot description: the exploration motion of the probe phase (approach
height, descend, retract, step 1 cm) is solved with our analytic IK and played on the
MuJoCo arm through its position servos; the sensor tip it reaches is compared with the
target. Slice 2, the tactile sensor: an emulated Teensy streams real protocol frames
with injected garbage and CRC errors over a pseudo-terminal; the serial reader decodes
them and the Madgwick filter estimates the tilt, compared with the emulated one.
Slice 3, data: scripted sweeps over three textures in the MuJoCo texture scene are
recorded as bags and converted into a windowed dataset. Slice 4, classification: the
statistics + ExtraTrees baseline, cross-validated by recording. Probing and the online
classifier are not in it yet.

Each slice states a threshold and is measured against it (the worst tracking error, the
filter's tilt error and how much of the stream it saw, the grouped accuracy); the demo
ends with a table of every figure and exits 1, naming the slice, when one is missed.
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass
import math
from pathlib import Path
import sys

import numpy as np

from tactex.errors import CommandError
from tactex.options import integer, number

# Folds of the demo's grouped cross-validation.
DEMO_FOLDS = 3
# The thresholds each slice is held to.
TRACKING_LIMIT_MM = 2.0  # worst steady-state error of the sensor edge at a waypoint
ROLL_LIMIT_DEG = 1.0  # Madgwick estimate vs the emulated 20 deg roll
MIN_DECODED_FRAMES = 350  # one second of the 3 s stream, so the filter really ran
ACCURACY_FLOOR = 0.70  # grouped, 3 textures, two of them alike (chance 0.33; 0.86 seen)


@dataclass(frozen=True)
class Check:
    """One figure of a slice against the threshold it is held to."""

    slice_name: str
    figure: str
    value: float
    limit: float
    unit: str
    at_least: bool = False  # True: the figure must reach the limit; False: stay within it

    @property
    def passed(self) -> bool:
        """Whether the figure meets its threshold (NaN never does)."""
        return self.value >= self.limit if self.at_least else self.value <= self.limit

    def line(self) -> str:
        """`slice: figure value (threshold): PASS|FAIL`."""
        bound = '>=' if self.at_least else '<='
        return (f'{self.slice_name}: {self.figure} {self.value:.4g} {self.unit} '
                f'(threshold {bound} {self.limit:g} {self.unit}): '
                f'{"PASS" if self.passed else "FAIL"}')


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('--points', type=integer(1, 10), default=5,
                        help='probe stations, 1 cm apart (1..10, default 5)')
    parser.add_argument('--settle-s', type=number(at_most=60.0), default=1.5,
                        help='simulated time to hold each waypoint (default 1.5 s)')
    parser.add_argument('--sweeps', type=integer(DEMO_FOLDS, 50), default=6,
                        help=f'sweeps per texture in the data slice ({DEMO_FOLDS}..50, default '
                             f'6): each texture needs a recording in every one of the '
                             f'{DEMO_FOLDS} folds')


def run(args: argparse.Namespace) -> int:
    """Run every slice, print each figure against its threshold; 1 if one is missed."""
    checks = [*_description_slice(args.points, args.settle_s), *_sensor_slice(),
              *_data_and_classification_slices(args.sweeps)]
    print('\ntactex demo, summary:')
    for check in checks:
        print(f'  {check.line()}')
    missed = [check for check in checks if not check.passed]
    for check in missed:
        print(f'error: {check.slice_name} missed its threshold: {check.line()}',
              file=sys.stderr)
    return 1 if missed else 0


def _description_slice(points: int, settle_s: float) -> list[Check]:
    """Play the probe motion in MuJoCo and print the tracking error per waypoint."""
    import mujoco

    from tactex_description.geometry import ARM_JOINT_NAMES
    from tactex_description.kinematics import forward_kinematics, inverse_kinematics
    from tactex_description.mjcf import build_mjcf

    print('tactex demo, slice 1/5: robot description (IK -> MuJoCo servos -> FK).')
    print('Not yet in the demo: probing the surface, the online classifier.\n')
    model = mujoco.MjModel.from_xml_string(build_mjcf())
    data = mujoco.MjData(model)
    joints = [model.joint(name).qposadr[0] for name in ARM_JOINT_NAMES]
    seed = np.array([0.0, -0.3, 0.3, 1.5])
    waypoints = []
    for station in range(points):
        x = 0.10 + 0.01 * station
        waypoints += [(x, 0.0, 0.08), (x, 0.0, 0.03), (x, 0.0, 0.08)]
    print(f'{"target x,y,z (m)":<26}{"reached x,y,z (m)":<28}{"error (mm)":>10}')
    worst = 0.0
    steps = int(round(settle_s / model.opt.timestep))
    for target in waypoints:
        result = inverse_kinematics(target, math.pi / 2, seed=seed)
        if not result.reachable:
            raise CommandError(f'--points {points}: waypoint {target} is unreachable: '
                               f'{result.detail}; use fewer points')
        seed = result.solutions[0]
        data.ctrl[:4] = seed
        for _ in range(steps):
            mujoco.mj_step(model, data)
        reached = forward_kinematics(data.qpos[joints], 'sensor_edge')[:3, 3]
        error_mm = 1e3 * float(np.linalg.norm(reached - target))
        worst = max(worst, error_mm)
        print(f'{_xyz(target):<26}{_xyz(reached):<28}{error_mm:>10.2f}')
    print(f'\n{len(waypoints)} waypoints, worst steady-state error {worst:.2f} mm '
          '(position servos under gravity).')
    return [Check('slice 1', 'worst tracking error', worst, TRACKING_LIMIT_MM, 'mm')]


def _sensor_slice() -> list[Check]:
    """Emulated Teensy -> pty -> decoder -> Madgwick; print what arrived and the tilt."""
    import tempfile
    import threading
    import time

    from tactex_sensor.emulator import Fault, Motion, SignalSource, TeensyEmulator
    from tactex_sensor.link import SerialLink
    from tactex_sensor.madgwick import MadgwickFilter
    from tactex_sensor.reader import TeensyReader

    print('\ntactex demo, slice 2/5: tactile sensor (emulated Teensy -> pty -> decoder -> '
          'Madgwick), 350 Hz for 3 s, 20 deg roll, garbage and CRC faults.')
    roll_deg = 20.0
    with tempfile.TemporaryDirectory() as folder:
        link_path = f'{folder}/teensy'
        faults = (Fault.parse('garbage@0.5:300'), Fault.parse('crc@1.0:5'))
        source = SignalSource(Motion.STATIC, roll_rad=math.radians(roll_deg), seed=1)
        with TeensyEmulator(link_path, 350.0, source, faults=faults) as emulator:
            streamer = threading.Thread(target=emulator.run, args=(3.0,), daemon=True)
            streamer.start()
            reader = TeensyReader(SerialLink(link_path, 250000), time.monotonic_ns)
            madgwick = MadgwickFilter()
            previous_ns = None
            while streamer.is_alive():
                for stamp_ns, sample in reader.poll():
                    dt = 0.0 if previous_ns is None else (stamp_ns - previous_ns) * 1e-9
                    previous_ns = stamp_ns
                    madgwick.update(sample.gyro, sample.accel, dt)
            reader.link.close()
    stats = reader.decoder.stats
    w, x, y, z = madgwick.quaternion
    roll = math.degrees(math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y)))
    print(f'frames decoded {stats.frames}, CRC errors {stats.crc_errors}, '
          f'lost {stats.lost_frames}, garbage bytes discarded {stats.discarded_bytes}')
    print(f'estimated roll {roll:.2f} deg (emulated {roll_deg:.1f} deg)')
    return [Check('slice 2', 'frames decoded', stats.frames, MIN_DECODED_FRAMES, 'frames',
                  at_least=True),
            Check('slice 2', 'roll error', abs(roll - roll_deg), ROLL_LIMIT_DEG, 'deg')]


def _xyz(values) -> str:
    return ' '.join(f'{v:+.4f}' for v in values)


DEMO_TEXTURES = ('ridged polymer', 'open weave cotton', 'tight weave cotton')


def _data_and_classification_slices(sweeps: int) -> list[Check]:
    """Simulated sweeps -> bags -> dataset -> grouped cross-validation of a baseline."""
    import tempfile

    from tactex_classify.baselines import StatsExtraTrees
    from tactex_classify.dataset import convert
    from tactex_classify.evaluate import confusion, cross_validate, metrics
    from tactex_sim.collect import collect
    from tactex_sim.scene import load_scene, resolve_scene

    print(f'\ntactex demo, slice 3/5: data ({sweeps} simulated sweeps of each of '
          f'{", ".join(DEMO_TEXTURES)} -> mcap bags -> 128-sample windows).')
    with tempfile.TemporaryDirectory() as folder:
        scene = load_scene(resolve_scene('uneven_texture'))
        collect(scene, sweeps, Path(folder), textures=DEMO_TEXTURES,
                progress=lambda line: print(f'  {line}', flush=True))
        dataset = convert([Path(folder)], window=128, hop=64, progress=lambda line: None)
    print(f'{len(dataset.X)} windows from {len(set(dataset.trial.tolist()))} recordings, '
          f'{dataset.info["sampling_rate_hz"]:.0f} Hz')
    print('\ntactex demo, slice 4/5: classification (statistics + ExtraTrees, '
          f'{DEMO_FOLDS}-fold CV '
          'grouped by recording: no recording on both sides).')
    result = cross_validate(dataset, lambda: StatsExtraTrees(seed=0), 'grouped',
                            folds=DEMO_FOLDS)
    for note in result.notes:
        print(f'note: {note}')
    matrix = confusion(dataset.y, result.proba.argmax(axis=1), len(dataset.classes))
    accuracy = metrics(matrix, dataset.classes)['accuracy']
    print(f'accuracy {100 * accuracy:.1f} % over {len(dataset.X)} windows; confusion '
          f'(rows true, columns predicted):')
    for name, row in zip(dataset.classes, matrix, strict=True):
        print(f'  {name:<20}' + ''.join(f'{count:>6}' for count in row))
    print('The two cotton weaves are meant to be confused: alike in reality, alike here.')
    return [Check('slice 4', 'grouped accuracy', 100 * accuracy, 100 * ACCURACY_FLOOR, '%',
                  at_least=True)]
