# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Where a tactex package's shared files (urdf/, config/, launch/) are on this machine.

An installed package (colcon, or pip without -e) is found through the ament index
(AMENT_PREFIX_PATH); an editable install in a source checkout uses the checkout
itself, where `tactex` shares the workspace's top-level config/ and launch/.
"""

from __future__ import annotations

import os
from pathlib import Path

WORKSPACE_ROOT = Path(__file__).resolve().parents[3]


def share_directory(package: str) -> Path:
    """Return the share directory of `package`.

    Raises:
        FileNotFoundError: the package is neither installed nor in a source checkout.
    """
    if os.environ.get('AMENT_PREFIX_PATH'):
        from ament_index_python.packages import get_package_share_directory, PackageNotFoundError
        try:
            return Path(get_package_share_directory(package))
        except PackageNotFoundError:
            pass
    source = WORKSPACE_ROOT / 'src' / package
    if (source / 'package.xml').is_file():
        return WORKSPACE_ROOT if package == 'tactex' else source
    raise FileNotFoundError(
        f'cannot find the share directory of {package!r}: source the workspace '
        f'(install/setup.bash) or install it with `make test` from the repository root')
