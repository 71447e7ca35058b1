# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex demo`: `pipeline` (the stages), `session` (the client of the launched nodes), `figures`.

`tactex.commands.demo` is the command line around them; `bench/soak.py` reuses the
pipeline and the session for the soak test (`tactex.soak`).
"""
