# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""MuJoCo bridge standing in for the arm and the tactile sensor: scenes, effects."""
