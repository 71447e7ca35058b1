# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Checks of command-line values and paths, run before any long work starts.

Value types for argparse (`integer`, `number`) refuse by value with the rule in the
message; path checks (`check_output_file`, `check_output_folder`, `check_input_file`,
`check_input_folder`) raise `CommandError` naming the option and the fix, and leave
nothing behind: an output is never a symbolic link (it would be written through or
replaced), and its folder is proven writable by making and removing a folder there, so
a run fails before its work, not after. An input file must be a regular file (a FIFO
would block the reader, a device never end). `staged_folder` builds an output folder
beside its final path and moves it into place only when the work succeeded, so a failure
leaves nothing behind.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable, Iterator
from contextlib import contextmanager
import glob
import itertools
import math
import os
from pathlib import Path
import re
import secrets
import shutil
import sys
import tempfile

from tactex.errors import CommandError
from tactex_classify.models.checkpoint import MAX_WINDOW
from tactex_classify.models.registry import MAX_EPOCHS
from tactex_common.constants import MAX_SEED
from tactex_common.errors import RefusedFileError
from tactex_common.files import check_regular


def integer(minimum: int, maximum: int | None = None) -> Callable[[str], int]:
    """An argparse type: a whole number in [minimum, maximum]."""
    rule = f'>= {minimum}' if maximum is None else f'in {minimum}..{maximum}'

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f'must be a whole number {rule}, got {text!r}'
                                             ) from None
        if value < minimum or (maximum is not None and value > maximum):
            raise argparse.ArgumentTypeError(f'must be a whole number {rule}, got {text!r}')
        return value
    parse.__name__ = 'integer'
    return parse


def number(*, above: float | None = 0.0, at_least: float | None = None,
           at_most: float | None = None) -> Callable[[str], float]:
    """An argparse type: a finite number > `above` (or >= `at_least`), <= `at_most`."""
    rules = [f'> {above:g}' if above is not None and at_least is None else '',
             f'>= {at_least:g}' if at_least is not None else '',
             f'<= {at_most:g}' if at_most is not None else '']
    rule = ' and '.join(r for r in rules if r) or 'finite'

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        if not math.isfinite(value) or (at_least is None and above is not None
                                        and value <= above) \
                or (at_least is not None and value < at_least) \
                or (at_most is not None and value > at_most):
            raise argparse.ArgumentTypeError(f'must be a finite number {rule}, got {text!r}')
        return value
    parse.__name__ = 'number'
    return parse


# Whole numbers that size memory or time, each bounded (the limit is in the error).
seed_value = integer(0, MAX_SEED)
epoch_count = integer(1, MAX_EPOCHS)
patience_epochs = integer(0, MAX_EPOCHS)
window_samples = integer(2, MAX_WINDOW)
hop_samples = integer(1, MAX_WINDOW)
fold_count = integer(2, 1000)
trial_id = integer(0, 2**32 - 1)  # uint32, as the Sweep goal carries it

RAY_ADDRESS = re.compile(r'^(ray://)?[A-Za-z0-9_.\-\[\]:]+:\d{1,5}$')


def ray_address(value: str) -> str:
    """An argparse type: a Ray cluster address, HOST:PORT or ray://HOST:PORT."""
    if not RAY_ADDRESS.match(value):
        raise argparse.ArgumentTypeError(f'must be HOST:PORT or ray://HOST:PORT (as `ray start '
                                         f'--head` prints it), got {value!r}')
    return value


def output_path(value: str) -> Path:
    """An argparse type: a path to write to, never empty ('' would be the current folder)."""
    if not value.strip():
        raise argparse.ArgumentTypeError('must not be empty: give the path to write to')
    return Path(value)


def input_path(value: str) -> Path:
    """An argparse type: a path to read, never empty ('' would be the current folder)."""
    if not value.strip():
        raise argparse.ArgumentTypeError('must not be empty: give the path of what to read')
    return Path(value)


def text(value: str) -> str:
    """An argparse type: non-blank text."""
    if not value.strip():
        raise argparse.ArgumentTypeError('must not be empty')
    return value


def _writable_parent(path: Path, option: str) -> None:
    """The nearest existing ancestor of `path` is a folder we may write into."""
    ancestor = path.parent
    while not ancestor.exists() and ancestor != ancestor.parent:
        if ancestor.is_symlink():
            raise CommandError(f'{option} {path}: {ancestor} is a broken link')
        ancestor = ancestor.parent
    if not ancestor.is_dir():
        raise CommandError(f'{option} {path}: {ancestor} is a file, not a folder; choose a '
                           'path inside a folder')
    _check_writable(ancestor, f'{option} {path}: {ancestor}')


def _check_writable(folder: Path, what: str) -> None:
    """Make and remove a folder in `folder` (os.access says yes to root on any folder)."""
    try:
        os.rmdir(tempfile.mkdtemp(prefix='.tactex-writable-', dir=folder))
    except OSError as err:
        raise CommandError(f'{what} is not writable ({err.strerror}); choose a folder you can '
                           'write to') from None


def _check_not_a_link(path: Path, option: str) -> None:
    if path.is_symlink():
        raise CommandError(f'{option} {path} is a symbolic link (to {os.readlink(path)}); give '
                           'the path itself: an output never writes through or replaces a link')


def check_output_file(path: Path, option: str = '--out', *, suffix: str | None = None,
                      companions: tuple[str, ...] = ()) -> Path:
    """`path` can be written as a file (replacing a file there); nothing is created.

    Args:
        path: the output file.
        option: the option's name, for messages.
        suffix: the suffix the file must have (added when missing).
        companions: suffixes of files written beside it (e.g. a sidecar's '.json').
    """
    path = given = Path(path)
    if suffix is not None:
        if path.suffix and path.suffix != suffix:
            raise CommandError(f'{option} {path}: must end in {suffix}')
        path = path.with_suffix(suffix)
    for item in (given, path, *(path.with_suffix(s) for s in companions)):
        _check_not_a_link(item, option)
        if item.is_dir():
            raise CommandError(f'{option} {item} is a folder; give a file path such as '
                               f'{item / ("data" + (suffix or ""))}')
    _writable_parent(path, option)
    return path


def refuse_to_replace(path: Path, *, force: bool, companions: tuple[str, ...] = (),
                      option: str = '--out') -> None:
    """Refuse an output file (or a companion beside it) that exists, unless `force`.

    Raises:
        CommandError: naming the existing file and --force.
    """
    existing = [item for item in (path, *(path.with_suffix(s) for s in companions))
                if item.exists()]
    if existing and not force:
        raise CommandError(f'{option} {existing[0]} exists; give --force to replace it, or '
                           f'another {option}')


def check_output_folder(path: Path, option: str = '--out') -> Path:
    """`path` is a folder to create (or an empty one); nothing is created.

    Raises:
        CommandError: a file is there, the folder holds files, or it cannot be written.
    """
    path = Path(path)
    _check_not_a_link(path, option)
    if path.exists() and not path.is_dir():
        raise CommandError(f'{option} {path} is a file; give a folder path')
    if path.is_dir() and any(path.iterdir()):
        raise CommandError(f'{option} {path} already holds files; choose a new folder (or '
                           'empty this one)')
    if path.is_dir():
        _check_writable(path, f'{option} {path}')
    _writable_parent(path, option)
    return path


def check_input_file(path: Path, option: str, hint: str = '') -> Path:
    """`path` is an existing, readable regular file (never opened here).

    `hint` (how to get the file) is said when it does not exist.
    """
    path = Path(path)
    if not path.exists():
        raise CommandError(f'{option} {path} does not exist' + (f'; {hint}' if hint else ''))
    if path.is_dir():
        raise CommandError(f'{option} {path} is a folder; give a file')
    try:
        check_regular(path)
    except RefusedFileError as err:
        raise CommandError(f'{option} {err}') from None
    if not os.access(path, os.R_OK):
        raise CommandError(f'{option} {path} is not readable')
    return path


def load_dataset(path: Path, option: str):
    """The converted dataset at `path` (its .npz; the suffix may be left out), given with `option`.

    Raises:
        CommandError: naming `option` and how to make one: missing, a folder, another kind
            of file, a sidecar missing, or not a dataset.
    """
    from tactex_classify.data.dataset import Dataset
    from tactex_classify.errors import DatasetError

    path = Path(path)
    make = 'make one with `tactex convert BAGS --out DATA.npz`'
    if path.is_dir():
        raise CommandError(f'{option} {path} is a folder; give the .npz dataset that '
                           f'`tactex convert` wrote ({make})')
    if path.suffix not in ('', '.npz'):
        raise CommandError(f'{option} {path} is not a dataset: give the .npz file that '
                           f'`tactex convert` wrote ({make})')
    path = path.with_suffix('.npz')
    check_input_file(path, option, hint=make)
    check_input_file(path.with_suffix('.json'), f'{option} {path}: its sidecar',
                     hint='convert writes it beside the .npz; keep the two together')
    try:
        return Dataset.load(path)
    except DatasetError as err:
        raise CommandError(f'{option} {err}') from None


MOVEMENTS_HINT = "give a movement file, such as the workspace's config/movements.yaml (default)"


def movement_file(path: Path, sample_rate_hz: float | None):
    """The `--movements` file, every movement held to the arm and to the sensor's rate.

    Each contact must hold one window after the converter's first `slide_span_s`, which it
    does not count as sliding.

    Raises:
        CommandError: the file is missing or unreadable, or a movement is refused (the
            loader's reason, naming the movement and the key).
    """
    from tactex_classify.data.dataset import FilterRule
    from tactex_description.movements import load_movements, MovementError

    check_input_file(path, '--movements', hint=MOVEMENTS_HINT)
    try:  # the converter does not keep a contact's first slide_span_s: it must hold a window
        return load_movements(path, sample_rate_hz=sample_rate_hz,
                              unmeasured_s=FilterRule().slide_span_s)
    except MovementError as err:
        raise CommandError(f'--movements {err}') from None


def check_input_folder(path: Path, option: str, hint: str = '') -> Path:
    """`path` is an existing folder (`hint`: how to get one, said when it does not exist)."""
    path = Path(path)
    if not path.exists():
        raise CommandError(f'{option} {path} does not exist' + (f'; {hint}' if hint else ''))
    if not path.is_dir():
        raise CommandError(f'{option} {path} is a file; give a folder')
    return path


def _remove_abandoned_stagings(path: Path) -> None:
    """Remove the staged folders of `path` left by runs that were killed (SIGKILL, power).

    A staging folder's name holds the process id that made it; one whose process no
    longer runs is removed, and said so on stderr. A live run's is left alone.
    """
    for staging in path.parent.glob(f'.{glob.escape(path.name)}.partial-*'):
        owner = staging.name.rsplit('.partial-', 1)[1].split('-', 1)[0]
        if owner.isdigit() and not Path(f'/proc/{owner}').exists() and staging.is_dir():
            shutil.rmtree(staging, ignore_errors=True)
            print(f'note: removed {staging}, left unfinished by a run that was killed',
                  file=sys.stderr)


@contextmanager
def staged_folder(path: Path) -> Iterator[Path]:
    """A hidden folder beside `path`, moved to `path` when the block succeeds.

    On an error the staged folder is removed and `path` is left as it was; one that a
    killed run left behind is removed by the next run (never reused).
    """
    path = Path(path)
    _remove_abandoned_stagings(path)
    staging = path.with_name(f'.{path.name}.partial-{os.getpid()}-{secrets.token_hex(4)}')
    made = list(itertools.takewhile(lambda folder: not folder.exists(), staging.parents))
    staging.mkdir(parents=True)
    try:
        yield staging
        if path.is_dir():
            path.rmdir()  # checked empty by check_output_folder
        os.replace(staging, path)
    finally:
        if staging.exists():
            shutil.rmtree(staging, ignore_errors=True)
        if not path.exists():  # the block failed: the folders made for it go too
            for folder in made:  # innermost first
                try:
                    folder.rmdir()
                except OSError:
                    break


def check_finite_windows(dataset, path: Path, option: str = 'DATA') -> None:
    """Refuse a dataset with NaN or inf in a window, naming its recordings and the fix.

    Raises:
        CommandError: naming `option`, the windows and recordings, and the fix.
    """
    import numpy as np
    bad = ~np.all(np.isfinite(dataset.X), axis=(1, 2))
    if bad.any():
        trials = np.unique(dataset.trial[bad]).tolist()
        raise CommandError(f'{option} {path}: {int(bad.sum())} window(s) hold NaN or inf '
                           f'(trials {", ".join(map(str, trials[:5]))}'
                           f'{"..." if len(trials) > 5 else ""}); convert or import the '
                           'recordings again (both drop non-finite samples)')


ROS_NAME_SEGMENT = re.compile(r'^[A-Za-z_][A-Za-z0-9_]*$')


def is_ros_name(name: str) -> bool:
    """Segments of letters, digits and _ (not starting with a digit) split by / ('' too)."""
    name = name.strip('/')
    return not name or all(ROS_NAME_SEGMENT.match(segment) for segment in name.split('/'))


def namespace(value: str) -> str:
    """An argparse type: a ROS namespace (segments of letters, digits and _, split by /)."""
    if not is_ros_name(value):
        raise argparse.ArgumentTypeError(
            f'must be a ROS namespace such as left_arm or /robots/left (letters, digits and _, '
            f'not starting with a digit, split by /), got {value!r}')
    return value


def topic_name(value: str) -> str:
    """An argparse type: a ROS topic name (as a namespace, but not empty)."""
    if not value.strip('/') or not is_ros_name(value):
        raise argparse.ArgumentTypeError(
            f'must be a ROS topic name such as /tactile/imu/data_raw (letters, digits and _, '
            f'not starting with a digit, split by /), got {value!r}')
    return value


MAX_SERVER_WAIT_S = 3600.0  # an hour: a node that has not answered by then will not


def add_goal_options(parser: argparse.ArgumentParser, node: str) -> None:
    """--namespace, --server-timeout and --timeout of a command that sends `node` a goal."""
    parser.add_argument('--namespace', type=namespace, default='', metavar='NS',
                        help=f'namespace of {node} (e.g. left_arm)')
    parser.add_argument('--server-timeout', type=number(at_most=MAX_SERVER_WAIT_S), default=30.0,
                        metavar='S', help=f'seconds to wait for {node} and for it to accept '
                        f'the goal (30; at most {MAX_SERVER_WAIT_S:g})')
    parser.add_argument('--timeout', type=number(), default=1800.0, metavar='S',
                        help='seconds the goal may run before it is canceled (1800)')
