# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex sim collect` with one worker against two, in the same run, on the same sweeps.

Records `--sweeps` sweeps of every texture of the uneven-texture scene once with
`--workers 1` (in process) and once with `--workers 2` (a local Ray instance of two
cores, its start included), checks that both wrote the same bags byte for byte, and
keeps the times and the load average in bench/results/sim_collect.json.
"""

import argparse
import json
import os
from pathlib import Path
import subprocess
import sys
import tempfile
import time

RESULTS = Path(__file__).parent / 'results'
TACTEX = str(Path(sys.executable).parent / 'tactex')


def main() -> int:
    """Time both, compare the bags, keep the record."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('--sweeps', type=int, default=2, help='sweeps per texture (2)')
    args = parser.parse_args()
    record = {'sweeps': 12 * args.sweeps, 'load_before': os.getloadavg()[0], 'runs': {}}
    with tempfile.TemporaryDirectory() as folder:
        for workers in (1, 2):
            out = Path(folder) / f'workers{workers}'
            start = time.monotonic()
            subprocess.run([TACTEX, 'sim', 'collect', '--sweeps', str(args.sweeps), '--workers',
                            str(workers), '--out', str(out)], check=True,
                           stdout=subprocess.DEVNULL)
            record['runs'][str(workers)] = round(time.monotonic() - start, 1)
            print(f'{workers} worker(s): {record["runs"][str(workers)]} s', flush=True)
        one, two = (sorted(p for p in (Path(folder) / f'workers{w}').rglob('*') if p.is_file())
                    for w in (1, 2))
        record['same_bags'] = [p.relative_to(Path(folder) / 'workers1') for p in one] == [
            p.relative_to(Path(folder) / 'workers2') for p in two] and all(
            a.read_bytes() == b.read_bytes() for a, b in zip(one, two, strict=True))
    record['load_after'] = os.getloadavg()[0]
    record['speedup'] = record['runs']['1'] / record['runs']['2']
    print(json.dumps(record))
    (RESULTS / 'sim_collect.json').write_text(json.dumps(record, indent=2) + '\n',
                                              encoding='utf-8')
    return 0


if __name__ == '__main__':
    sys.exit(main())
