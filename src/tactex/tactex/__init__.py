# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Bring-up: launch files, parameter files and the tactex command line."""
