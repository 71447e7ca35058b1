# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Errors of the shared plumbing: bad tables and files, foreign links, refused parameters."""


class CommonError(Exception):
    """Base of every tactex_common error."""


class TableError(CommonError, ValueError):
    """A text table (CSV) cannot be read; the message names the file and, where known, line."""


class RefusedFileError(CommonError, OSError):
    """A path given as a file is no regular file (a FIFO, device, folder) or is too large."""


class LinkError(CommonError, OSError):
    """A path given for a pty link holds something the tool did not create."""


class ClusterError(CommonError):
    """Ray cannot be started or reached, or is asked for something it cannot give."""


class NodeParameterError(CommonError, ValueError):
    """A node parameter has a value the node refuses; the message says what is allowed."""


class GpuSharingError(CommonError):
    """NVIDIA's Multi-Process Service cannot be started, or a GPU program cannot use it."""
