# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Teensy emulator: real frames on a pty, faults as asked, replayed recordings."""

import os
import threading

import numpy as np
import pytest
import serial

from tactex.cli import main
from tactex_common.errors import LinkError
from tactex_common.pty_link import PtyLink
from tactex_sensor.emulator import (
    Fault,
    FaultKind,
    Motion,
    ReplaySource,
    SignalSource,
    TeensyEmulator,
)
from tactex_sensor.protocol import FrameDecoder


def read_stream(link, emulator, duration_s):
    decoder = FrameDecoder()
    samples = []
    with emulator:
        port = serial.Serial(str(link), 250000, timeout=0.05)
        streamer = threading.Thread(target=emulator.run, args=(duration_s,), daemon=True)
        streamer.start()
        while streamer.is_alive():
            samples += decoder.feed(port.read(max(1, port.in_waiting)))
        samples += decoder.feed(port.read(port.in_waiting))
        port.close()
    return samples, decoder.stats


def test_frames_arrive_at_the_rate_with_gravity(tmp_path):
    link = tmp_path / 'teensy'
    samples, stats = read_stream(link, TeensyEmulator(link, 200.0, SignalSource()), 0.5)
    assert 90 <= len(samples) <= 101
    assert stats.dropped == 0 and stats.lost_frames == 0
    assert abs(np.linalg.norm(samples[-1].accel) - 9.81) < 0.2
    assert not link.exists()


def test_faults_are_injected_and_counted(tmp_path):
    link = tmp_path / 'teensy'
    faults = (Fault.parse('garbage@0.1:100'), Fault.parse('crc@0.2:3'),
              Fault.parse('drop@0.3:4'))
    samples, stats = read_stream(link, TeensyEmulator(link, 200.0, SignalSource(),
                                                      faults=faults), 0.6)
    assert stats.crc_errors == 3
    assert stats.lost_frames == 7  # 3 rejected + 4 never sent
    assert stats.discarded_bytes >= 100


def test_fault_spec_errors_name_the_kinds():
    assert Fault.parse('stall@2') == Fault(FaultKind.STALL, 2.0, 0.5)
    with pytest.raises(ValueError, match='garbage, crc, drop, stall, disconnect'):
        Fault.parse('explode@1')
    with pytest.raises(ValueError, match='>= 0'):
        Fault.parse('crc@-1')


def test_replay_interpolates_and_loops(tmp_path):
    recording = tmp_path / 'sweep.csv'
    recording.write_text('t,ax,ay,az,gx,gy,gz,mx,my,mz,baro\n'
                         '0.0,0,0,9.8,0,0,0,1e-5,0,-4e-5,101000\n'
                         '1.0,1,0,9.8,0.2,0,0,1e-5,0,-4e-5,101200\n', encoding='utf-8')
    source = ReplaySource(recording)
    accel, gyro, _, pressure, temperature = source.sample(0.25)
    assert accel[0] == pytest.approx(0.25) and gyro[0] == pytest.approx(0.05)
    assert pressure == pytest.approx(101050.0) and temperature == 24.0
    assert source.sample(1.25)[0][0] == pytest.approx(0.25)


@pytest.mark.parametrize('rows, match', [
    ('0,0,0,9.8,0,0,0,1e-5,0,-4e-5,101000,1e39\n1,0,0,9.8,0,0,0,1e-5,0,-4e-5,101000,24\n',
     "column temp holds values beyond the frame's float32"),
    ('-1e308,0,0,9.8,0,0,0,1e-5,0,-4e-5,101000,24\n1e308,0,0,9.8,0,0,0,1e-5,0,-4e-5,101000,24\n',
     'a finite span')])
def test_replay_refuses_what_no_frame_can_carry_before_streaming(tmp_path, rows, match):
    recording = tmp_path / 'bad.csv'
    recording.write_text('t,ax,ay,az,gx,gy,gz,mx,my,mz,baro,temp\n' + rows, encoding='utf-8')
    with pytest.raises(ValueError, match=match):
        ReplaySource(recording)


def test_replay_rejects_a_file_without_the_channels(tmp_path):
    recording = tmp_path / 'bad.csv'
    recording.write_text('t,ax,ay\n0,0,0\n1,0,0\n', encoding='utf-8')
    with pytest.raises(ValueError, match='missing column'):
        ReplaySource(recording)


def test_cli_reports_a_bad_fault(capsys, tmp_path):
    assert main(['emulate', 'teensy', '--link', str(tmp_path / 'l'), '--fault', 'nope']) == 1
    assert 'error: --fault: bad fault' in capsys.readouterr().err


@pytest.mark.parametrize('device', ['teensy', 'dynamixel'])
def test_a_regular_file_at_the_link_path_is_never_replaced(tmp_path, capsys, device):
    precious = tmp_path / 'notes.txt'
    precious.write_text('hours of work')
    assert main(['emulate', device, '--link', str(precious), '--duration', '0.2']) == 1
    assert precious.read_text() == 'hours of work' and not precious.is_symlink()
    assert 'is an existing file' in capsys.readouterr().err
    with pytest.raises(LinkError, match='existing file'):
        TeensyEmulator(precious, 100.0, SignalSource()).open()
    assert precious.read_text() == 'hours of work'


def test_only_an_emulator_pty_symlink_is_replaced_and_removed(tmp_path):
    other = tmp_path / 'port'
    other.symlink_to('/dev/ttyUSB0')
    with pytest.raises(LinkError, match='not to a pty'):
        PtyLink(other).open()
    assert os.readlink(other) == '/dev/ttyUSB0'
    stale = tmp_path / 'teensy'
    stale.symlink_to('/dev/pts/9999')  # left by a killed emulator
    neighbour = tmp_path / 'teensy.tmp'
    neighbour.write_text('mine')
    link = PtyLink(stale)
    link.open()
    assert os.readlink(stale) != '/dev/pts/9999'
    link.close()
    assert not stale.exists() and not stale.is_symlink() and neighbour.read_text() == 'mine'


@pytest.mark.parametrize('fault', ['stall@0.05:60', 'disconnect@0.05:60'])
def test_duration_is_honoured_during_stalls_and_disconnects(tmp_path, fault):
    emulator = TeensyEmulator(tmp_path / 'teensy', 100.0, SignalSource(),
                              faults=(Fault.parse(fault),))
    with emulator:
        streamer = threading.Thread(target=emulator.run, args=(0.3,), daemon=True)
        streamer.start()
        streamer.join(timeout=15)  # the fault lasts 60 s; the duration ends it
        assert not streamer.is_alive()
    assert not (tmp_path / 'teensy').exists()


def test_sway_motion_moves(tmp_path):
    source = SignalSource(Motion.SWAY, seed=3)
    gyro_a = source.sample(0.0)[1]
    assert np.linalg.norm(gyro_a) > 0.1
