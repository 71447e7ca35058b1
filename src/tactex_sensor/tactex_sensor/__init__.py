# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Teensy wire protocol, serial publisher node and Madgwick orientation filter."""
