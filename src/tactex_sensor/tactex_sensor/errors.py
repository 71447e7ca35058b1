# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Errors of tactex_sensor: readings that carry no usable information."""


class SensorError(Exception):
    """Base of every tactex_sensor error."""


class ReadingError(SensorError, ValueError):
    """A reading is unusable (not finite, zero, or the wrong shape); the message quotes it."""


class FrameError(SensorError, ValueError):
    """A sample cannot be put into a protocol frame (a value beyond float32, a bad integer)."""
