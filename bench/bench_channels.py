# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Which channels carry texture information in simulation: grouped accuracy per channel group.

Simulates the uneven-texture scene (`tactex sim collect`, 12 textures x `--sweeps`),
converts it once per channel group (accelerometer, gyro, magnetometer, barometer, all;
`tactex convert --channels`), and cross-validates each baseline on each, grouped by
recording (`tactex train --cv grouped`). Writes bench/results/channels/ablation.{md,json}
and ablation.png; the README's channel table is generated from the JSON. A group that
scores near chance carries no texture information the physics put there.
"""

import argparse
import json
from pathlib import Path
import subprocess
import sys
import tempfile
import time

RESULTS = Path(__file__).parent / 'results' / 'channels'
TACTEX = str(Path(sys.executable).parent / 'tactex')
GROUPS = {'accelerometer': 'ax,ay,az', 'gyro': 'gx,gy,gz', 'magnetometer': 'mx,my,mz',
          'barometer': 'baro', 'all': 'ax,ay,az,gx,gy,gz,mx,my,mz,baro'}
MODELS = ('extratrees', 'minirocket')


def run(command: list[str]) -> None:
    """Run a tactex command quietly; fail loudly with its output."""
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode:
        sys.exit(f'{" ".join(command)} failed:\n{result.stdout[-2000:]}{result.stderr[-2000:]}')


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--sweeps', type=int, default=5, help='sweeps per texture (5)')
    parser.add_argument('--folds', type=int, default=5, help='grouped folds (5)')
    parser.add_argument('--out', type=Path, default=RESULTS)
    args = parser.parse_args()
    started = time.monotonic()
    rows = []
    with tempfile.TemporaryDirectory(prefix='tactex-channels-') as scratch:
        bags = Path(scratch) / 'bags'
        print(f'simulating 12 textures x {args.sweeps} sweeps', flush=True)
        run([TACTEX, 'sim', 'collect', '--sweeps', str(args.sweeps), '--out', str(bags)])
        for group, channels in GROUPS.items():
            data = Path(scratch) / f'{group}.npz'
            run([TACTEX, 'convert', str(bags), '--out', str(data), '--channels', channels])
            for model in MODELS:
                out = Path(scratch) / f'{group}-{model}'
                run([TACTEX, 'train', str(data), '--model', model, '--cv', 'grouped',
                     '--folds', str(args.folds), '--no-final', '--out', str(out)])
                metrics = json.loads((out / 'metrics.json').read_text(encoding='utf-8'))
                accuracy = float(metrics['schemes']['grouped']['accuracy'])
                rows.append({'group': group, 'channels': channels, 'model': model,
                             'grouped_accuracy': accuracy})
                print(f'{group:13s} {model:10s} {100 * accuracy:5.1f} % grouped', flush=True)
    summary = {'sweeps_per_texture': args.sweeps, 'folds': args.folds, 'chance': 1 / 12,
               'command': 'python bench/bench_channels.py ' + ' '.join(sys.argv[1:]),
               'seconds': round(time.monotonic() - started, 1), 'rows': rows}
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / 'ablation.json').write_text(json.dumps(summary, indent=1) + '\n',
                                            encoding='utf-8')
    (args.out / 'ablation.md').write_text(markdown(summary), encoding='utf-8')
    plot(summary, args.out / 'ablation.png')
    print(f'wrote {args.out}/ablation.md, ablation.json, ablation.png')
    return 0


def markdown(summary: dict) -> str:
    """The table: a row per channel group, a column per model."""
    lines = [f'Grouped {summary["folds"]}-fold accuracy by channel group, 12 textures x '
             f'{summary["sweeps_per_texture"]} simulated sweeps (chance '
             f'{100 * summary["chance"]:.1f} %); `{summary["command"].strip()}`.', '',
             '| channels | ' + ' | '.join(MODELS) + ' |', '|---|' + '---|' * len(MODELS)]
    for group in GROUPS:
        cells = [next(f'{100 * r["grouped_accuracy"]:.1f} %' for r in summary['rows']
                      if r['group'] == group and r['model'] == model) for model in MODELS]
        lines.append(f'| {group} | ' + ' | '.join(cells) + ' |')
    return '\n'.join(lines) + '\n'


def plot(summary: dict, path: Path) -> None:
    """Bars per channel group and model, chance as a line."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    import numpy as np

    figure, axes = plt.subplots(figsize=(7, 4))
    positions = np.arange(len(GROUPS))
    width = 0.8 / len(MODELS)
    for index, model in enumerate(MODELS):
        values = [100 * next(r['grouped_accuracy'] for r in summary['rows']
                             if r['group'] == group and r['model'] == model) for group in GROUPS]
        axes.bar(positions + index * width, values, width, label=model)
    axes.axhline(100 * summary['chance'], color='grey', linestyle='--', label='chance')
    axes.set_xticks(positions + width * (len(MODELS) - 1) / 2, list(GROUPS))
    axes.set_ylabel('accuracy grouped by recording (%)')
    axes.set_title('Texture information per channel group (simulation)')
    axes.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    plt.close(figure)


if __name__ == '__main__':
    sys.exit(main())
