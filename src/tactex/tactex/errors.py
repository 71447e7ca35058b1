# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Errors of the tactex command line."""


class CommandError(Exception):
    """A bad command-line value or path; the message names the option and the fix."""
