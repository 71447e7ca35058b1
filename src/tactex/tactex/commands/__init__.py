# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Subcommands of the tactex command line, one module each."""
