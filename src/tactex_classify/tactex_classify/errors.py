# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Errors of tactex_classify: bad bags, datasets, windows, checkpoints; unfit models."""


class ClassifyError(Exception):
    """Base of every tactex_classify error."""


class BagError(ClassifyError):
    """A recording cannot be read or holds no usable tactile data."""


class DatasetError(ClassifyError):
    """A dataset file or its sidecar breaks the format."""


class WindowError(ClassifyError):
    """A dataset's windows are too short for a model's layers."""


class NotFittedError(ClassifyError):
    """A model or scaler was used before `fit`."""


class CheckpointError(ClassifyError):
    """A checkpoint is missing, malformed, or holds something other than weights."""


class ExportError(ClassifyError):
    """A model cannot be exported, or its export does not reproduce it."""
