# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What `tactex predict` costs against `tactex convert`, and how on time `tactex bag play` is.

1. A 1-hour 120 Hz recording (IMU, magnetometer, pressure: 1.3 million messages) is
   written once. In fresh processes, `tactex convert --all-samples` (the reference: it
   reads and windows the same samples) and `tactex predict --contact always` with a
   MiniRocket and with a cnn_3 checkpoint (128-sample windows, hop 64) run on it.
   Target: predict at most 1.5 times convert, for both models.
2. A 30 s recording at 350 Hz (three topics, 31,500 messages) is played by
   `tactex bag play` on an idle machine and again with two busy processes (one per
   core). Target on the idle machine: p99 publish lateness under 2 ms.
"""

import os
from pathlib import Path
import subprocess
import sys
import tempfile
import time

from bench_convert import write_hour
import numpy as np

TACTEX = Path(sys.executable).parent / 'tactex'
WINDOW, HOP, RATE_HZ = 128, 64, 120


def checkpoints(folder: Path) -> dict[str, Path]:
    """A MiniRocket and a cnn_3 trained briefly on noise windows of the recording's shape."""
    from tactex_classify.models.baselines import MiniRocketRidge
    from tactex_classify.training.deep_classifier import DeepClassifier, TrainingConfig
    rng = np.random.default_rng(0)
    X = rng.normal(size=(64, WINDOW, 10)).astype(np.float32)
    y = np.arange(64) % 2
    X[y == 1, :, 0] += 1.0
    MiniRocketRidge().fit(X, y, ['a', 'b']).save(folder / 'minirocket', hop=HOP,
                                                 sampling_rate_hz=RATE_HZ)
    DeepClassifier(TrainingConfig(model='cnn_3', epochs=1)).fit(X, y, ['a', 'b']).save(
        folder / 'cnn_3', hop=HOP, sampling_rate_hz=RATE_HZ)
    return {'minirocket': folder / 'minirocket', 'cnn_3': folder / 'cnn_3'}


def seconds(*argv: str) -> tuple[float, str]:
    """Wall seconds of one tactex command (start-up included), and its output."""
    start = time.perf_counter()
    done = subprocess.run([str(TACTEX), *argv], capture_output=True, text=True,
                          env={**os.environ, 'OMP_NUM_THREADS': '1'})
    if done.returncode:
        raise SystemExit(f'tactex {" ".join(argv)} failed: {done.stderr}')
    return time.perf_counter() - start, done.stdout


def play_line(recording: Path, busy: int) -> str:
    """`tactex bag play`'s lateness line, with `busy` spinning processes beside it."""
    spinners = [subprocess.Popen([sys.executable, '-c', 'while True: pass'])
                for _ in range(busy)]
    try:
        return seconds('bag', 'play', str(recording), '--delay', '0.5')[1].strip()
    finally:
        for spinner in spinners:
            spinner.kill()


def main() -> None:
    """Write, time convert and predict, play idle and loaded, print the tables."""
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        hour = folder / 'hour'
        messages = write_hour(hour, rate_hz=RATE_HZ)
        print(f'wrote a 1-hour {RATE_HZ} Hz recording: {messages} messages')
        models = checkpoints(folder)
        convert_s, _ = seconds('convert', str(hour), '--out', str(folder / 'hour.npz'),
                               '--all-samples', '--label', 'x', '--window', str(WINDOW),
                               '--hop', str(HOP))
        print(f'{"command":<44}{"seconds":>9}{"ratio":>8}')
        print(f'{"tactex convert --all-samples (reference)":<44}{convert_s:>9.1f}{1.0:>8.2f}')
        for name, checkpoint in models.items():
            predict_s, output = seconds('predict', str(checkpoint), str(hour),
                                        '--contact', 'always')
            print(f'{"tactex predict, " + name:<44}{predict_s:>9.1f}'
                  f'{predict_s / convert_s:>8.2f}')
        print('target: predict <= 1.5x convert')
        short = folder / 'short'
        write_hour(short, rate_hz=350, seconds=30)
        print(f'bag play, 350 Hz x 3 topics for 30 s, idle: {play_line(short, 0)}')
        print(f'bag play, 350 Hz x 3 topics for 30 s, two busy cores: {play_line(short, 2)}')
        print('target (idle): p99 lateness < 2 ms')


if __name__ == '__main__':
    main()
