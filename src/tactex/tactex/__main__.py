# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Run the tactex command line as `python -m tactex`."""

import sys

from tactex.cli import main

sys.exit(main())
