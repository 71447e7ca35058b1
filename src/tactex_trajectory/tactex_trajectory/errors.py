# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Errors of the sweep planner: one base, one class per stage that can refuse a sweep."""


class TrajectoryError(Exception):
    """Base of every tactex_trajectory error; the message says what to change."""


class PathError(TrajectoryError):
    """The pathway gives no usable curve (too few contacts, malformed arrays, too short)."""


class SweepRefused(TrajectoryError):
    """The arm cannot sweep the path as asked.

    Out of reach, a pose residual over the tolerance, an IK branch switch, a joint limit,
    or a speed the joints cannot follow; the message names the sample and the fix.
    """
