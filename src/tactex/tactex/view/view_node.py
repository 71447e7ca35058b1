# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""view_node: the Foxglove live view (tactex.view.server) as a node process."""

from __future__ import annotations

from tactex.view.server import serve


def main(args: list[str] | None = None) -> None:
    """Run the node until shutdown."""
    serve(args)
