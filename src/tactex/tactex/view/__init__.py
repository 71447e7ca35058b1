# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The Foxglove live view: `channels` (what is shown, pure), `server` (the node), `view_node`."""
