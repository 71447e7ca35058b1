# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The texture results end to end: synthetic set -> dataset -> each classifier's report.

Runs `tactex sim collect` (12 textures x 25 sweeps of the uneven-texture scene),
`tactex convert` (128-sample windows, 50 % overlap) and `tactex train` for the two
baselines and the deep models given on the command line (default: cnn_3 for 80 epochs;
the original's 250 epochs x 8 models take hours on one CPU), each with both CV schemes.
Reports land in bench/results/textures/<model>/.
"""

import argparse
from pathlib import Path
import shutil
import subprocess
import sys
import tempfile

RESULTS = Path(__file__).parent / 'results' / 'textures'
TACTEX = str(Path(sys.executable).parent / 'tactex')


def main() -> int:
    """Collect, convert, train, copy the reports."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('--models', nargs='+', default=['extratrees', 'minirocket', 'cnn_3'])
    parser.add_argument('--epochs', type=int, default=80)
    parser.add_argument('--sweeps', type=int, default=25)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        bags, data = Path(folder) / 'bags', Path(folder) / 'sim128.npz'
        subprocess.run([TACTEX, 'sim', 'collect', '--scene', 'uneven_texture', '--sweeps',
                        str(args.sweeps), '--out', str(bags)], check=True)
        subprocess.run([TACTEX, 'convert', str(bags), '--out', str(data), '--window', '128'],
                       check=True)
        for model in args.models:
            run = Path(folder) / model
            subprocess.run([TACTEX, 'train', str(data), '--model', model, '--epochs',
                            str(args.epochs), '--threads', '2', '--out', str(run),
                            '--no-final'], check=True)
            target = RESULTS / model
            shutil.rmtree(target, ignore_errors=True)
            target.mkdir(parents=True)
            for item in run.iterdir():
                if item.is_file():
                    shutil.copy2(item, target / item.name)
            print((target / 'report.md').read_text(encoding='utf-8').split('## Per class')[0])
    return 0


if __name__ == '__main__':
    sys.exit(main())
