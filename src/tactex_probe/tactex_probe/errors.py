# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Errors of the probing package: one base, one class per way probing can be refused."""


class ProbeError(Exception):
    """Base of every tactex_probe error."""


class ParameterError(ProbeError, ValueError):
    """A probing parameter is missing, not finite or outside its range; the message says which."""


class PathwayError(ProbeError):
    """A pathway file cannot be read or breaks the format; the message names the file and key."""
