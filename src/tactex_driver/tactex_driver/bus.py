# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The Dynamixel Protocol 2.0 bus of the arm, on ROBOTIS's dynamixel-sdk (no ROS).

One sync read fetches present current, velocity and position of every servo in a single
transaction; one GroupSyncWrite sends every goal position. Values cross this
module's boundary in SI units (rad, rad/s, A); raw counts stay inside.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
import struct

import dynamixel_sdk as sdk
import numpy as np

from tactex_common.constants import SERVO_IDS
from tactex_driver import control_table as ct
from tactex_driver.errors import CommunicationError, DriverError, HardwareAlert

DEFAULT_BAUD = 1_000_000


@dataclass(frozen=True)
class BusState:
    """One read of every servo: angles (rad), rates (rad/s), currents (A), in ID order."""

    positions: np.ndarray
    velocities: np.ndarray
    currents: np.ndarray
    alerts: tuple[int, ...]  # IDs whose status packet had the hardware-alert bit


class ServoBus:
    """The servos on one serial port.

    Args:
        port: device (`/dev/ttyUSB0`, a udev name, or an emulator's pty).
        baud: line rate (the servos' setting; 1 Mbps by default).
        ids: servo IDs in joint order.
        port_handler: injectable for tests; dynamixel-sdk's PortHandler by default.
    """

    def __init__(self, port: str, *, baud: int = DEFAULT_BAUD,
                 ids: Sequence[int] = SERVO_IDS, port_handler=None) -> None:
        if len(set(ids)) != len(ids) or not all(0 <= i <= 252 for i in ids):
            raise ValueError(f'servo IDs must be distinct and in 0..252, got {list(ids)!r}')
        self.ids = tuple(int(i) for i in ids)
        self.baud = int(baud)
        self._port = port_handler or sdk.PortHandler(port)
        self._packets = sdk.PacketHandler(2.0)
        self._writer = sdk.GroupSyncWrite(self._port, self._packets, ct.GOAL_POSITION, 4)
        self._open = False

    @property
    def is_open(self) -> bool:
        """True between `open` and `close`."""
        return self._open

    @property
    def port_name(self) -> str:
        """The serial device."""
        return self._port.getPortName()

    def __enter__(self) -> ServoBus:
        self.open()
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()

    def open(self) -> None:
        """Open the port at the baud rate.

        Raises:
            CommunicationError: the port cannot be opened or the baud rate is not supported.
        """
        try:
            opened = self._port.openPort() and self._port.setBaudRate(self.baud)
        except (OSError, ValueError) as err:  # pyserial's SerialException is an OSError
            raise CommunicationError(f'cannot open {self._port.getPortName()!r}: {err}') from err
        if not opened:
            raise CommunicationError(f'cannot open {self._port.getPortName()!r} at '
                                     f'{self.baud} baud')
        self._open = True

    def close(self) -> None:
        """Close the port; safe to call twice."""
        if self._open:
            self._port.closePort()
        self._open = False

    def _check_open(self) -> None:
        if not self._open:
            raise DriverError('the servo bus is closed')

    def ping(self) -> dict[int, int]:
        """Return the model number of every servo.

        Raises:
            CommunicationError: a servo does not answer.
        """
        self._check_open()
        models = {}
        for servo in self.ids:
            model, result, error = self._packets.ping(self._port, servo)
            self._raise_for(result, error, servo, 'ping')
            models[servo] = model
        return models

    def answering(self) -> dict[int, int]:
        """Model number of every servo that answers a ping (the silent ones left out)."""
        self._check_open()
        models = {}
        for servo in self.ids:
            model, result, _error = self._packets.ping(self._port, servo)
            if result == sdk.COMM_SUCCESS:
                models[servo] = model
        return models

    def write_byte(self, address: int, values: Sequence[int] | int) -> None:
        """Write one byte to every servo (a value each, or one for all), acknowledged."""
        self._check_open()
        values = [values] * len(self.ids) if isinstance(values, int) else list(values)
        for servo, value in zip(self.ids, values, strict=True):
            result, error = self._packets.write1ByteTxRx(self._port, servo, address, int(value))
            self._raise_for(result, error, servo, f'write address {address}')

    def write_word(self, address: int, values: Sequence[int] | int) -> None:
        """Write a 4-byte value to every servo (a value each, or one for all), acknowledged."""
        self._check_open()
        values = [values] * len(self.ids) if isinstance(values, int) else list(values)
        for servo, value in zip(self.ids, values, strict=True):
            result, error = self._packets.write4ByteTxRx(self._port, servo, address,
                                                         int(value) & 0xFFFFFFFF)
            self._raise_for(result, error, servo, f'write address {address}')

    def read_byte(self, address: int) -> dict[int, int]:
        """Read one byte from every servo."""
        return self.read_unsigned(address, 1)

    def read_unsigned(self, address: int, size: int, ids: Sequence[int] | None = None
                      ) -> dict[int, int]:
        """Read an unsigned 1-, 2- or 4-byte value from every servo (or those of `ids`)."""
        self._check_open()
        read = {1: self._packets.read1ByteTxRx, 2: self._packets.read2ByteTxRx,
                4: self._packets.read4ByteTxRx}[size]
        values = {}
        for servo in self.ids if ids is None else ids:
            value, result, error = read(self._port, servo, address)
            self._raise_for(result, error, servo, f'read address {address}', alert_ok=True)
            values[servo] = value
        return values

    def set_torque(self, enabled: bool) -> None:
        """Enable or disable torque on every servo."""
        self.write_byte(ct.TORQUE_ENABLE, 1 if enabled else 0)

    def hardware_errors(self) -> dict[int, int]:
        """Hardware error status of every servo (0 when healthy)."""
        return self.read_byte(ct.HARDWARE_ERROR_STATUS)

    def reboot(self, servo: int) -> None:
        """Reboot one servo (clears a hardware error; torque comes back disabled)."""
        self._check_open()
        result, error = self._packets.reboot(self._port, servo)
        self._raise_for(result, error, servo, 'reboot', alert_ok=True)

    def read_state(self) -> BusState:
        """Read current, velocity and position of every servo in one sync read.

        Raises:
            CommunicationError: a servo did not answer or its answer was corrupt.
        """
        self._check_open()
        # The sync read instruction as GroupSyncRead sends it, with each status packet
        # read through the packet handler so its error byte (hardware alert) is kept.
        result = self._packets.syncReadTx(self._port, ct.STATE_BLOCK_START,
                                          ct.STATE_BLOCK_LENGTH, list(self.ids),
                                          len(self.ids), False)
        if result != sdk.COMM_SUCCESS:
            raise CommunicationError(f'sync read failed: {self._packets.getTxRxResult(result)}')
        raw = np.empty((len(self.ids), 3), dtype=np.int64)
        alerts = []
        for row, servo in enumerate(self.ids):
            data, result, error = self._packets.readRx(self._port, servo, ct.STATE_BLOCK_LENGTH)
            if result != sdk.COMM_SUCCESS:
                raise CommunicationError(
                    f'servo {servo}: sync read: {self._packets.getTxRxResult(result)}')
            raw[row] = struct.unpack('<hii', bytes(data))
            if error & sdk.ERRBIT_ALERT:
                alerts.append(servo)
        return BusState(positions=ct.position_to_rad(raw[:, 2]),
                        velocities=ct.velocity_to_rad_s(raw[:, 1]),
                        currents=ct.current_to_ampere(raw[:, 0]), alerts=tuple(alerts))

    def write_goals(self, positions_rad: Sequence[float]) -> None:
        """Send every goal position (rad) in one sync write (unacknowledged by design)."""
        self._check_open()
        counts = ct.rad_to_position(positions_rad)
        if counts.shape != (len(self.ids),):
            raise ValueError(f'expected {len(self.ids)} goals, got shape {counts.shape!r}')
        self._writer.clearParam()
        for servo, count in zip(self.ids, counts, strict=True):
            self._writer.addParam(servo, list(struct.pack('<i', int(count))))
        result = self._writer.txPacket()
        if result != sdk.COMM_SUCCESS:
            raise CommunicationError(f'sync write failed: {self._packets.getTxRxResult(result)}')

    def _raise_for(self, result: int, error: int, servo: int, action: str, *,
                   alert_ok: bool = False) -> None:
        if result != sdk.COMM_SUCCESS:
            raise CommunicationError(
                f'servo {servo}: {action}: {self._packets.getTxRxResult(result)}')
        if error & sdk.ERRBIT_ALERT and not alert_ok:
            raise HardwareAlert(servo, f'servo {servo}: {action}: hardware alert; read '
                                       f'hardware error status (address 70) and reboot')
        if error & 0x7F:
            raise CommunicationError(
                f'servo {servo}: {action}: {self._packets.getRxPacketError(error)}')
