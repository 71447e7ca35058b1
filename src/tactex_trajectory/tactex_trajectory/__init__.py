# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Pathway to edge-offset sweep poses, timing and the trajectory executor."""
