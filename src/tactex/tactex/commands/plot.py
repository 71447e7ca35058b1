# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex plot`: draw a recording, or draw a run's plots again from what it kept."""

from __future__ import annotations

import argparse
from pathlib import Path

from tactex.errors import CommandError
from tactex.options import check_output_file, input_path, output_path, refuse_to_replace

MAX_JSON_BYTES = 256 * 1024**2  # a comparison's summary.json holds every confusion matrix
MAX_JSON_DEPTH = 32


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('target', type=input_path, metavar='RECORDING|RUN',
                        help='a recording (bag folder), or the folder of a `tactex train` '
                             'run, a `tactex compare` grid or a `tactex report accuracy-time` '
                             'report, whose PNGs are drawn again from its kept numbers')
    parser.add_argument('--out', type=output_path,
                        help="PNG to write for a recording (required then); a run's plots "
                             'are written into the run')
    parser.add_argument('--force', action='store_true', help='replace an existing --out PNG')


def run(args: argparse.Namespace) -> int:
    """Draw; print what was written."""
    from tactex_classify.data.sources import is_recording
    target = args.target
    if not target.exists():
        raise CommandError(f'RECORDING|RUN {target} does not exist')
    if is_recording(target):
        written = [_plot_recording(target, args.out, args.force)]
    elif not target.is_dir():
        raise CommandError(f'RECORDING|RUN {target} is neither a recording nor a run: plot '
                           'draws a recording (rosbag2 folder, .bag, .mcap or .db3) or the '
                           'folder of a train run, compare grid or accuracy-time report')
    else:
        if args.out is not None:
            raise CommandError("--out is for a recording; a run's plots go into the run "
                               f'({target})')
        written = _replot_run(target)
    print('wrote ' + ', '.join(str(path) for path in written))
    return 0


def _plot_recording(recording: Path, out: Path | None, force: bool) -> Path:
    """One PNG of the recording's channels, its windows' samples shaded."""
    from tactex_classify.data.bags import read_recording
    from tactex_classify.data.dataset import FilterRule, keep_mask
    from tactex_classify.errors import BagError
    from tactex_classify.evaluation.recording_plot import plot_recording
    if out is None:
        raise CommandError('a recording needs --out FILE.png (nothing is written beside the '
                           'recording)')
    out = check_output_file(out, suffix='.png')
    refuse_to_replace(out, force=force)
    try:
        recording = read_recording(recording)
    except BagError as err:
        raise CommandError(str(err)) from None
    if not recording.stamps_ns.size:
        raise CommandError(f'{recording.path}: no IMU samples to plot')
    out.parent.mkdir(parents=True, exist_ok=True)
    against = plot_recording(out, recording, keep_mask(recording, FilterRule(), False,
                                                       recording.metadata.get('label')))
    print(f'{out.name}: channels against {against}')
    return out


def _replot_run(folder: Path) -> list[Path]:
    """The PNGs of a train run, a comparison grid or an accuracy-time report, drawn again."""
    kinds = {'metrics.json': 'a `tactex train` run', 'summary.json': 'a `tactex compare` grid',
             'results.json': 'a `tactex report accuracy-time` report'}
    found = [name for name in kinds if (folder / name).is_file()]
    if (folder / 'recordings.csv').is_file():
        raise CommandError(f'{folder} is a `tactex predict` report: predict draws its plot '
                           '(confusion.png, with labelled inputs) when it writes the report')
    if not folder.is_dir() or not found:
        raise CommandError(f'{folder} is neither a recording (a bag folder) nor a run: it holds '
                           f'none of {", ".join(kinds)} ({", ".join(kinds.values())})')
    name = found[0]
    kept = _load(folder / name)
    try:
        if name == 'metrics.json':
            return _replot_training(folder, kept)
        if name == 'summary.json':
            from tactex_classify.evaluation.grid_report import plot_grid
            return plot_grid(folder, kept['rows'])
        from tactex.accuracy_time.runner import write_files
        from tactex.accuracy_time.sections import SECTIONS
        write_files(folder, kept)
        return [folder / section.plot_file for section in SECTIONS
                if 'failed' not in kept[section.key]]
    except (KeyError, TypeError, ValueError, IndexError, AttributeError) as err:
        raise CommandError(f'{folder / name} does not hold what {kinds[name]} keeps '
                           f'({type(err).__name__}: {err}); was it written by another '
                           'version?') from None


def _replot_training(folder: Path, kept: dict) -> list[Path]:
    from tactex_classify.evaluation.training_report import plot_run
    schemes = kept['schemes']
    classes = list(next(iter(schemes.values()))['per_class'])
    plot_run(folder, classes, schemes)
    return [folder / 'confusion.png', folder / 'learning_curves.png',
            folder / 'accuracy_vs_time.png']


def _load(path: Path):
    from tactex_common.files import load_json
    try:
        value = load_json(path, max_bytes=MAX_JSON_BYTES, max_depth=MAX_JSON_DEPTH)
    except (UnicodeDecodeError, ValueError) as err:
        raise CommandError(f'{path}: not JSON ({err})') from None
    if not isinstance(value, dict):
        raise CommandError(f'{path}: expected a JSON object')
    return value
