# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Errors of the shared plumbing: unreadable tables, links that are not ours to replace."""


class CommonError(Exception):
    """Base of every tactex_common error."""


class TableError(CommonError, ValueError):
    """A text table (CSV) cannot be read; the message names the file and, where known, line."""


class LinkError(CommonError, OSError):
    """A path given for a pty link holds something the tool did not create."""
