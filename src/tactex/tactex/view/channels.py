# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What the live view shows, as Foxglove channels: pure conversions from plain values.

The arm's links as `foxglove.FrameTransforms` (from joint states, through the robot
description's joints), the probed pathway as a `foxglove.SceneUpdate` (a sphere per
contact, an arrow along its normal) and the tactile channels, the sweep state and the
texture estimates as JSON with a JSON schema each (Foxglove has no schema of its own for
an IMU sample or a class posterior). Channel names are the ROS topics' relative names
with a leading slash, so one layout fits every namespace. The robot description and its
files are served to Foxglove's URDF layer as `package://` assets, from the packages'
share folders only.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
import json
from pathlib import Path

from foxglove import messages as fm
import numpy as np
from transforms3d.quaternions import mat2quat

from tactex_common import frames, topics
from tactex_common.share import share_directory
from tactex_description.geometry import OPEN_MANIPULATOR_X
from tactex_description.kinematics import joint_transform

TF_CHANNEL = '/tf'
PATHWAY_CHANNEL = '/probe/scene'
LAYOUT_FILE = 'foxglove_layout.json'  # under the tactex share folder's config/
PACKAGES = ('tactex', 'tactex_description')  # whose files the view may serve
_VECTOR = {'type': 'object', 'properties': {a: {'type': 'number'} for a in 'xyz'}}
# JSON channels: ROS topic -> (schema name, JSON schema of the message).
JSON_CHANNELS = {
    topics.IMU_RAW: ('tactex.ImuSample', {
        'type': 'object', 'properties': {'linear_acceleration': _VECTOR,
                                         'angular_velocity': _VECTOR}}),
    topics.IMU_FILTERED: ('tactex.Orientation', {
        'type': 'object', 'properties': {'orientation': {
            'type': 'object', 'properties': {a: {'type': 'number'} for a in 'xyzw'}}}}),
    topics.MAG: ('tactex.MagneticField', {
        'type': 'object', 'properties': {'magnetic_field': _VECTOR}}),
    topics.PRESSURE: ('tactex.Pressure', {
        'type': 'object', 'properties': {'fluid_pressure': {'type': 'number'}}}),
    topics.SWEEP_ACTIVE: ('tactex.SweepActive', {
        'type': 'object', 'properties': {'active': {'type': 'boolean'}}}),
    topics.TEXTURE_ESTIMATE: ('tactex.TextureEstimate', {
        'type': 'object', 'properties': {
            'label': {'type': 'string'}, 'confidence': {'type': 'number'},
            'decided': {'type': 'boolean'}, 'windows_used': {'type': 'integer'},
            'contact_seconds': {'type': 'number'},
            'probabilities': {'type': 'object', 'additionalProperties': {'type': 'number'}}}}),
}


def channel_name(topic: str) -> str:
    """The Foxglove channel of a relative ROS topic."""
    return '/' + topic.strip('/')


def schema_bytes(schema: Mapping) -> bytes:
    """A JSON schema as the bytes a Foxglove channel declares."""
    return json.dumps(schema, sort_keys=True).encode()


def timestamp(stamp_ns: int) -> fm.Timestamp:
    """A Foxglove timestamp of nanoseconds."""
    seconds, nanoseconds = divmod(int(stamp_ns), 1_000_000_000)
    return fm.Timestamp(sec=seconds, nsec=nanoseconds)


def frame_transforms(positions: Mapping[str, float], stamp_ns: int) -> fm.FrameTransforms:
    """Every joint's parent -> child transform at `positions` (absent joints at 0)."""
    transforms = []
    for joint in OPEN_MANIPULATOR_X.joints:
        matrix = joint_transform(joint, float(positions.get(joint.name, 0.0)))
        w, x, y, z = mat2quat(matrix[:3, :3])
        tx, ty, tz = (float(v) for v in matrix[:3, 3])
        transforms.append(fm.FrameTransform(
            timestamp=timestamp(stamp_ns), parent_frame_id=joint.parent,
            child_frame_id=joint.child, translation=fm.Vector3(x=tx, y=ty, z=tz),
            rotation=fm.Quaternion(x=float(x), y=float(y), z=float(z), w=float(w))))
    return fm.FrameTransforms(transforms=transforms)


def pathway_scene(points: np.ndarray, normals: np.ndarray, frame_id: str,
                  stamp_ns: int) -> fm.SceneUpdate:
    """The contacts as spheres and their normals as 20 mm arrows, replacing the last set."""
    spheres, arrows = [], []
    for point, normal in zip(np.asarray(points, float).reshape(-1, 3),
                             np.asarray(normals, float).reshape(-1, 3), strict=True):
        spheres.append(fm.SpherePrimitive(pose=_pose(point, (1.0, 0.0, 0.0, 0.0)),
                                          size=fm.Vector3(x=0.003, y=0.003, z=0.003),
                                          color=fm.Color(r=0.1, g=0.8, b=0.2, a=1.0)))
        arrows.append(fm.ArrowPrimitive(pose=_pose(point, _along_x(normal)),
                                        shaft_length=0.015, shaft_diameter=0.001,
                                        head_length=0.005, head_diameter=0.003,
                                        color=fm.Color(r=0.1, g=0.3, b=0.9, a=1.0)))
    entity = fm.SceneEntity(timestamp=timestamp(stamp_ns), frame_id=frame_id or frames.BASE,
                            id='pathway', spheres=spheres, arrows=arrows)
    return fm.SceneUpdate(deletions=[fm.SceneEntityDeletion(
        timestamp=timestamp(stamp_ns), type=fm.SceneEntityDeletionType.MatchingId,
        id='pathway')], entities=[entity])


def _pose(point: Sequence[float], quaternion_wxyz: Sequence[float]) -> fm.Pose:
    w, x, y, z = (float(v) for v in quaternion_wxyz)
    px, py, pz = (float(v) for v in point)
    return fm.Pose(position=fm.Vector3(x=px, y=py, z=pz),
                   orientation=fm.Quaternion(x=x, y=y, z=z, w=w))


def _along_x(direction: Sequence[float]) -> tuple[float, float, float, float]:
    """The rotation (w, x, y, z) turning +x onto `direction` (a Foxglove arrow points +x)."""
    d = np.asarray(direction, float)
    norm = np.linalg.norm(d)
    if not np.isfinite(norm) or norm == 0.0:
        return (1.0, 0.0, 0.0, 0.0)
    d = d / norm
    axis = np.cross((1.0, 0.0, 0.0), d)
    w = 1.0 + d[0]
    if w < 1e-9:  # opposite: half a turn about z
        return (0.0, 0.0, 0.0, 1.0)
    q = np.array([w, *axis])
    return tuple(float(v) for v in q / np.linalg.norm(q))


def asset(uri: str) -> bytes | None:
    """The file a `package://PACKAGE/PATH` URI names, inside that package's share folder.

    None for any other scheme, an unknown package, a path leaving the share folder, or a
    missing file: the view serves the robot description, nothing else of this machine.
    """
    prefix = 'package://'
    if not uri.startswith(prefix):
        return None
    package, _, relative = uri[len(prefix):].partition('/')
    if package not in PACKAGES or not relative:
        return None
    try:
        root = share_directory(package).resolve()
        path = (root / relative).resolve()
    except (FileNotFoundError, OSError):
        return None
    if root not in path.parents or not path.is_file():
        return None
    return path.read_bytes()


def layout_path() -> Path:
    """The Foxglove layout that opens every channel of the view in one window."""
    return share_directory('tactex') / 'config' / LAYOUT_FILE
