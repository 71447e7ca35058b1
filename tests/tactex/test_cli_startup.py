# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The command line starts fast: building it imports neither torch nor rclpy."""

import subprocess
import sys

import pytest

HEAVY = ('torch', 'rclpy', 'mujoco', 'sklearn', 'matplotlib')


@pytest.mark.parametrize('argv', [['--help'], ['train', '--help'], ['convert', '--help'],
                                  ['sim', '--help'], ['import', '--help'],
                                  ['predict', '--help'], ['bag', 'play', '--help']])
def test_help_imports_no_heavy_library(argv):
    code = ('import sys\n'
            'from tactex.cli import main\n'
            'try:\n'
            f'    main({argv!r})\n'
            'except SystemExit:\n'
            '    pass\n'
            f'print(sorted(m for m in {HEAVY!r} if m in sys.modules))\n')
    result = subprocess.run([sys.executable, '-c', code], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip().splitlines()[-1] == '[]'
