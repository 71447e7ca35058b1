# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Robot model of the arm and tactile module: geometry, URDF, MJCF, FK/IK."""
