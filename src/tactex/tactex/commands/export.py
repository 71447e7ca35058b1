# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex export`: write a checkpoint's model in a portable form (ONNX)."""

from __future__ import annotations

import argparse

from tactex.errors import CommandError
from tactex.options import (
    check_input_folder,
    check_output_file,
    input_path,
    output_path,
    refuse_to_replace,
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('checkpoint', type=input_path, metavar='CHECKPOINT',
                        help='checkpoint folder (RUN/model/ of `tactex train`)')
    parser.add_argument('--onnx', action='store_true',
                        help='write the model as ONNX, checked against the native model, for '
                             'classifier_node runtime:=onnxruntime (deep models, ExtraTrees)')
    parser.add_argument('--out', type=output_path,
                        help='ONNX file to write (default CHECKPOINT/model.onnx, where the '
                             'node looks for it)')
    parser.add_argument('--force', action='store_true',
                        help='replace an existing --out file (the default one is replaced)')


def run(args: argparse.Namespace) -> int:
    """Export the model; print where it went."""
    if not args.onnx:
        raise CommandError('nothing to export: give --onnx')
    check_input_folder(args.checkpoint, 'CHECKPOINT')
    from tactex_classify.models.checkpoint import ONNX_FILE
    out = check_output_file(args.out or args.checkpoint / ONNX_FILE, suffix='.onnx')
    if args.out is not None:
        refuse_to_replace(out, force=args.force)
    out.parent.mkdir(parents=True, exist_ok=True)

    from tactex_classify.online.runtime import export_onnx
    path = export_onnx(args.checkpoint, out)
    print(f'wrote {path} ({path.stat().st_size / 1e6:.2f} MB); run it with '
          f'classifier_node --ros-args -p checkpoint:={args.checkpoint} -p '
          f'runtime:=onnxruntime' + ('' if args.out is None else
                                     f' (it looks for {args.checkpoint / ONNX_FILE})'))
    return 0
