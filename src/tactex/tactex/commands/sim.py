# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex sim collect` (synthetic labelled recordings) and `tactex sim stats` (their channels)."""

from __future__ import annotations

import argparse
from dataclasses import replace

from tactex.errors import CommandError
from tactex.options import (
    check_input_folder,
    check_output_folder,
    input_path,
    integer,
    movement_file,
    output_path,
    ray_address,
    seed_value,
    staged_folder,
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    sub = parser.add_subparsers(dest='action', required=True, metavar='ACTION')
    collect = sub.add_parser('collect', help='record scripted sweeps of every texture as bags')
    collect.add_argument('--scene', default='uneven_texture',
                         help='scene name under config/scenes/ or a .toml path '
                              '(default uneven_texture)')
    collect.add_argument('--sweeps', type=integer(1, 1000), default=25,
                         help='sweeps per texture (25)')
    collect.add_argument('--out', type=output_path, required=True,
                         help='folder for the bags (new)')
    collect.add_argument('--seed', type=seed_value,
                         help="replace the scene's seed (e.g. a seed no test uses, for a "
                              'held-out evaluation)')
    collect.add_argument('--movements', type=input_path, metavar='YAML',
                         help='sweep every texture under every movement of this file (e.g. '
                              'config/movements.yaml), --sweeps per texture and movement; '
                              'each recording names its movement')
    from tactex_sim.textures import TEXTURES  # numpy only: the names for the help
    collect.add_argument('--textures', nargs='+', metavar='NAME',
                         help='only these textures (default: all): ' + ', '.join(
                             f"'{name}'" if ' ' in name else name for name in TEXTURES))
    collect.add_argument('--workers', type=integer(1, 1024), default=None,
                         help='sweeps recorded at once, as Ray tasks (default 1: one after '
                              'another here); the bags are the same for any number')
    collect.add_argument('--address', type=ray_address, metavar='HOST:PORT',
                         help='run the sweeps on this Ray cluster (every node needs tactex '
                              'installed); --workers then caps the sweeps in flight')
    stats = sub.add_parser('stats', help='per texture and channel: RMS, p99, max, share at '
                                         'the rails, dominant frequency; spectra as PNG '
                                         '(simulated or real recordings)')
    stats.add_argument('paths', nargs='+', type=input_path, metavar='BAG_OR_DIR',
                       help='recordings, or folders holding recordings')
    stats.add_argument('--out', type=output_path, required=True,
                       help='folder for stats.md, stats.json and the spectra (new)')


def run(args: argparse.Namespace) -> int:
    """Run the action."""
    return _stats(args) if args.action == 'stats' else _collect(args)


def _stats(args: argparse.Namespace) -> int:
    """Write the channel statistics of the recordings; warn on any beyond full scale."""
    import json
    import sys

    from tactex_classify.data import signal_stats

    check_output_folder(args.out)
    for path in args.paths:
        check_input_folder(path, 'BAG_OR_DIR')
    textures = signal_stats.collect(args.paths, progress=print)
    if not textures:
        raise CommandError(f'no recordings in {", ".join(map(str, args.paths))}')
    limits = signal_stats.Limits.configured()
    table = signal_stats.statistics(textures, limits)
    with staged_folder(args.out) as folder:
        (folder / 'stats.json').write_text(json.dumps(table, indent=1, sort_keys=True) + '\n',
                                           encoding='utf-8')
        (folder / 'stats.md').write_text(signal_stats.markdown(table, limits), encoding='utf-8')
        plots = signal_stats.plot_spectra(textures, folder)
    for line in signal_stats.warnings(table):
        print(f'warning: {line}', file=sys.stderr)
    print(f'wrote {args.out}/stats.md, stats.json and {len(plots)} spectra for '
          f'{len(table)} texture(s)')
    return 0


def _collect(args: argparse.Namespace) -> int:
    """Record the sweeps."""
    from tactex_sim.collect import collect, collectable_scenes
    from tactex_sim.errors import SceneError
    from tactex_sim.scene import load_scene, resolve_scene
    from tactex_sim.textures import TEXTURES

    check_output_folder(args.out)
    textures = args.textures or list(TEXTURES)
    unknown = [t for t in textures if t not in TEXTURES]
    if unknown:
        raise CommandError(f'--textures: unknown texture(s) {unknown}; known: '
                           f'{", ".join(TEXTURES)}')
    if len(set(textures)) != len(textures):
        raise CommandError('--textures names a texture twice')
    scene = load_scene(resolve_scene(args.scene))
    if args.seed is not None:
        scene = replace(scene, seed=args.seed)
    movements = movement_file(args.movements, scene.sensor_rate_hz) if args.movements else None
    try:
        collectable_scenes(scene, movements)
    except SceneError as err:
        if movements is None:
            raise
        raise CommandError(f'--movements {args.movements}: {err}') from None
    with staged_folder(args.out) as folder:
        paths = collect(scene, args.sweeps, folder, textures=textures,
                        workers=args.workers, address=args.address, movements=movements)
    print(f'wrote {len(paths)} recordings to {args.out}')
    return 0
