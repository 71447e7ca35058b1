# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""teensy_node end to end: frame written to the pty -> Imu message received, at 350 Hz.

The emulator runs in this process and notes the wall time of every frame it writes;
teensy_node runs as its own process; a subscriber here notes when each Imu arrives
and matches it to its frame by stamp (frames are 2.9 ms apart, stamps within 1 ms of
the write). The reference, measured in the same run on the same machine, is a bare
pyserial reader of the same pty stream (write -> bytes read, no decoding, no ROS).
Prints p50/p99/max of both and their ratio; target p99 < 5 ms.
"""

from __future__ import annotations

from contextlib import nullcontext
from pathlib import Path
import subprocess
import sys
import tempfile
import threading
import time

import numpy as np
import serial

from tactex.launching.environment import ros_environment
from tactex_sensor.emulator import Motion, SignalSource, TeensyEmulator
from tactex_sensor.protocol import FRAME_SIZE

RATE_HZ = 350.0
DURATION_S = 12.0
WARMUP_S = 3.0


class TimedEmulator(TeensyEmulator):
    """The emulator, noting the wall time (ns) of each write."""

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.write_times_ns: list[int] = []

    def _write(self, data: bytes) -> None:
        self.write_times_ns.append(time.time_ns())
        super()._write(data)


def reference_latencies(link: Path) -> np.ndarray:
    """Write -> read latency (ms) of a bare pyserial reader on the same kind of stream."""
    source = SignalSource(Motion.STATIC)
    emulator = TimedEmulator(link, RATE_HZ, source)
    received: list[int] = []
    with emulator:
        port = serial.Serial(str(link), 250000, timeout=0.05)
        streamer = threading.Thread(target=emulator.run, args=(5.0,), daemon=True)
        streamer.start()
        pending = 0
        while streamer.is_alive():
            data = port.read(max(1, port.in_waiting))
            now = time.time_ns()
            pending += len(data)
            while pending >= FRAME_SIZE:
                pending -= FRAME_SIZE
                received.append(now)
        port.close()
    count = min(len(received), len(emulator.write_times_ns))
    return (np.array(received[:count]) - np.array(emulator.write_times_ns[:count])) / 1e6


def node_latencies(link: Path, beside=nullcontext) -> tuple[np.ndarray, int, int]:
    """Write -> Imu received latency (ms) through teensy_node; also frames and messages.

    `beside()` is entered once teensy_node runs and left after the stream: what runs
    beside the node meanwhile (bench_observers.py: the live view, status, watch).
    """
    import rclpy
    from rclpy.qos import qos_profile_sensor_data
    from sensor_msgs.msg import Imu

    env = ros_environment()
    emulator = TimedEmulator(link, RATE_HZ, SignalSource(Motion.SWAY))
    arrivals: list[tuple[int, int]] = []
    with emulator:
        node_process = subprocess.Popen(
            [str(Path(sys.executable).parent / 'teensy_node'), '--ros-args', '-p',
             f'port:={link}'], env=env)
        rclpy.init()
        listener = rclpy.create_node('latency_listener')
        listener.create_subscription(
            Imu, 'tactile/imu/data_raw',
            lambda msg: arrivals.append((time.time_ns(), msg.header.stamp.sec * 10**9
                                         + msg.header.stamp.nanosec)),
            qos_profile_sensor_data)
        with beside():
            streamer = threading.Thread(target=emulator.run, args=(DURATION_S,), daemon=True)
            streamer.start()
            while streamer.is_alive():
                rclpy.spin_once(listener, timeout_sec=0.01)
        listener.destroy_node()
        rclpy.shutdown()
        node_process.terminate()
        node_process.wait(timeout=10)
    writes = np.array(emulator.write_times_ns)
    start_ns = writes[0] + int(WARMUP_S * 1e9)
    latencies = []
    for received_ns, stamp_ns in arrivals:
        index = int(np.argmin(np.abs(writes - stamp_ns)))
        if writes[index] >= start_ns:
            latencies.append((received_ns - writes[index]) / 1e6)
    return np.array(latencies), len(writes), len(arrivals)


def main() -> None:
    """Measure both paths and print one table."""
    with tempfile.TemporaryDirectory() as folder:
        reference = reference_latencies(Path(folder) / 'reference')
        node, frames, messages = node_latencies(Path(folder) / 'teensy')
    print(f'{RATE_HZ:.0f} Hz, {frames} frames written, {messages} Imu messages received '
          f'(latency over the last {DURATION_S - WARMUP_S:.0f} s)')
    print(f'{"path":<34}{"p50 ms":>9}{"p99 ms":>9}{"max ms":>9}')
    for label, values in (('bare pyserial read (reference)', reference),
                          ('teensy_node -> Imu subscriber', node)):
        print(f'{label:<34}{np.percentile(values, 50):>9.3f}{np.percentile(values, 99):>9.3f}'
              f'{values.max():>9.3f}')
    ratio = np.percentile(node, 99) / np.percentile(reference, 99)
    print(f'p99 node / reference: {ratio:.1f}x; target p99 < 5 ms: '
          f'{"met" if np.percentile(node, 99) < 5.0 else "NOT met"}')


if __name__ == '__main__':
    main()
