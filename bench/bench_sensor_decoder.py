# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Frame decoder throughput against the bare unpack of the same aligned frames, in one run.

The reference is the least any pure-Python decoder must do (one struct unpack per
frame, no search, no CRC); the ratio shows what resynchronisation and checking cost.
The stream is fed in 4 KiB reads, with 1 % of frames preceded by garbage.
"""

import struct
import time

import numpy as np

from tactex_sensor.protocol import encode, FRAME_SIZE, FrameDecoder, Sample

FRAMES = 100_000


def main() -> None:
    """Print frames/s of the decoder and of the reference, and their ratio."""
    rng = np.random.default_rng(0)
    frames = [encode(Sample(i % 65536, i * 2857, (0.1, 0.2, 9.8), (0.01, 0.02, 0.03),
                            (2e-5, 0.0, -4e-5), 101325.0, 24.0)) for i in range(FRAMES)]
    clean = b''.join(frames)
    noisy = b''.join((rng.integers(0, 256, 20, np.uint8).tobytes() if i % 100 == 0 else b'')
                     + f for i, f in enumerate(frames))
    unpack = struct.Struct('<2sBBHI3f3f3fff').unpack_from
    start = time.perf_counter()
    for offset in range(0, len(clean), FRAME_SIZE):
        unpack(clean, offset)
    reference = FRAMES / (time.perf_counter() - start)
    rows = []
    for label, stream in (('clean', clean), ('1 % garbage', noisy)):
        decoder = FrameDecoder()
        start = time.perf_counter()
        decoded = sum(len(decoder.feed(stream[i:i + 4096])) for i in range(0, len(stream), 4096))
        rate = FRAMES / (time.perf_counter() - start)
        assert decoded == FRAMES, (label, decoded)
        rows.append((label, rate))
    print(f'{"stream":<14}{"frames/s":>12}{"vs bare unpack":>16}')
    print(f'{"bare unpack":<14}{reference:>12.0f}{1.0:>16.2f}')
    for label, rate in rows:
        print(f'{label:<14}{rate:>12.0f}{rate / reference:>16.2f}')
    print('target: >= 50000 frames/s; a 250000-baud link carries at most ~450 frames/s')


if __name__ == '__main__':
    main()
