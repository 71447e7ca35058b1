# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Run every benchmark in bench/ (bench_*.py), print and keep each one's output in results/."""

from pathlib import Path
import subprocess
import sys

RESULTS = Path(__file__).parent / 'results'


def main() -> int:
    """Run the benchmarks; return the first non-zero exit code, else 0."""
    RESULTS.mkdir(exist_ok=True)
    for script in sorted(Path(__file__).parent.glob('bench_*.py')):
        print(f'== {script.name}', flush=True)
        run = subprocess.run([sys.executable, str(script)], capture_output=True, text=True)
        print(run.stdout, end='', flush=True)
        if run.returncode:
            print(run.stderr, file=sys.stderr)
            return run.returncode
        (RESULTS / f'{script.stem}.txt').write_text(run.stdout, encoding='utf-8')
    return 0


if __name__ == '__main__':
    sys.exit(main())
