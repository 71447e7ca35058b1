# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex doctor` and the launch's hardware checks, against the protocol-level emulators.

Every check says what it found; a failed one says the fix. The Teensy's stream is read
from the emulator on a pty (or from prepared bytes), the servos' control tables from the
emulated chain, the ROS settings from an environment; `tactex launch` without sim:=true
stops with the same lines instead of starting nodes that would retry forever.
"""

import math
import os
from pathlib import Path
import signal
import struct
import subprocess
import sys
import threading

import pytest
from support.processes import stop, wait_for

from tactex.bringup import lines, ros_checks
from tactex_common.bringup import FAIL, OK, port_checks, WARN
from tactex_driver import control_table as ct
from tactex_driver.bringup import servo_checks
from tactex_driver.playback import JointLimits
from tactex_driver.servo_emulator import ServoChainEmulator
from tactex_sensor.bringup import stream_checks
from tactex_sensor.emulator import Fault, SignalSource, TeensyEmulator
from tactex_sensor.protocol import encode, Sample

BIN = Path(sys.executable).parent
BAUD = 250000


def by_name(checks):
    return {check.name: check for check in checks}


def streamed(tmp_path, rate_hz, expected_hz, *, faults=(), source=None, seconds=1.0):
    """The stream checks of an emulated Teensy sending at `rate_hz`."""
    link = tmp_path / 'teensy'
    with TeensyEmulator(link, rate_hz, source or SignalSource(), faults=faults) as teensy:
        sender = threading.Thread(target=teensy.run, args=(seconds + 1.0,), daemon=True)
        sender.start()
        checks = stream_checks(str(link), BAUD, expected_hz, seconds)
        teensy.close()
        sender.join()
    return by_name(checks)


class Replay:
    """A serial port (pyserial's interface) that gives `data` once, then nothing."""

    def __init__(self, data: bytes) -> None:
        self.data = data

    def __call__(self, port, baud, timeout):
        return self

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False

    def reset_input_buffer(self):
        pass

    @property
    def in_waiting(self):
        return len(self.data)

    def read(self, size):
        chunk, self.data = self.data[:size], self.data[size:]
        return chunk


def frames(count, *, version=1, mag=(2e-5, 0.0, 4e-5)):
    return b''.join(encode(Sample(i, 1000 * i, (0.0, 0.0, 9.81), (0.0, 0.0, 0.0), mag,
                                  101325.0, 21.0), version=version) for i in range(count))


# -- the Teensy --------------------------------------------------------------------------
def test_a_teensy_streaming_at_its_rate_passes_every_check(tmp_path):
    checks = streamed(tmp_path, 120.0, 120.0)
    assert {c.status for c in checks.values()} == {OK}, lines(checks.values())
    rate = float(checks['Teensy frame rate'].detail.split()[0])
    assert rate == pytest.approx(120.0, rel=0.1)


def test_a_rate_other_than_the_expected_one_fails_and_names_the_firmware_setting(tmp_path):
    check = streamed(tmp_path, 120.0, 350.0)['Teensy frame rate']
    assert check.status == FAIL and 'expected 350 Hz' in check.detail
    assert 'TACTEX_RATE_HZ' in check.fix


def test_corrupt_frames_are_counted_and_flagged(tmp_path):
    check = streamed(tmp_path, 200.0, 200.0, faults=(Fault.parse('crc@0.1:20'),))[
        'Teensy frames intact']
    assert check.status == FAIL and check.detail.startswith('20 CRC errors')
    assert 'cable' in check.fix


@pytest.mark.parametrize(('data', 'found', 'fix'), [
    (frames(50, version=2), '50 frames of another protocol version', 'flash firmware'),
    (bytes(range(256)) * 4, '1024 bytes but no frame', 'is this the Teensy'),
    (b'', 'no byte', 'powered and flashed')],
    ids=['another protocol version', 'another device', 'silence'])
def test_a_stream_without_frames_fails_with_what_came_instead(data, found, fix):
    [check] = stream_checks('/dev/fake', BAUD, 120.0, 0.2, opener=Replay(data))
    assert check.status == FAIL and check.detail.startswith(found), check
    assert fix in check.fix


def test_a_chip_that_sends_only_nan_is_named():
    checks = by_name(stream_checks('/dev/fake', BAUD, None, 0.2,
                                   opener=Replay(frames(40, mag=(math.nan,) * 3))))
    chips = checks['Teensy chips']
    assert chips.status == FAIL and chips.detail == 'LSM9DS0 magnetometer sent only NaN'
    assert 'I2C' in chips.fix
    assert checks['Teensy frame rate'].status == OK  # no rate asked for: only reported


def test_a_port_that_cannot_be_opened_is_one_failure_naming_it():
    [check] = stream_checks(str(Path('/nonexistent/tty')), BAUD, 120.0, 0.2)
    assert check.status == FAIL and check.detail.startswith('cannot open /nonexistent/tty')


# -- the port ----------------------------------------------------------------------------
def test_a_missing_port_fails_with_where_to_look_and_the_udev_rule(tmp_path):
    [check] = port_checks(str(tmp_path / 'ttyACM0'), 'Teensy')
    assert check.status == FAIL and check.detail.endswith('ttyACM0 does not exist')
    assert 'ls /dev/serial/by-id/' in check.fix and '99-tactex.rules' in check.fix
    assert Path(check.fix.split('install ')[1].split()[0]).is_file()


def test_a_file_that_is_no_serial_device_is_refused(tmp_path):
    (tmp_path / 'port').write_text('')
    [check] = port_checks(str(tmp_path / 'port'), 'Teensy')
    assert check.status == FAIL and 'is not a serial device (a regular file)' in check.detail


def test_a_serial_device_passes(tmp_path):
    with ServoChainEmulator(tmp_path / 'dxl') as chain:
        assert [c.status for c in port_checks(str(chain.link), 'servo adapter')] == [OK]


@pytest.mark.skipif(os.geteuid() == 0, reason='root may open any device')
def test_a_port_this_user_may_not_open_suggests_the_group_or_the_rule(tmp_path):
    with ServoChainEmulator(tmp_path / 'dxl') as chain:
        os.chmod(os.path.realpath(chain.link), 0o600)
        os.chown(os.path.realpath(chain.link), -1, 0)
        [check] = port_checks(str(chain.link), 'servo adapter')
    assert check.status == FAIL and 'usermod -aG' in check.fix


# -- the servos --------------------------------------------------------------------------
@pytest.fixture
def chain(tmp_path):
    with ServoChainEmulator(tmp_path / 'dxl') as emulator:
        yield emulator


def servos(chain, ids=(11, 12, 13, 14, 15)):
    return by_name(servo_checks(str(chain.link), 1_000_000, ids, JointLimits.of_robot()))


def test_a_healthy_chain_passes_every_servo_check(chain):
    checks = servos(chain)
    assert {c.status for c in checks.values()} == {OK}, lines(checks.values())
    assert checks['servo supply'].detail == '12.0 to 12.0 V at the servos'


def test_a_servo_that_does_not_answer_is_named(chain):
    chain.silence(13)
    check = servos(chain)['servo IDs']
    assert check.status == FAIL
    assert check.detail == 'servo(s) [13] do not answer (answering: [11, 12, 14, 15])'


def test_a_chain_that_answers_nowhere_says_so_after_trying_every_baud_rate(chain):
    for servo in chain.servos:
        chain.silence(servo)
    [check] = servos(chain).values()
    assert check.status == FAIL and 'at any baud rate' in check.detail
    assert 'powered' in check.fix


def test_an_unexpected_model_is_refused(chain):
    struct.pack_into('<H', chain.servos[14].table, ct.MODEL_NUMBER, 1060)
    check = servos(chain)['servo models']
    assert check.status == FAIL and '{14: 1060}' in check.detail


@pytest.mark.parametrize(('tenths', 'status'), [(105, WARN), (90, FAIL), (160, FAIL)])
def test_the_supply_voltage_is_held_to_the_servos_range(chain, tenths, status):
    struct.pack_into('<H', chain.servos[11].table, ct.PRESENT_INPUT_VOLTAGE, tenths)
    check = servos(chain)['servo supply']
    assert check.status == status, check


@pytest.mark.parametrize(('celsius', 'status'), [(75, WARN), (80, FAIL)])
def test_a_hot_servo_is_flagged_before_it_shuts_down(chain, celsius, status):
    chain.servos[12].table[ct.PRESENT_TEMPERATURE] = celsius
    check = servos(chain)['servo temperature']
    assert check.status == status and check.detail.startswith(f'hottest servo 12 at {celsius}')


def test_a_latched_overload_is_named_with_how_to_clear_it(chain):
    chain.overload(14)
    check = servos(chain)['servo errors']
    assert check.status == FAIL and "{14: 'overload'}" in check.detail
    assert 'power-cycle' in check.fix


def test_position_limits_narrower_than_the_urdf_are_refused_with_the_counts(chain):
    struct.pack_into('<i', chain.servos[12].table, ct.MIN_POSITION_LIMIT, 1800)
    check = servos(chain)['joint limits']
    assert check.status == FAIL and check.detail.startswith('servo 12 (joint2) stops at')
    lower = JointLimits.of_robot().lower[1]
    assert f'{math.floor(ct.rad_to_position(lower))}/' in check.detail


# -- the ROS settings --------------------------------------------------------------------
@pytest.mark.parametrize(('env', 'name', 'status', 'said'), [
    ({}, 'ROS domain', OK, 'domain 0'),
    ({'ROS_DOMAIN_ID': '7'}, 'ROS domain', OK, 'ROS_DOMAIN_ID=7'),
    ({'ROS_DOMAIN_ID': 'seven'}, 'ROS domain', FAIL, 'is not a domain'),
    ({'ROS_DOMAIN_ID': '150'}, 'ROS domain', WARN, 'ephemeral ports'),
    ({'ROS_AUTOMATIC_DISCOVERY_RANGE': 'LAN'}, 'ROS discovery', FAIL, "'LAN'"),
    ({'ROS_AUTOMATIC_DISCOVERY_RANGE': 'OFF'}, 'ROS discovery', WARN, 'no node finds another'),
    ({'ROS_LOCALHOST_ONLY': '1'}, 'ROS discovery', WARN, 'Kilted ignores'),
    ({'RMW_IMPLEMENTATION': 'rmw_cyclonedds_cpp'}, 'ROS middleware', FAIL, 'does not install'),
    ({'FASTDDS_DEFAULT_PROFILES_FILE': '/no/profile.xml'}, 'Fast DDS profile', FAIL,
     'is not a file')])
def test_ros_settings_are_checked(env, name, status, said):
    check = by_name(ros_checks(env))[name]
    assert check.status == status and said in check.detail, check


# -- the commands ------------------------------------------------------------------------
@pytest.fixture
def emulators(tmp_path):
    """`tactex emulate teensy` and `tactex emulate dynamixel` on ptys: their links."""
    links = {device: tmp_path / device for device in ('teensy', 'dynamixel')}
    processes = [subprocess.Popen([BIN / 'tactex', 'emulate', device, '--link', str(link)],
                                  stdout=subprocess.PIPE, text=True)
                 for device, link in links.items()]
    for process in processes:
        process.stdout.readline()  # the emulator prints its pty once it is there
    yield links
    stop(processes, signal.SIGINT)


def test_doctor_passes_on_the_emulated_hardware_and_prints_every_check(emulators):
    run = subprocess.run([BIN / 'tactex', 'doctor', '--sensor-port', str(emulators['teensy']),
                          '--arm-port', str(emulators['dynamixel']), '--listen', '1'],
                         capture_output=True, text=True, timeout=120,
                         env={k: v for k, v in os.environ.items() if not k.startswith('ROS_')})
    assert run.returncode == 0, run.stdout + run.stderr
    shown = run.stdout.splitlines()
    assert shown[-1] == '15 checks passed'
    assert all(line.startswith('[ ok ] ') for line in shown[:-1])


def test_doctor_fails_on_missing_hardware_with_a_fix_under_each_failure(tmp_path):
    run = subprocess.run([BIN / 'tactex', 'doctor', '--only', 'sensor', '--only', 'arm',
                          '--sensor-port', str(tmp_path / 'ttyACM0'),
                          '--arm-port', str(tmp_path / 'ttyUSB0')],
                         capture_output=True, text=True, timeout=60)
    assert run.returncode == 1
    shown = run.stdout.splitlines()
    assert shown[0].startswith('[FAIL] Teensy port: ') and shown[1].startswith('       fix: ')
    assert shown[2].startswith('[FAIL] servo adapter port: ')
    assert shown[-1] == '2 checks: 2 failed'


def test_a_hardware_launch_checks_first_and_starts_no_node_when_it_is_not_ready(tmp_path):
    run = subprocess.run([BIN / 'tactex', 'launch', 'robot',
                          f'sensor_port:={tmp_path / "ttyACM0"}',
                          f'arm_port:={tmp_path / "ttyUSB0"}'],
                         capture_output=True, text=True, timeout=60)
    assert run.returncode == 1
    assert '[launch] started' not in run.stdout
    assert run.stderr.startswith('[FAIL] Teensy port: ')
    assert run.stderr.rstrip().splitlines()[-1].startswith('error: the hardware is not ready')


@pytest.mark.parametrize('skip', ['checks:=false', '--no-checks'])
def test_a_hardware_launch_told_not_to_check_starts_its_nodes_anyway(tmp_path, skip):
    log = tmp_path / 'launch.log'
    with open(log, 'w') as out:
        launcher = subprocess.Popen(
            [BIN / 'tactex', 'launch', 'robot', f'sensor_port:={tmp_path / "ttyACM0"}',
             f'arm_port:={tmp_path / "ttyUSB0"}', skip], stdout=out, stderr=subprocess.STDOUT,
            env=dict(os.environ, PYTHONUNBUFFERED='1'))
        try:
            assert wait_for(lambda: '[launch] started' in log.read_text(), 60), log.read_text()
            assert 'hardware is not ready' not in log.read_text()
        finally:
            stop([launcher], signal.SIGINT)


def test_a_hardware_launch_on_ready_hardware_starts_its_nodes(emulators, tmp_path):
    log = tmp_path / 'launch.log'
    with open(log, 'w') as out:
        launcher = subprocess.Popen(
            [BIN / 'tactex', 'launch', 'robot', f'sensor_port:={emulators["teensy"]}',
             f'arm_port:={emulators["dynamixel"]}'], stdout=out, stderr=subprocess.STDOUT,
            env=dict(os.environ, PYTHONUNBUFFERED='1'))
        try:
            assert wait_for(lambda: log.read_text().count('[launch] started') == 3, 60), \
                log.read_text()
        finally:
            stop([launcher], signal.SIGINT)
