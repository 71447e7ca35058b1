# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Result sections of recordings: conversion, formats from elsewhere, predict and play."""

from results_common import kept_text, line_starting, numbers_in


def convert() -> str:
    text = kept_text('bench_convert.txt')
    wrote = numbers_in(line_starting(text, 'wrote'))
    reference = numbers_in(line_starting(text, 'rosbags read'))
    ours = numbers_in(line_starting(text, 'tactex read_recording'))
    return (f'- `python bench/bench_convert.py`: on a 1-hour 350 Hz recording '
            f'({wrote[0] / 1e6:.2f} million messages, {wrote[1]:.0f} MB) conversion runs at '
            f"{ours[-2] / reference[-2]:.2f}x the speed of rosbags' own read + deserialise "
            f'(target 0.5x) with a peak of {ours[-1]:.0f} MB resident.\n')


def recordings() -> str:
    """ROS 1 conversion speed and `tactex bag info` on a 1-hour 350 Hz recording."""
    text = kept_text('bench_recordings.txt')
    ratio = numbers_in(line_starting(text, 'ROS 1 throughput ratio'))[1]
    reference = numbers_in(line_starting(text, 'rosbags read + deserialise ROS 1'))
    info = {(fmt, timing): numbers_in(line_starting(text, f'bag info {fmt}, {timing}'))[-2]
            for fmt in ('rosbag2 MCAP', 'ROS 1 bag')
            for timing in ('summary from the index', 'with rates, jitter, gaps')}
    return (f'- `python bench/bench_recordings.py` (a 1-hour 350 Hz recording, 3.78 million '
            f'messages, rewritten as a ROS 1 bag by rosbags): `read_recording` converts the '
            f"ROS 1 bag at {ratio:.2f}x the speed of rosbags' own read + deserialise "
            f'({reference[1]:,.0f} messages/s; target 0.7x).\n\n'
            f'- `tactex bag info` on it, start-up included: the summary from the index in '
            f'{info["rosbag2 MCAP", "summary from the index"]:.1f} s for the rosbag2 MCAP '
            f'folder and {info["ROS 1 bag", "summary from the index"]:.1f} s for the ROS 1 '
            f'bag (its chunk records; target 2 s); with rates, jitter and gaps '
            f'{info["rosbag2 MCAP", "with rates, jitter, gaps"]:.1f} s and '
            f'{info["ROS 1 bag", "with rates, jitter, gaps"]:.1f} s (the log times from the '
            f'MCAP message indexes and the ROS 1 index; target 15 s).\n')


def predict_play() -> str:
    """`tactex predict` against `tactex convert`, and `tactex bag play`'s lateness."""
    text = kept_text('bench_predict_play.txt')
    convert_s = numbers_in(line_starting(text, 'tactex convert'))[0]
    rows = {name: numbers_in(line_starting(text, f'tactex predict, {name}'))
            for name in ('minirocket', 'cnn_3')}
    idle, busy = (numbers_in(line_starting(text, f'bag play, 350 Hz x 3 topics for 30 s, {load}'))
                  for load in ('idle', 'two busy cores'))
    return (f'- `python bench/bench_predict_play.py` (a 1-hour 120 Hz recording, 1.3 million '
            f'messages): `tactex convert --all-samples` takes {convert_s:.0f} s; `tactex '
            f'predict` through the live core takes {rows["minirocket"][0]:.0f} s with '
            f'MiniRocket ({rows["minirocket"][1]:.2f}x) and {rows["cnn_3"][0]:.0f} s with '
            f'cnn_3 ({rows["cnn_3"][1]:.2f}x); target 1.5x.\n\n'
            f'- `tactex bag play` of 350 Hz x 3 topics for 30 s: publish lateness p99 '
            f'{idle[-4]:.2f} ms, max {idle[-3]:.1f} ms on an idle machine (target 2 ms); '
            f'p99 {busy[-4]:.2f} ms, max {busy[-3]:.1f} ms with both cores busy.\n')
