# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex sim collect`: synthetic labelled recordings from the MuJoCo scenes."""

from __future__ import annotations

import argparse
from pathlib import Path

from tactex.errors import CommandError
from tactex.options import check_output_folder, integer, staged_folder


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    sub = parser.add_subparsers(dest='action', required=True, metavar='ACTION')
    collect = sub.add_parser('collect', help='record scripted sweeps of every texture as bags')
    collect.add_argument('--scene', default='uneven_texture',
                         help='scene name under config/scenes/ or a .toml path '
                              '(default uneven_texture)')
    collect.add_argument('--sweeps', type=integer(1, 1000), default=25,
                         help='sweeps per texture (25)')
    collect.add_argument('--out', type=Path, required=True, help='folder for the bags (new)')
    collect.add_argument('--textures', nargs='+', metavar='NAME',
                         help='only these textures (default: all 12)')


def run(args: argparse.Namespace) -> int:
    """Run the action."""
    from tactex_sim.collect import check_collectable, collect
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
    check_collectable(scene)
    with staged_folder(args.out) as folder:
        paths = collect(scene, args.sweeps, folder, textures=textures)
    print(f'wrote {len(paths)} recordings to {args.out}')
    return 0
