# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Contact detection, surface normals and the probe-and-broadcast node."""
