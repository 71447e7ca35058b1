# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex demo`: the whole pipeline in simulation, through the launched nodes.

`launch/system.launch.py sim:=true` is started by the launcher (supervised processes);
the demo then talks to the nodes only through their interfaces: it probes the uneven
surface (the `probe` action; the pathway is broadcast on probe/pathway and
probe/contacts), sweeps each of the 12 textures along it while sweep_node records
(the `sweep` action with `record: true`; the texture is the bridge's `patch_texture`
parameter), converts the recordings (`tactex convert`), trains with grouped and
stratified cross-validation (`tactex train`), starts the system again with the
checkpoint and classifies fresh sweeps live through classifier_node (texture/estimate).
Identification has sweeps of its own (each texture under the movements of
config/movements.yaml that the pathway holds, recorded apart and trained into a bundle
with `tactex train --movements`); after the fixed sweeps, identify_node identifies the
textures, one Identify goal each, choosing its movements. It writes summary.json, the
plots and every node's log under --out, prints each figure against its threshold
(docs/guides/quick-start.md, "The demo") and exits 1 naming a figure that misses it.
"""

from __future__ import annotations

import argparse
from dataclasses import replace
import os
from pathlib import Path
import shutil
import sys
import time

from tactex.demo.pipeline import DEFAULT, Demo, demo_environment, MARKER, QUICK
from tactex.errors import CommandError
from tactex.options import check_output_folder, integer, number, output_path, staged_folder


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('--out', type=output_path, default=Path('out/demo'),
                        help='folder for summary.json, plots, recordings, model and logs '
                             '(default out/demo; a previous demo there is replaced)')
    parser.add_argument('--quick', action='store_true',
                        help=f'{len(QUICK.textures)} textures, {QUICK.sweeps} sweeps each, a '
                             f'shorter pathway, {QUICK.identify_textures} identified (a few '
                             'minutes)')
    parser.add_argument('--sweeps', type=integer(2, 50), default=None,
                        help=f'recorded sweeps per texture (2..50; default {DEFAULT.sweeps}, '
                             f'--quick {QUICK.sweeps})')
    parser.add_argument('--live-sweeps', type=integer(1, 20), default=None,
                        help='fresh sweeps per texture classified live (1..20, default 1)')
    parser.add_argument('--rate-factor', type=number(at_most=10.0), default=None,
                        help='simulated seconds per wall second (default '
                             f'{DEFAULT.rate_factor:g}, --quick {QUICK.rate_factor:g}; a loaded '
                             'machine keeps up with less)')



def run(args: argparse.Namespace) -> int:
    """Run every stage; print the figures against their thresholds; 1 if one misses."""
    sizes = QUICK if args.quick else DEFAULT
    sweeps = args.sweeps or sizes.sweeps
    sizes = replace(sizes, sweeps=sweeps, live_sweeps=args.live_sweeps or sizes.live_sweeps,
                    folds=min(DEFAULT.folds, sweeps),
                    rate_factor=args.rate_factor or sizes.rate_factor)
    out = _check_out(args.out)
    started = time.monotonic()
    with staged_folder(out) as folder, demo_environment(folder):
        (folder / MARKER).write_text('written by tactex demo\n', encoding='utf-8')
        demo = Demo(folder, out, sizes, started)
        summary, checks = demo.run()
        if out.is_dir():
            shutil.rmtree(out)  # a previous demo (checked by _check_out)
    _print_summary(out, summary, checks)
    missed = [check for check in checks if not check.passed]
    if missed:
        print(f'error: {len(missed)} figure(s) missed the threshold: '
              f'{"; ".join(check.line() for check in missed)}', file=sys.stderr)
    return 1 if missed else 0



def _check_out(out: Path) -> Path:
    """--out is new, empty, or a previous demo's folder (which the run replaces)."""
    if out.is_dir() and (out / MARKER).is_file():
        if not os.access(out.parent, os.W_OK | os.X_OK):
            raise CommandError(f'--out {out}: {out.parent} is not writable')
        return out
    return check_output_folder(out)


def _print_summary(out: Path, summary: dict, checks: list) -> None:
    print(f'\ntactex demo, summary ({out}/summary.json; plots pathway.png, sweep.png, '
          'confusion.png, accuracy_vs_contact_time.png, identification.png):')
    print(f'  cv_accuracy_stratified {summary["cv_accuracy_stratified"]:.4g} (leaky, '
          'reported only)')
    for check in checks:
        print(f'  {check.line()}')
    print(f'  madgwick_bad_stamps {summary["madgwick_bad_stamps"]:.4g} (IMU stamps that did '
          'not advance or left a gap, reported only)')
    identification = summary.get('identification', {})
    if identification.get('episodes'):
        print(f'  identification (identify_node, active): {identification["accuracy"]:.3g} of '
              f'{identification["episodes"]} textures right, median '
              f'{identification["median_movements"]:g} movements, '
              f'{identification["median_contact_s"]:.1f} s of contact, '
              f'{identification["median_wall_s"]:.0f} s wall each (reported only; '
              'identification.png)')
        print(f'  beside the fixed sweep (classifier_node): {summary["live_accuracy"]:.3g} right, '
              f'decided after a median {summary["time_to_decision_s"]:.1f} s of contact in one '
              'sweep')
    print(f'  wall_s {summary["wall_s"]:.0f} s')
