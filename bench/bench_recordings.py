# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Recordings made elsewhere: ROS 1 conversion speed, and `tactex bag info` on a long one.

The 1-hour 350 Hz recording of bench_convert (3.8 million messages) is written once and
rewritten as a ROS 1 bag by rosbags' converter. Then, each in a fresh process:
- rosbags reads and deserialises every message of the ROS 1 bag (the reference) and
  `read_recording` reads, aligns and returns its 10 channels (target: at least 0.7x the
  reference's messages per second);
- `tactex bag info --no-timing` (the index's summary: metadata.yaml, the ROS 1 chunk
  records; target under 2 s) and `tactex bag info` (with every topic's rate, jitter and
  gaps, from the MCAP message indexes and the ROS 1 index; target under 15 s), on the
  rosbag2 folder and on the ROS 1 bag, command start-up included.
"""

from pathlib import Path
import subprocess
import sys
import tempfile
import time

from bench_convert import OURS, REFERENCE, timed, write_hour
from rosbags.convert.converter import convert

TACTEX = Path(sys.executable).parent / 'tactex'


def bag_info_s(path: Path, *options: str) -> float:
    """Seconds `tactex bag info` takes on `path`, start-up included."""
    start = time.perf_counter()
    subprocess.run([str(TACTEX), 'bag', 'info', *options, str(path)], check=True,
                   capture_output=True)
    return time.perf_counter() - start


def main() -> None:
    """Write, convert to ROS 1, time the readers and bag info, print the tables."""
    with tempfile.TemporaryDirectory() as folder:
        hour, ros1 = Path(folder) / 'hour', Path(folder) / 'hour.bag'
        start = time.perf_counter()
        messages = write_hour(hour)
        print(f'wrote {messages} messages in {time.perf_counter() - start:.0f} s')
        start = time.perf_counter()
        convert([hour], ros1, dst_storage='mcap', dst_version=9, compress=None,
                compress_mode='file', default_typestore=None, typestore=_ros1_store(),
                exclude_topics=(), include_topics=(), exclude_msgtypes=(),
                include_msgtypes=())
        print(f'rewrote it as a ROS 1 bag ({ros1.stat().st_size / 1e6:.0f} MB) in '
              f'{time.perf_counter() - start:.0f} s')
        reference_s, reference_count, reference_kb = timed(REFERENCE, ros1)
        ours_s, ours_count, ours_kb = timed(OURS, ros1)
        info = {(name, timing): bag_info_s(path, *([] if timing else ['--no-timing']))
                for name, path in (('rosbag2 MCAP', hour), ('ROS 1 bag', ros1))
                for timing in (False, True)}
    print(f'{"ROS 1 reader":<44}{"messages/s":>12}{"peak RSS MB":>13}')
    print(f'{"rosbags read + deserialise ROS 1 (reference)":<44}'
          f'{reference_count / reference_s:>12.0f}{reference_kb / 1024:>13.0f}')
    print(f'{"tactex read_recording ROS 1 (align, 10 ch)":<44}{ours_count / ours_s:>12.0f}'
          f'{ours_kb / 1024:>13.0f}')
    ratio = (ours_count / ours_s) / (reference_count / reference_s)
    print(f'ROS 1 throughput ratio {ratio:.2f} (target >= 0.7)')
    for (name, timing), seconds in info.items():
        label = 'with rates, jitter, gaps' if timing else 'summary from the index'
        print(f'bag info {name}, {label}: {seconds:.1f} s (target {15 if timing else 2} s)')


def _ros1_store():
    from rosbags.typesys import get_typestore, Stores
    return get_typestore(Stores.ROS1_NOETIC)


if __name__ == '__main__':
    main()
