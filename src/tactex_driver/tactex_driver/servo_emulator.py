# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""A chain of XM430-W350 servos speaking Dynamixel Protocol 2.0 on a pseudo-terminal.

It answers ping, read, write, sync read, sync write and reboot with proper status
packets (byte stuffing, CRC-16, error byte with the alert bit), moves each servo towards
its goal under its profile velocity with first-order dynamics, records every goal it
is sent, and injects faults on request: a servo that stops answering, a corrupt status
packet, an overload.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import os
from pathlib import Path
import select
import struct
import threading
import time

from tactex_common.constants import SERVO_IDS
from tactex_common.pty_link import PtyLink
from tactex_driver import control_table as ct

HEADER = b'\xff\xff\xfd\x00'
BROADCAST_ID = 0xFE
PING, READ, WRITE, REBOOT, STATUS, SYNC_READ, SYNC_WRITE = 0x01, 0x02, 0x03, 0x08, 0x55, 0x82, 0x83
ERROR_CRC, ERROR_INSTRUCTION, ERROR_DATA_RANGE, ERROR_ACCESS = 0x03, 0x02, 0x04, 0x07
ALERT = 0x80
EEPROM_END = ct.TORQUE_ENABLE  # EEPROM addresses below this are writable with torque off only
MAX_RATE_COUNTS_S = 4.8 / ct.RAD_PER_COUNT  # unloaded speed at 12 V
TIME_CONSTANT_S = 0.03


def _crc_table() -> list[int]:
    table = []
    for byte in range(256):
        crc = byte << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x8005) if crc & 0x8000 else crc << 1
        table.append(crc & 0xFFFF)
    return table


_CRC_TABLE = _crc_table()


def crc16(data: bytes) -> int:
    """Dynamixel's CRC-16 (poly 0x8005, init 0, no reflection)."""
    crc = 0
    for byte in data:
        crc = ((crc << 8) ^ _CRC_TABLE[((crc >> 8) ^ byte) & 0xFF]) & 0xFFFF
    return crc


def stuff(body: bytes) -> bytes:
    """Insert 0xFD after every FF FF FD in a packet body (after the header)."""
    return body.replace(b'\xff\xff\xfd', b'\xff\xff\xfd\xfd')


def unstuff(body: bytes) -> bytes:
    """Undo `stuff`."""
    return body.replace(b'\xff\xff\xfd\xfd', b'\xff\xff\xfd')


def status_packet(servo: int, error: int, params: bytes = b'', *, corrupt: bool = False
                  ) -> bytes:
    """A status packet from `servo`, stuffed, with its CRC (wrong when `corrupt`)."""
    region = stuff(bytes([STATUS, error]) + params)
    packet = HEADER + bytes([servo]) + struct.pack('<H', len(region) + 2) + region
    crc = crc16(packet) ^ (0xFFFF if corrupt else 0)
    return packet + struct.pack('<H', crc)


@dataclass
class Servo:
    """One emulated servo: its control table and continuous position (counts)."""

    servo_id: int
    table: bytearray = field(default_factory=lambda: bytearray(ct.TABLE_SIZE))
    position: float = float(ct.CENTER_COUNT)
    rate: float = 0.0
    silent: bool = False
    corrupt_next: int = 0

    def __post_init__(self) -> None:
        """Fill the factory values of the control table."""
        struct.pack_into('<H', self.table, ct.MODEL_NUMBER, ct.XM430_W350_MODEL)
        self.table[ct.FIRMWARE_VERSION] = 48
        self.table[ct.ID] = self.servo_id
        self.table[ct.OPERATING_MODE] = ct.MODE_POSITION
        self.table[ct.BAUD_RATE] = 3  # 1 Mbps, as the OpenMANIPULATOR-X ships
        self.table[ct.TEMPERATURE_LIMIT] = 80
        struct.pack_into('<HH', self.table, ct.MAX_VOLTAGE_LIMIT, 160, 95)
        struct.pack_into('<ii', self.table, ct.MAX_POSITION_LIMIT, 4095, 0)
        struct.pack_into('<H', self.table, ct.PRESENT_INPUT_VOLTAGE, 120)  # 12.0 V supply
        self.table[ct.PRESENT_TEMPERATURE] = 32
        struct.pack_into('<i', self.table, ct.GOAL_POSITION, int(self.position))
        self._publish()

    def word(self, address: int) -> int:
        """Signed 4-byte value at `address`."""
        return struct.unpack_from('<i', self.table, address)[0]

    def advance(self, dt: float) -> None:
        """Move towards the goal for `dt` seconds if torque is on and no error latched."""
        if self.table[ct.TORQUE_ENABLE] and not self.table[ct.HARDWARE_ERROR_STATUS]:
            profile = self.word(ct.PROFILE_VELOCITY)
            limit = MAX_RATE_COUNTS_S if profile <= 0 else min(
                MAX_RATE_COUNTS_S, profile * ct.RAD_S_PER_VELOCITY_UNIT / ct.RAD_PER_COUNT)
            error = self.word(ct.GOAL_POSITION) - self.position
            self.rate = max(-limit, min(limit, error / TIME_CONSTANT_S))
            step = self.rate * dt
            self.position += step if abs(step) < abs(error) else error
        else:
            self.rate = 0.0
        self._publish()

    def _publish(self) -> None:
        velocity_units = self.rate * ct.RAD_PER_COUNT / ct.RAD_S_PER_VELOCITY_UNIT
        current_units = 40.0 + 0.05 * velocity_units  # holding load plus friction
        struct.pack_into('<h', self.table, ct.PRESENT_CURRENT, int(current_units))
        struct.pack_into('<i', self.table, ct.PRESENT_VELOCITY, int(round(velocity_units)))
        struct.pack_into('<i', self.table, ct.PRESENT_POSITION, int(round(self.position)))
        self.table[ct.MOVING] = 1 if abs(self.rate) > 1.0 else 0


class ServoChainEmulator:
    """Servos `ids` on a pty; `link` is a stable symlink to it.

    Args:
        link: path to create as a symlink to the pty's slave side.
        ids: servo IDs on the chain.
        initial_rad: starting angle of each servo (rad), default 0.
    """

    def __init__(self, link: Path, ids=SERVO_IDS, *,
                 initial_rad: dict[int, float] | None = None) -> None:
        self.link = Path(link)
        self.servos = {i: Servo(i) for i in ids}
        for servo_id, angle in (initial_rad or {}).items():
            servo = self.servos[servo_id]
            servo.position = float(ct.rad_to_position(angle))
            struct.pack_into('<i', servo.table, ct.GOAL_POSITION, int(servo.position))
            servo.advance(0.0)
        self.goal_history: list[tuple[float, int, int]] = []
        self.packets_handled = 0
        self.crc_errors = 0
        self._lock = threading.Lock()
        self._pty = PtyLink(self.link)
        self._thread: threading.Thread | None = None
        self._running = False
        self._last_advance = time.monotonic()

    # -- life cycle -------------------------------------------------------------------
    def __enter__(self) -> ServoChainEmulator:
        self.start()
        return self

    def __exit__(self, *exc_info) -> None:
        self.stop()

    def start(self) -> None:
        """Open the pty, link it, and serve in a background thread."""
        self._pty.open()
        self._running = True
        self._thread = threading.Thread(target=self._serve, name='servo_emulator', daemon=True)
        self._thread.start()

    def stop(self) -> None:
        """Stop serving and remove the pty and link; safe to call twice."""
        self._running = False
        if self._thread is not None:
            self._thread.join(timeout=2.0)
        self._pty.close()
        self._thread = None

    # -- faults -------------------------------------------------------------------------
    def silence(self, servo_id: int, silent: bool = True) -> None:
        """Make a servo stop (or resume) answering."""
        self.servos[servo_id].silent = silent

    def corrupt_next_status(self, servo_id: int, count: int = 1) -> None:
        """Send the next `count` status packets of a servo with a wrong CRC."""
        self.servos[servo_id].corrupt_next += count

    def overload(self, servo_id: int) -> None:
        """Latch an overload error: torque drops and every status carries the alert bit."""
        with self._lock:
            servo = self.servos[servo_id]
            servo.table[ct.HARDWARE_ERROR_STATUS] |= ct.ERROR_OVERLOAD
            servo.table[ct.TORQUE_ENABLE] = 0

    # -- protocol -----------------------------------------------------------------------
    def _serve(self) -> None:
        buffer = bytearray()
        while self._running:
            ready, _, _ = select.select([self._pty.master], [], [], 0.005)
            self._advance()
            if not ready:
                continue
            try:
                buffer += os.read(self._pty.master, 4096)
            except OSError:
                continue
            while True:
                packet, consumed = self._next_packet(buffer)
                if consumed == 0:
                    break
                del buffer[:consumed]
                if packet is not None:
                    self._handle(*packet)

    def _advance(self) -> None:
        now = time.monotonic()
        with self._lock:
            dt, self._last_advance = now - self._last_advance, now
            for servo in self.servos.values():
                servo.advance(dt)

    def _next_packet(self, buffer: bytearray):
        """Return ((id, instruction, params) or None, bytes consumed); (None, 0) = need more."""
        start = buffer.find(HEADER)
        if start < 0:
            keep = max(0, len(buffer) - 3)
            return None, keep
        if len(buffer) - start < 7:
            return None, 0 if start == 0 else start
        length = buffer[start + 5] | (buffer[start + 6] << 8)
        end = start + 7 + length
        if len(buffer) < end:
            return None, 0 if start == 0 else start
        raw = bytes(buffer[start:end])
        servo_id, instruction = raw[4], raw[7]
        if crc16(raw[:-2]) != struct.unpack('<H', raw[-2:])[0]:
            self.crc_errors += 1
            if servo_id in self.servos:
                self._reply(servo_id, ERROR_CRC)
            return None, end
        params = unstuff(raw[8:-2])
        return (servo_id, instruction, params), end

    def _reply(self, servo_id: int, error: int, params: bytes = b'') -> None:
        servo = self.servos[servo_id]
        if servo.silent:
            return
        if servo.table[ct.HARDWARE_ERROR_STATUS]:
            error |= ALERT
        corrupt = servo.corrupt_next > 0
        servo.corrupt_next -= 1 if corrupt else 0
        os.write(self._pty.master, status_packet(servo_id, error, params, corrupt=corrupt))

    def _handle(self, servo_id: int, instruction: int, params: bytes) -> None:
        self.packets_handled += 1
        with self._lock:
            if instruction == SYNC_READ and servo_id == BROADCAST_ID and len(params) >= 4:
                address, size = struct.unpack_from('<HH', params)
                for target in params[4:]:
                    if target in self.servos and not self.servos[target].silent:
                        table = self.servos[target].table
                        self._reply(target, 0, bytes(table[address:address + size]))
                    else:
                        break  # the chain waits for the missing servo: the rest stay silent
            elif instruction == SYNC_WRITE and servo_id == BROADCAST_ID and len(params) >= 4:
                address, size = struct.unpack_from('<HH', params)
                for offset in range(4, len(params) - size + 1, size + 1):
                    target = params[offset]
                    if target in self.servos and not self.servos[target].silent:
                        self._write(self.servos[target], address,
                                    params[offset + 1:offset + 1 + size])
            elif servo_id in self.servos:
                self._unicast(self.servos[servo_id], instruction, params)

    def _unicast(self, servo: Servo, instruction: int, params: bytes) -> None:
        if servo.silent:
            return
        if instruction == PING:
            self._reply(servo.servo_id, 0, bytes(servo.table[0:2]) + bytes([servo.table[6]]))
        elif instruction == READ and len(params) == 4:
            address, size = struct.unpack('<HH', params)
            if address + size > ct.TABLE_SIZE:
                self._reply(servo.servo_id, ERROR_DATA_RANGE)
            else:
                self._reply(servo.servo_id, 0, bytes(servo.table[address:address + size]))
        elif instruction == WRITE and len(params) >= 3:
            address = struct.unpack_from('<H', params)[0]
            self._reply(servo.servo_id, self._write(servo, address, params[2:]))
        elif instruction == REBOOT:
            self._reply(servo.servo_id, 0)
            servo.table[ct.HARDWARE_ERROR_STATUS] = 0
            servo.table[ct.TORQUE_ENABLE] = 0
        else:
            self._reply(servo.servo_id, ERROR_INSTRUCTION)

    def _write(self, servo: Servo, address: int, data: bytes) -> int:
        """Apply a write; return the error number of the status (0 if accepted)."""
        if address + len(data) > ct.TABLE_SIZE:
            return ERROR_DATA_RANGE
        if address < EEPROM_END and servo.table[ct.TORQUE_ENABLE]:
            return ERROR_ACCESS
        if address == ct.TORQUE_ENABLE and servo.table[ct.HARDWARE_ERROR_STATUS] and data[:1] \
                == b'\x01':
            return ERROR_ACCESS  # torque stays off until a reboot clears the error
        servo.table[address:address + len(data)] = data
        if address <= ct.GOAL_POSITION < address + len(data):
            goal = servo.word(ct.GOAL_POSITION)
            self.goal_history.append((time.monotonic(), servo.servo_id, goal))
        return 0
