# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Run every benchmark in bench/ (bench_*.py) in turn and stop at the first failure."""

from pathlib import Path
import subprocess
import sys


def main() -> int:
    """Run the benchmarks and return the first non-zero exit code, else 0."""
    for script in sorted(Path(__file__).parent.glob('bench_*.py')):
        print(f'== {script.name}', flush=True)
        code = subprocess.call([sys.executable, str(script)])
        if code:
            return code
    return 0


if __name__ == '__main__':
    sys.exit(main())
