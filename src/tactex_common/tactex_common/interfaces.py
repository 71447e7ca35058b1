# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The tactex_msgs interfaces as rosbags types, parsed from their .msg/.action files (no ROS).

Offline tools (the bag converter, notebooks) read recordings with rosbags on machines
without ROS. A rosbag2 file written by ROS 2 Iron or later carries the definition of
every type it holds; older ones (Humble's sqlite3 bags) carry none, and rosbags then
decodes with the typestore it is given. `typestore()` returns rosbags' store of the
standard ROS 2 types with the tactex_msgs messages and actions added, read from the
package's own definitions: the source checkout (src/tactex_msgs) or an installed share
directory (the venv of `make test`, or a colcon install on AMENT_PREFIX_PATH).

An action `tactex_msgs/action/Probe` gives the types ROS generates for it:
`Probe_Goal`, `Probe_Result`, `Probe_Feedback`, `Probe_FeedbackMessage` (the feedback
topic), `Probe_SendGoal_Request`/`_Response` and `Probe_GetResult_Request`/`_Response`.
"""

from __future__ import annotations

from functools import lru_cache
import os
from pathlib import Path
import sys
from typing import TYPE_CHECKING

from rosbags.typesys import get_types_from_msg, get_typestore, Stores, TypesysError
from rosbags.typesys.base import Nodetype

if TYPE_CHECKING:
    from rosbags.typesys.store import Typestore
    from rosbags.typesys.types import Typesdict

PACKAGE = 'tactex_msgs'
DEFAULT_STORE = Stores.ROS2_KILTED
_SOURCE = Path(__file__).resolve().parents[2] / PACKAGE  # src/tactex_msgs in a checkout
# The types ROS 2 wraps around an action's goal, result and feedback (rosidl_adapter).
_ACTION_WRAPPERS = (
    ('FeedbackMessage', 'unique_identifier_msgs/UUID goal_id\n{name}_Feedback feedback\n'),
    ('SendGoal_Request', 'unique_identifier_msgs/UUID goal_id\n{name}_Goal goal\n'),
    ('SendGoal_Response', 'bool accepted\nbuiltin_interfaces/Time stamp\n'),
    ('GetResult_Request', 'unique_identifier_msgs/UUID goal_id\n'),
    ('GetResult_Response', 'int8 status\n{name}_Result result\n'),
)


def interface_directory() -> Path:
    """Return the directory holding tactex_msgs' msg/ and action/ folders.

    Looked up in this order: the share directory of an install on AMENT_PREFIX_PATH
    (colcon), the source checkout this module belongs to, the share directory of the
    running Python's prefix (the venv `make test` builds into).

    Raises:
        FileNotFoundError: no definitions found; the message lists where it looked.
    """
    prefixes = [Path(p) for p in os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep) if p]
    candidates = [p / 'share' / PACKAGE for p in prefixes]
    candidates += [_SOURCE, Path(sys.prefix) / 'share' / PACKAGE]
    for candidate in candidates:
        if (candidate / 'msg').is_dir():
            return candidate
    looked = ', '.join(str(c) for c in candidates)
    raise FileNotFoundError(f'cannot find the {PACKAGE} definitions (msg/, action/) in: {looked}')


def interface_types(directory: Path | None = None) -> Typesdict:
    """Parse every .msg and .action file of tactex_msgs into rosbags type definitions.

    Args:
        directory: the folder holding msg/ and action/ (default: `interface_directory()`).

    Returns:
        Type name (e.g. 'tactex_msgs/msg/Contact') -> rosbags parse tree.

    Raises:
        FileNotFoundError: no definitions found.
        ValueError: a definition does not parse; the message names the file.
    """
    return dict(_parse(_checked(directory)))


def _checked(directory: Path | None) -> Path:
    """`directory` resolved (default: `interface_directory()`), if it holds msg/."""
    if directory is None:
        return interface_directory().resolve()
    if not (Path(directory) / 'msg').is_dir():
        raise FileNotFoundError(f'{directory} holds no {PACKAGE} definitions (no msg/ folder)')
    return Path(directory).resolve()


@lru_cache(maxsize=8)
def _parse(directory: Path) -> tuple[tuple[str, tuple], ...]:
    """Parse once per directory (the converter asks for every recording)."""
    types: Typesdict = {}
    for path in sorted((directory / 'msg').glob('*.msg')):
        types.update(_parse_file(path, f'{PACKAGE}/msg/{path.stem}', path.read_text()))
    for path in sorted((directory / 'action').glob('*.action')):
        types.update(_action_types(path))
    return tuple(types.items())


def _parse_file(path: Path, name: str, text: str) -> Typesdict:
    try:
        return get_types_from_msg(text, name)
    except TypesysError as err:
        raise ValueError(f'{path}: cannot parse {name!r}: {err}') from err


def _action_types(path: Path) -> Typesdict:
    """The goal, result, feedback and wrapper types of one .action file."""
    sections = path.read_text().split('\n---')
    if len(sections) != 3:
        raise ValueError(f'{path}: an action needs 3 sections separated by "---", '
                         f'found {len(sections)}')
    name = f'{PACKAGE}/action/{path.stem}'
    types: Typesdict = {}
    for suffix, text in zip(('Goal', 'Result', 'Feedback'), sections, strict=True):
        types.update(_parse_file(path, f'{name}_{suffix}', text))
    for suffix, template in _ACTION_WRAPPERS:
        types.update(_parse_file(path, f'{name}_{suffix}',
                                 template.format(name=f'{PACKAGE}/action/{path.stem}')))
    # A bare type name in an .action file names a message of the same package, while
    # rosbags resolves it next to the action (tactex_msgs/action/Pathway).
    own = set(types)
    return {typename: (constants, [(field, _message_ref(desc, own)) for field, desc in fields])
            for typename, (constants, fields) in types.items()}


def _message_ref(desc: tuple, own: set[str]) -> tuple:
    """`desc` with a reference to tactex_msgs/action/X turned into tactex_msgs/msg/X."""
    kind, value = desc
    if kind == Nodetype.NAME and value.startswith(f'{PACKAGE}/action/') and value not in own:
        return kind, f'{PACKAGE}/msg/{value.rsplit("/", 1)[1]}'
    if kind in (Nodetype.ARRAY, Nodetype.SEQUENCE):
        inner, size = value
        return kind, (_message_ref(inner, own), size)
    return desc


def typestore(store: Stores = DEFAULT_STORE, *, directory: Path | None = None) -> Typestore:
    """Return a new rosbags typestore of `store`'s standard types plus tactex_msgs.

    Args:
        store: the ROS 2 distribution's store (default: Kilted, as the PyPI wheels).
        directory: where msg/ and action/ are (default: `interface_directory()`).

    Raises:
        FileNotFoundError: no definitions found.
        ValueError: a definition does not parse.
    """
    registered = _registered(store, _checked(directory))
    result = get_typestore(store)
    # Registering generates and compiles code (about 10 ms); copy it from the cached store.
    result.fielddefs.update(registered.fielddefs)
    result.types.update(registered.types)
    return result


@lru_cache(maxsize=8)
def _registered(store: Stores, directory: Path) -> Typestore:
    registered = get_typestore(store)
    registered.register(dict(_parse(directory)))
    return registered
