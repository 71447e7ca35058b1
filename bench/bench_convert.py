# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Conversion throughput against rosbags' own read + deserialise, and peak memory, one run.

A 1-hour recording at 350 Hz (IMU, magnetometer, pressure: 3.8 million messages) is
written once; then, each in a fresh process, (a) rosbags reads and deserialises every
message (the practical limit) and (b) `read_recording` reads, aligns and returns the
10-channel array. Prints messages per second of both, their ratio (target >= 0.5) and
each process's peak resident memory: the converter must not hold the bag in memory.
"""

from pathlib import Path
import subprocess
import sys
import tempfile
import textwrap
import time

import numpy as np
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import get_typestore, Stores

RATE_HZ = 350
SECONDS = 3600
TS = get_typestore(Stores.ROS2_KILTED)
T = TS.types


def write_hour(path: Path, rate_hz: int = RATE_HZ, seconds: int = SECONDS) -> int:
    """Write the recording (IMU, magnetometer, pressure at `rate_hz`); return its messages."""
    count = rate_hz * seconds
    rng = np.random.default_rng(0)
    vector = T['geometry_msgs/msg/Vector3']
    with Writer(path, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
        imu = writer.add_connection('/tactile/imu/data_raw', 'sensor_msgs/msg/Imu', typestore=TS)
        mag = writer.add_connection('/tactile/imu/mag', 'sensor_msgs/msg/MagneticField',
                                    typestore=TS)
        pressure = writer.add_connection('/tactile/pressure', 'sensor_msgs/msg/FluidPressure',
                                         typestore=TS)
        noise = rng.normal(size=(count, 10))
        for i in range(count):
            stamp = 10**18 + i * (10**9 // rate_hz)
            sec, nanosec = divmod(stamp, 10**9)
            header = T['std_msgs/msg/Header'](
                stamp=T['builtin_interfaces/msg/Time'](sec=sec, nanosec=nanosec),
                frame_id='sensor_link')
            row = noise[i]
            writer.write(imu, stamp, TS.serialize_cdr(T['sensor_msgs/msg/Imu'](
                header=header, orientation=T['geometry_msgs/msg/Quaternion'](x=0.0, y=0.0,
                                                                              z=0.0, w=1.0),
                orientation_covariance=np.zeros(9),
                angular_velocity=vector(x=row[3], y=row[4], z=row[5]),
                angular_velocity_covariance=np.zeros(9),
                linear_acceleration=vector(x=row[0], y=row[1], z=row[2]),
                linear_acceleration_covariance=np.zeros(9)), 'sensor_msgs/msg/Imu'))
            writer.write(mag, stamp, TS.serialize_cdr(T['sensor_msgs/msg/MagneticField'](
                header=header, magnetic_field=vector(x=row[6], y=row[7], z=row[8]),
                magnetic_field_covariance=np.zeros(9)), 'sensor_msgs/msg/MagneticField'))
            writer.write(pressure, stamp, TS.serialize_cdr(T['sensor_msgs/msg/FluidPressure'](
                header=header, fluid_pressure=101325.0 + row[9], variance=0.0),
                'sensor_msgs/msg/FluidPressure'))
    return 3 * count


REFERENCE = textwrap.dedent("""
    import sys, resource
    from rosbags.highlevel import AnyReader
    count = 0
    with AnyReader([__import__('pathlib').Path(sys.argv[1])]) as reader:
        for connection, _, raw in reader.messages():
            reader.deserialize(raw, connection.msgtype)
            count += 1
    print(count, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
""")
OURS = textwrap.dedent("""
    import sys, resource
    from tactex_classify.data.bags import read_recording
    recording = read_recording(__import__('pathlib').Path(sys.argv[1]))
    print(recording.messages, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
""")


def timed(code: str, bag: Path) -> tuple[float, int, int]:
    start = time.perf_counter()
    out = subprocess.run([sys.executable, '-c', code, str(bag)], capture_output=True,
                         text=True, check=True).stdout.split()
    return time.perf_counter() - start, int(out[0]), int(out[1])


def main() -> None:
    """Write, time both readers, print the table."""
    with tempfile.TemporaryDirectory() as folder:
        bag = Path(folder) / 'hour'
        start = time.perf_counter()
        messages = write_hour(bag)
        size = sum(f.stat().st_size for f in bag.iterdir()) / 1e6
        print(f'wrote {messages} messages ({size:.0f} MB) in {time.perf_counter() - start:.0f} s')
        reference_s, reference_count, reference_kb = timed(REFERENCE, bag)
        ours_s, ours_count, ours_kb = timed(OURS, bag)
    print(f'{"reader":<40}{"messages/s":>12}{"peak RSS MB":>13}')
    print(f'{"rosbags read + deserialise (reference)":<40}{reference_count / reference_s:>12.0f}'
          f'{reference_kb / 1024:>13.0f}')
    print(f'{"tactex read_recording (align, 10 ch)":<40}{ours_count / ours_s:>12.0f}'
          f'{ours_kb / 1024:>13.0f}')
    ratio = (ours_count / ours_s) / (reference_count / reference_s)
    print(f'throughput ratio {ratio:.2f} (target >= 0.5); the aligned hour itself is '
          f'{RATE_HZ * SECONDS * 10 * 8 / 1e6:.0f} MB of float64; the bag is {size:.0f} MB')


if __name__ == '__main__':
    main()
