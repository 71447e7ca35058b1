# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The bus on dynamixel-sdk against the Protocol 2.0 emulator, byte for byte on a pty."""

import time

import numpy as np
import pytest

from tactex_driver import control_table as ct
from tactex_driver.bus import ServoBus
from tactex_driver.errors import CommunicationError, DriverError, HardwareAlert
from tactex_driver.servo_emulator import crc16, status_packet, stuff, unstuff


def test_crc_matches_the_sdk():
    import dynamixel_sdk as sdk
    packet = list(b'\xff\xff\xfd\x00\x01\x07\x00\x02\x84\x00\x04\x00')
    assert crc16(bytes(packet)) == sdk.PacketHandler(2.0).updateCRC(0, packet, len(packet))


def test_byte_stuffing_roundtrip():
    body = b'\x01\xff\xff\xfd\x02\xff\xff\xfd'
    assert stuff(body) == b'\x01\xff\xff\xfd\xfd\x02\xff\xff\xfd\xfd'
    assert unstuff(stuff(body)) == body


def test_status_packet_with_stuffed_data_is_read_by_the_sdk(bus, chain):
    # A present position of -3 counts is FD FF FF FF: with its neighbours it needs stuffing.
    servo = chain.servos[11]
    servo.position = -3.0
    servo.advance(0.0)
    assert bus.read_state().positions[0] == pytest.approx(ct.position_to_rad(-3))
    assert status_packet(11, 0, b'\xff\xff\xfd').count(b'\xff\xff\xfd\xfd') == 1


def test_ping_reports_xm430_models(bus):
    assert bus.ping() == {i: ct.XM430_W350_MODEL for i in (11, 12, 13, 14, 15)}


def test_one_sync_read_gives_all_five_servos(bus, chain):
    before = chain.packets_handled
    state = bus.read_state()
    assert chain.packets_handled == before + 1
    assert state.positions.shape == (5,) and state.alerts == ()
    np.testing.assert_allclose(state.positions, 0.0)


def test_goals_move_the_servos_under_torque_only(bus, chain):
    goals = [0.4, -0.3, 0.2, 0.1, 0.0]
    bus.write_goals(goals)
    time.sleep(0.3)
    np.testing.assert_allclose(bus.read_state().positions, 0.0)  # torque off: no motion
    bus.set_torque(True)
    bus.write_goals(goals)
    time.sleep(0.5)
    np.testing.assert_allclose(bus.read_state().positions, goals, atol=2 * ct.RAD_PER_COUNT)


def test_profile_velocity_limits_the_speed(bus, chain):
    bus.write_word(ct.PROFILE_VELOCITY, int(ct.rad_s_to_velocity(0.5)))
    bus.set_torque(True)
    bus.write_goals([1.0, 0, 0, 0, 0])
    time.sleep(0.4)
    assert 0.1 < bus.read_state().positions[0] < 0.3  # 0.5 rad/s for ~0.4 s


def test_a_silent_servo_is_a_communication_error(bus, chain):
    chain.silence(13)
    with pytest.raises(CommunicationError, match='servo 13'):
        bus.read_state()
    chain.silence(13, False)
    assert bus.read_state().positions.shape == (5,)


def test_a_corrupt_status_packet_is_a_communication_error(bus, chain):
    chain.corrupt_next_status(12)
    with pytest.raises(CommunicationError, match='servo 12'):
        bus.read_state()
    assert bus.read_state().positions.shape == (5,)


def test_overload_sets_the_alert_and_reboot_clears_it(bus, chain):
    bus.set_torque(True)
    chain.overload(14)
    assert bus.read_state().alerts == (14,)
    assert bus.hardware_errors()[14] == ct.ERROR_OVERLOAD
    with pytest.raises(HardwareAlert, match='servo 14'):
        bus.set_torque(True)
    bus.reboot(14)
    assert bus.hardware_errors()[14] == 0 and bus.read_state().alerts == ()


def test_eeprom_write_with_torque_on_is_refused(bus):
    bus.set_torque(True)
    with pytest.raises(CommunicationError, match='not available to target address'):
        bus.write_byte(ct.OPERATING_MODE, ct.MODE_POSITION)


def test_closed_bus_and_missing_port_fail_clearly(tmp_path):
    bus = ServoBus(str(tmp_path / 'nothing'))
    with pytest.raises(CommunicationError, match='cannot open'):
        bus.open()
    with pytest.raises(DriverError, match='closed'):
        bus.read_state()
    with pytest.raises(ValueError, match='distinct'):
        ServoBus('x', ids=(1, 1))
