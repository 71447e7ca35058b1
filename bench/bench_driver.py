# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Arm driver timing against the servo emulator: bus cycle and the 100 Hz loop's jitter.

The full cycle is one sync read of five servos plus one sync write of their goals; the
reference measured in the same run is pinging the five servos one by one (five round
trips, what a driver without sync read needs just to hear from each). Then arm_driver
runs for 10 s against the emulator in its own process (as hardware would be) and
reports its own loop jitter (|period - 10 ms|). Targets: cycle median <= 2 ms, loop
p99 jitter < 2 ms.
"""

from pathlib import Path
import tempfile
import time

import numpy as np

from tactex.launching.environment import ros_environment
from tactex_driver.bus import ServoBus
from tactex_driver.servo_emulator import ServoChainEmulator

CYCLES = 1000


def percentiles(values_ms):
    return np.percentile(values_ms, 50), np.percentile(values_ms, 99)


def bus_timing(link: Path):
    with ServoChainEmulator(link), ServoBus(str(link)) as bus:
        bus.set_torque(True)
        pings, cycles = [], []
        for _ in range(CYCLES):
            start = time.perf_counter()
            bus.ping()
            pings.append((time.perf_counter() - start) * 1e3)
        goals = np.zeros(5)
        for _ in range(CYCLES):
            start = time.perf_counter()
            bus.read_state()
            bus.write_goals(goals)
            cycles.append((time.perf_counter() - start) * 1e3)
    return percentiles(pings), percentiles(cycles)


def loop_jitter(link: Path):
    import os
    import subprocess
    import sys
    os.environ.update(ros_environment())
    import rclpy
    from rclpy.parameter import Parameter

    from tactex_driver.arm_driver_node import ArmDriverNode
    emulator = subprocess.Popen([str(Path(sys.executable).parent / 'tactex'), 'emulate',
                                 'dynamixel', '--link', str(link)], stdout=subprocess.PIPE,
                                text=True)
    try:
        emulator.stdout.readline()  # the chain is up once it prints its path
        rclpy.init()
        node = ArmDriverNode(parameter_overrides=[Parameter('port', value=str(link))])
        end = time.monotonic() + 10.0
        while time.monotonic() < end:
            rclpy.spin_once(node, timeout_sec=0.005)
        median, p99 = node.loop_jitter_ms()
        node.destroy_node()
        rclpy.shutdown()
    finally:
        emulator.terminate()
        emulator.wait(timeout=10)
    return median, p99


def main() -> None:
    """Print the table."""
    with tempfile.TemporaryDirectory() as folder:
        (ping50, ping99), (cycle50, cycle99) = bus_timing(Path(folder) / 'dxl')
        jitter50, jitter99 = loop_jitter(Path(folder) / 'dxl2')
    print(f'{"measure":<44}{"median ms":>10}{"p99 ms":>9}')
    print(f'{"5 unicast pings (reference)":<44}{ping50:>10.3f}{ping99:>9.3f}')
    print(f'{"sync read 5 servos + sync write goals":<44}{cycle50:>10.3f}{cycle99:>9.3f}')
    print(f'{"arm_driver 100 Hz loop |period - 10 ms|":<44}{jitter50:>10.3f}{jitter99:>9.3f}')
    print(f'cycle / 5 pings: {cycle50 / ping50:.2f}x; targets: cycle median <= 2 ms '
          f'({"met" if cycle50 <= 2 else "NOT met"}), loop p99 jitter < 2 ms '
          f'({"met" if jitter99 < 2 else "NOT met"}); '
          f'{1000 / cycle50:.0f} cycles/s possible')


if __name__ == '__main__':
    main()
