# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Errors of the arm driver: one base, one class per way the bus or a command can fail."""


class DriverError(Exception):
    """Base of every tactex_driver error."""


class CommunicationError(DriverError):
    """A servo did not answer, or answered with a corrupt or error status packet."""


class HardwareAlert(DriverError):
    """A servo reports a hardware error (overload, overheating, ...) and has stopped."""

    def __init__(self, servo: int, message: str) -> None:
        super().__init__(message)
        self.servo = servo


class TrajectoryRejected(DriverError):
    """A trajectory was refused as a whole; nothing of it was executed."""
