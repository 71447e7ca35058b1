# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Errors of tactex_classify: unreadable bags, bad datasets, unfit models, bad checkpoints."""


class ClassifyError(Exception):
    """Base of every tactex_classify error."""


class BagError(ClassifyError):
    """A recording cannot be read or holds no usable tactile data."""


class DatasetError(ClassifyError):
    """A dataset file or its sidecar breaks the format."""


class NotFittedError(ClassifyError):
    """A model or scaler was used before `fit`."""


class CheckpointError(ClassifyError):
    """A checkpoint is missing, malformed, or holds something other than weights."""


class ExportError(ClassifyError):
    """A model cannot be exported, or its export does not reproduce it."""
