# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Dynamixel Protocol 2.0 bus and arm driver node for the OpenMANIPULATOR-X."""
