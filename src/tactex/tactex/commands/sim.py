# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex sim collect`: synthetic labelled recordings from the MuJoCo scenes."""

from __future__ import annotations

import argparse
from pathlib import Path
import sys


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    sub = parser.add_subparsers(dest='action', required=True, metavar='ACTION')
    collect = sub.add_parser('collect', help='record scripted sweeps of every texture as bags')
    collect.add_argument('--scene', default='uneven_texture',
                         help='scene name under config/scenes/ or a .toml path '
                              '(default uneven_texture)')
    collect.add_argument('--sweeps', type=int, default=25, help='sweeps per texture (25)')
    collect.add_argument('--out', type=Path, required=True, help='folder for the bags')
    collect.add_argument('--textures', nargs='+', metavar='NAME',
                         help='only these textures (default: all 12)')


def run(args: argparse.Namespace) -> int:
    """Run the action."""
    from tactex_sim.collect import collect
    from tactex_sim.errors import SimError
    from tactex_sim.scene import load_scene, resolve_scene
    from tactex_sim.textures import TEXTURES

    try:
        scene = load_scene(resolve_scene(args.scene))
        textures = args.textures or list(TEXTURES)
        unknown = [t for t in textures if t not in TEXTURES]
        if unknown or args.sweeps < 1:
            raise SimError(f'unknown texture(s) {unknown}; known: {", ".join(TEXTURES)}'
                           if unknown else '--sweeps must be >= 1')
        if 'texture' not in scene.effects or not scene.patches:
            raise SimError(f'scene {scene.name!r} has no texture effect or no patch to sweep')
        paths = collect(scene, args.sweeps, args.out, textures=textures)
    except SimError as err:
        print(f'error: {err}', file=sys.stderr)
        return 1
    print(f'wrote {len(paths)} recordings to {args.out}')
    return 0
