# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Cost of the eight models at windows of 128, 256 and 512 samples, on one CPU thread.

For each model and window, in a fresh process: the time of ten training batches of 32
(Adamax, clipping), projected to an epoch and to a 250-epoch fold of the original's
uneven-surface dataset (3962 / 1864 / 900 windows, 80 % for training); the latency of
classifying one window (batch 1, p50 and p99 of 200 calls); the process's peak memory.
Ratios are against cnn_1 at 128 samples measured in the same run. Writes
bench/results/classify.md and bench/results/classify.png.
"""

from pathlib import Path
import subprocess
import sys
import textwrap

import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402

from tactex_classify.models.architectures import MODELS  # noqa: E402

RESULTS = Path(__file__).parent / 'results'
WINDOWS = {128: 3962, 256: 1864, 512: 900}
PROBE = textwrap.dedent("""
    import os, resource, sys, time
    os.environ['OMP_WAIT_POLICY'] = 'PASSIVE'
    import numpy as np, torch
    from tactex_classify.models.architectures import build_model
    torch.set_num_threads(1)
    name, window = sys.argv[1], int(sys.argv[2])
    model = build_model(name, window, 10, 12)
    optimizer = torch.optim.Adamax(model.parameters(), lr=1e-3)
    x = torch.randn(32, window, 10)
    y = torch.randint(0, 12, (32,))
    model.train()
    start = time.perf_counter()
    for _ in range(10):
        optimizer.zero_grad()
        loss = torch.nn.functional.cross_entropy(model(x), y)
        loss.backward()
        torch.nn.utils.clip_grad_norm_(model.parameters(), 1.0)
        optimizer.step()
    batch_s = (time.perf_counter() - start) / 10
    model.eval()
    one = torch.randn(1, window, 10)
    times = []
    with torch.no_grad():
        for _ in range(20):
            model(one)
        for _ in range(200):
            start = time.perf_counter()
            model(one)
            times.append(time.perf_counter() - start)
    print(batch_s, np.percentile(times, 50), np.percentile(times, 99),
          resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
""")


def main() -> None:
    """Measure every model at every window, print and save the table and the plot."""
    rows = []
    for name in MODELS:
        for window, windows in WINDOWS.items():
            out = subprocess.run([sys.executable, '-c', PROBE, name, str(window)],
                                 capture_output=True, text=True, check=True).stdout.split()
            batch_s, p50, p99, rss_kb = float(out[0]), float(out[1]), float(out[2]), int(out[3])
            batches = -(-int(0.8 * windows) // 32)
            rows.append((name, window, batch_s * batches, batch_s * batches * 250 / 60,
                         p50 * 1e3, p99 * 1e3, rss_kb / 1024))
            print(f'{name:<13}{window:>5}: epoch {rows[-1][2]:6.1f} s, fold {rows[-1][3]:6.0f} '
                  f'min, latency p50 {rows[-1][4]:6.2f} ms p99 {rows[-1][5]:6.2f} ms, '
                  f'peak {rows[-1][6]:5.0f} MB', flush=True)
    reference = next(r for r in rows if r[0] == 'cnn_1' and r[1] == 128)
    lines = ['| model | window | epoch s | fold of 250 epochs (min, projected) | latency p50 ms '
             '| latency p99 ms | peak MB | epoch vs cnn_1@128 | latency vs cnn_1@128 |',
             '|---|---|---|---|---|---|---|---|---|']
    for row in rows:
        lines.append(f'| {row[0]} | {row[1]} | {row[2]:.1f} | {row[3]:.0f} | {row[4]:.2f} | '
                     f'{row[5]:.2f} | {row[6]:.0f} | {row[2] / reference[2]:.1f}x | '
                     f'{row[4] / reference[4]:.1f}x |')
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / 'classify.md').write_text(
        '# Model cost, one CPU thread (bench/bench_classify.py)\n\n' + '\n'.join(lines) + '\n',
        encoding='utf-8')
    print('\n'.join(lines))
    figure, axes = plt.subplots(1, 2, figsize=(12, 4))
    names = list(MODELS)
    for offset, window in enumerate(WINDOWS):
        picked = [r for r in rows if r[1] == window]
        positions = [i + 0.27 * (offset - 1) for i in range(len(names))]
        axes[0].bar(positions, [r[2] for r in picked], 0.27, label=f'{window} samples')
        axes[1].bar(positions, [r[4] for r in picked], 0.27, label=f'{window} samples')
    for axis, label in zip(axes, ('training epoch (s)', 'latency per window, p50 (ms)'),
                           strict=True):
        axis.set_xticks(range(len(names)), names, rotation=30, ha='right')
        axis.set_ylabel(label)
        axis.set_yscale('log')
        axis.legend()
    figure.tight_layout()
    figure.savefig(RESULTS / 'classify.png', dpi=100)


if __name__ == '__main__':
    main()
