# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What each launch argument may be, by its name, checked before any node starts.

An argument means the same in every launch file that takes it (system.launch.py hands
its `scene` to sim.launch.py's), so its check is keyed by name. Arguments with
`choices` are checked by `LaunchFile.resolve`; every other argument has a check here
(a test keeps it so). Each check raises `LaunchError` naming the argument, the value
and the fix, in one line, and writes nothing. A bundle given with a movement file is
then loaded against it, so that one trained for other movements or another window is
refused here rather than by identify_node once the system runs.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
import os
from pathlib import Path
import re
import stat

from tactex.errors import CommandError
from tactex.launching.spec import as_float, LaunchError, LaunchFile
from tactex.options import check_output_file, check_output_folder

# A ROS namespace without its leading slash: tokens of letters, digits and underscores,
# none starting with a digit, joined by single slashes (rmw_validate_namespace's rules).
_NAMESPACE = re.compile(r'[A-Za-z_][A-Za-z0-9_]*(/[A-Za-z_][A-Za-z0-9_]*)*')
# rmw's longest namespace, leading slash included (RMW_NAMESPACE_MAX_LENGTH).
NAMESPACE_MAX_LENGTH = 245


def _namespace(name: str, value: str) -> None:
    bare = value.strip('/')
    if bare and (not _NAMESPACE.fullmatch(bare) or len(bare) + 1 > NAMESPACE_MAX_LENGTH):
        raise LaunchError(f'{name}:={value!r} is not a ROS namespace: letters, digits and _ '
                          'in parts joined by /, no part starting with a digit, at most '
                          f'{NAMESPACE_MAX_LENGTH} characters (e.g. left_arm)')


def _scene(name: str, value: str) -> None:
    from tactex_sim.errors import SimError
    from tactex_sim.scene import load_scene, resolve_scene
    try:
        load_scene(resolve_scene(value))
    except SimError as err:
        raise LaunchError(f'{name}:={value!r}: {err}; give a scene under config/scenes/ or a '
                          '.toml path') from None


def _rate_factor(name: str, value: str) -> None:
    from tactex_sim.world import MAX_RATE_FACTOR
    if not 0.0 <= as_float(name, value) <= MAX_RATE_FACTOR:
        raise LaunchError(f'{name}:={value!r} must be from 0 to {MAX_RATE_FACTOR:g} simulated '
                          'seconds per wall second (0: as fast as possible)')


def _patch_texture(name: str, value: str) -> None:
    from tactex_sim.errors import UnknownNameError
    from tactex_sim.textures import texture
    if not value:  # the scene's
        return
    try:
        texture(value)
    except UnknownNameError as err:
        raise LaunchError(f"{name}:={value!r}: {err.args[0]}; or '' for the scene's") from None


def _checkpoint(name: str, value: str) -> None:
    from tactex_classify.errors import ClassifyError
    from tactex_classify.models.checkpoint import read_checkpoint
    if not value:  # no classifier (classify.launch.py asks for one itself)
        return
    try:
        read_checkpoint(Path(value).expanduser())
    except ClassifyError as err:
        raise LaunchError(f'{name}:={value!r}: {err}') from None


def _bundle(name: str, value: str) -> None:
    from tactex_classify.identification.bundle import BUNDLE_FILE
    if not value:  # no identification (identify.launch.py asks for one itself)
        return
    if not (Path(value).expanduser() / BUNDLE_FILE).is_file():
        raise LaunchError(f'{name}:={value!r} holds no {BUNDLE_FILE}: give RUN/bundle of '
                          '`tactex train DATA --movements YAML --out RUN`')


def _movements(name: str, value: str) -> None:
    from tactex.cli import describe
    from tactex_description.movements import load_movements, MovementError
    try:
        load_movements(Path(value).expanduser())
    except (MovementError, OSError) as err:
        raise LaunchError(f'{name}:={value!r}: {describe(err)}') from None


def _bundle_for_movements(values: Mapping[str, str]) -> None:
    """A given bundle was trained for the given movement file: its movements and window.

    Reads bundle.json and the checkpoints' metadata only; identify_node loads the models.

    Raises:
        LaunchError: the bundle's refusal (a checkpoint, a movement or the window), naming
            both arguments.
    """
    from tactex.cli import describe
    from tactex_classify.errors import ClassifyError
    from tactex_classify.identification.bundle import check_bundle
    from tactex_description.movements import load_movements
    bundle, movements = values.get('bundle'), values.get('movements')
    if not bundle or movements is None:
        return
    try:
        check_bundle(Path(bundle).expanduser(), load_movements(Path(movements).expanduser()))
    except (ClassifyError, OSError) as err:
        raise LaunchError(f'bundle:={bundle!r} with movements:={movements!r}: '
                          f'{describe(err)}') from None


def _threshold(name: str, value: str) -> None:
    from tactex_classify.online.evidence import EvidenceSettings
    try:
        EvidenceSettings(threshold=as_float(name, value))
    except ValueError as err:
        raise LaunchError(f'{name}:={value!r}: {err}') from None


def _recording_root(name: str, value: str) -> None:
    path = Path(value).expanduser()
    if path.is_dir():  # recordings add up in it
        if not os.access(path, os.W_OK | os.X_OK):
            raise LaunchError(f'{name} {path} is not writable; choose a folder you can write '
                              'to')
        return
    try:
        check_output_folder(path, name)
    except CommandError as err:
        raise LaunchError(str(err)) from None


def _pathway_file(name: str, value: str) -> None:
    if not value:
        raise LaunchError(f"{name}:='' names no file; give the path the pathway is kept at "
                          '(e.g. ~/.ros/tactex/pathway.json)')
    try:
        check_output_file(Path(value).expanduser(), name)
    except CommandError as err:
        raise LaunchError(str(err)) from None


def _serial_port(name: str, value: str) -> None:
    # A missing device is fine: the node opens it when it appears (plugged in later).
    path = Path(value)
    if not value or (path.exists() and not stat.S_ISCHR(path.stat().st_mode)):
        raise LaunchError(f'{name}:={value!r} is not a serial device; give its path (e.g. '
                          '/dev/ttyACM0, or a udev link to it)')


# Every launch argument without choices, by name: (name, value) -> None or LaunchError.
CHECKS: dict[str, Callable[[str, str], None]] = {
    'namespace': _namespace, 'scene': _scene, 'rate_factor': _rate_factor,
    'patch_texture': _patch_texture, 'checkpoint': _checkpoint, 'threshold': _threshold,
    'bundle': _bundle, 'movements': _movements,
    'recording_root': _recording_root, 'pathway_file': _pathway_file,
    'port': _serial_port, 'sensor_port': _serial_port, 'arm_port': _serial_port}


def check_arguments(launch: LaunchFile, values: Mapping[str, str]) -> None:
    """Check every argument of `launch` (resolved `values`), in its declared order.

    Raises:
        LaunchError: the first bad one, named with its value and the fix; or a bundle
            trained for another movement file than the one given.
    """
    for argument in launch.all_arguments:
        check = CHECKS.get(argument.name)
        if check is not None:
            check(argument.name, values[argument.name])
    _bundle_for_movements(values)
