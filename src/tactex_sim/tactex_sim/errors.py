# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Errors of the simulator: bad scenes and unknown effects or textures."""


class SimError(Exception):
    """Base of every tactex_sim error."""


class SceneError(SimError):
    """A scene file breaks a rule; the message names the file, section and key."""


class UnknownNameError(SimError, KeyError):
    """An effect or texture name that is not registered; the message lists the known ones."""

    def __str__(self) -> str:
        """Plain message (KeyError would quote it)."""
        return str(self.args[0])
