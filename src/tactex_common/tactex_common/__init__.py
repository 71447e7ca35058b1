# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What every tactex package shares: topic names, QoS, channel order, constants, node helpers."""
