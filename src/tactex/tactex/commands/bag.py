# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex bag info|play`: what recordings hold, and recordings played into the nodes."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
import sys

from tactex.errors import CommandError
from tactex.options import input_path, namespace, number, topic_name


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    sub = parser.add_subparsers(dest='bag', required=True, metavar='ACTION')
    info = sub.add_parser(
        'info', help='storage, span, and per topic: type, count, rate, jitter and gaps',
        description='What recordings hold: rosbag2 folders (sqlite3, MCAP, zstd), ROS 1 '
        'bags, lone .mcap or .db3 files, folders of part bags.')
    info.add_argument('paths', nargs='+', type=input_path, metavar='RECORDING',
                      help='recordings (a folder of recordings: each one in it)')
    info.add_argument('--json', action='store_true',
                      help='one JSON document (a list, one object per recording)')
    info.add_argument('--no-timing', action='store_true',
                      help='the summary from the index only (no rates, jitter or gaps; '
                           'instant on long recordings)')
    play = sub.add_parser(
        'play', help='publish recordings at their recorded timing (like ros2 bag play)',
        description='Publish recordings (any format bag info reads; ROS 1 messages as their '
        'ROS 2 types) at their recorded timing, one after another, so classifier_node, '
        'tactex watch and the live view run on them. Ctrl-C stops it.')
    play.add_argument('paths', nargs='+', type=input_path, metavar='RECORDING')
    play.add_argument('--rate-factor', type=number(), default=1.0, metavar='F',
                      help="playback speed (ros2 bag play's --rate; here --rate means Hz): 2 "
                           'plays twice as fast (1)')
    play.add_argument('--start-offset', type=number(at_least=0.0), default=0.0, metavar='S',
                      help='skip the first S seconds of each recording (0)')
    play.add_argument('--duration', type=number(), metavar='S',
                      help='play S seconds of each recording (default: all)')
    play.add_argument('--loop', action='store_true', help='play again until Ctrl-C')
    play.add_argument('--clock', action='store_true',
                      help='publish /clock with the recorded time (for nodes with '
                           'use_sim_time:=true, as classifier_node needs for sweep/active)')
    play.add_argument('--topics', nargs='+', default=[], metavar='TOPIC',
                      help='only these recorded topics (default: all)')
    play.add_argument('--remap', action='append', default=[], metavar='OLD:=NEW',
                      help='publish a recorded topic under another name; repeatable')
    play.add_argument('--namespace', type=namespace, default='', metavar='NS',
                      help='publish every topic under this namespace (e.g. left_arm)')
    play.add_argument('--delay', type=number(at_least=0.0), default=1.0, metavar='S',
                      help='wait S seconds after creating the publishers, for discovery (1)')
    play.add_argument('--wait-for', nargs='+', type=topic_name, default=[], metavar='TOPIC',
                      help='before the first message, wait until each of these published '
                           'topics (/clock too with --clock) has a subscriber (then --delay '
                           'more)')
    play.add_argument('--wait-timeout', type=number(), metavar='S',
                      help='longest wait for the --wait-for subscribers (30)')


def run(args: argparse.Namespace) -> int:
    """Describe or play the recordings."""
    for path in args.paths:
        if not path.exists():
            raise CommandError(f'RECORDING {path} does not exist')
    return _play(args) if args.bag == 'play' else _info(args)


def _recordings(paths: list[Path]) -> list[Path]:
    from tactex_classify.data.dataset import recording_paths
    recordings = recording_paths(paths, progress=lambda line: print(line, file=sys.stderr))
    if not recordings:
        raise CommandError(f'no recordings in {", ".join(map(str, paths))}; give rosbag2 '
                           'folders, .bag, .mcap or .db3 files')
    return recordings


def _play(args: argparse.Namespace) -> int:
    """Publish the recordings; report how many and how late."""
    from tqdm import tqdm

    from tactex.bag_playback import parse_remap, PlayOptions
    from tactex_classify.data.sources import is_recording
    for path in args.paths:
        if not (path.is_dir() or is_recording(path)):
            raise CommandError(f'RECORDING {path} is no recording; give a rosbag2 folder, a '
                               'ROS 1 .bag, an .mcap or .db3 file')
    try:
        remaps = tuple(parse_remap(text) for text in args.remap)
    except ValueError as err:
        raise CommandError(str(err)) from None
    if args.wait_timeout is not None and not args.wait_for:
        raise CommandError('--wait-timeout bounds the wait of --wait-for: add --wait-for '
                           'TOPIC ... or drop --wait-timeout')
    if not args.clock and '/clock' in {'/' + name.strip('/') for name in args.wait_for}:
        raise CommandError('--wait-for /clock: /clock is published only with --clock; add '
                           '--clock')
    options = PlayOptions(args.rate_factor, args.start_offset, args.duration,
                          tuple(args.topics), remaps, args.namespace)
    recordings = _recordings(args.paths)
    from tactex.bag_player import NoSubscriberError, play, WAIT_TIMEOUT_S
    bar = tqdm(desc='playing', unit=' s', bar_format='{desc}: {n:.1f} s of recording',
               disable=None, file=sys.stderr)
    try:
        summary = play(recordings, options, loop=args.loop, clock=args.clock,
                       delay_s=args.delay, wait_for=args.wait_for,
                       wait_timeout_s=args.wait_timeout or WAIT_TIMEOUT_S,
                       said=lambda line: print(line, file=sys.stderr),
                       progress=lambda played: bar.update(played - bar.n))
    except NoSubscriberError as err:
        raise CommandError(f'--wait-for: {err}') from None
    finally:
        bar.close()
    if summary['stopped']:
        print(f'stopped by {summary["stopped"]}', file=sys.stderr)
    if not summary.get('published') and not summary['stopped']:
        raise CommandError(_nothing_published(args))
    print(_lateness_line(summary))
    return 0


def _nothing_published(args: argparse.Namespace) -> str:
    """Why a play published nothing, naming the options that can cause it."""
    causes = ([f'--topics {" ".join(args.topics)} names no recorded topic'] if args.topics
              else []) + ([f'--start-offset {args.start_offset:g} s is past the end']
                          if args.start_offset else []) + (
        [f'--duration {args.duration:g} s holds no message'] if args.duration else [])
    return ('published nothing: ' + (' or '.join(causes) if causes else
                                     'no topic of the recordings could be played')
            + '; `tactex bag info RECORDING` lists the topics and the duration')


def _lateness_line(summary: dict) -> str:
    if not summary.get('published'):
        return 'published nothing'
    return (f'published {summary["published"]:,} messages ({summary["passes"]} recording '
            f'pass(es)); lateness p50 {summary["p50_ms"]:.2f} ms, p99 {summary["p99_ms"]:.2f} '
            f'ms, max {summary["max_ms"]:.1f} ms; {summary["late"]} later than 5 ms')


def _info(args: argparse.Namespace) -> int:
    """Describe each recording."""
    from tqdm import tqdm

    from tactex_classify.data.bag_info import describe, format_text
    from tactex_classify.errors import BagError

    recordings = _recordings(args.paths)
    described, failed = [], []
    for path in recordings:
        with tqdm(desc=path.name, unit=' msg', unit_scale=True, leave=False, disable=None,
                  file=sys.stderr) as bar:
            try:
                described.append(describe(path, timing=not args.no_timing,
                                          progress=bar.update))
            except BagError as err:
                failed.append(str(err))
                if args.json:  # in the listing too, where the recording would have been
                    described.append({'path': str(path), 'unreadable': str(err)})
    if args.json:
        print(json.dumps([info if isinstance(info, dict) else info.as_json()
                          for info in described], indent=1))
    elif described:
        print('\n\n'.join(format_text(info) for info in described))
    if len(failed) == 1 and len(recordings) == 1:
        raise CommandError(failed[0])
    for message in failed:
        print(f'warning: {message}', file=sys.stderr)
    if failed:
        raise CommandError(f'{len(failed)} of {len(recordings)} recordings cannot be read (the '
                           'warnings above say why)')
    return 0
