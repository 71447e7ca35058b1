# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Helpers the tests share: processes, bags, bad inputs, live streams, ROS launch."""
