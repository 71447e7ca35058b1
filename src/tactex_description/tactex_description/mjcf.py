# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""MJCF (MuJoCo) model of the arm and tactile module, generated from `geometry`.

Every link becomes a body at its joint origin, every moving joint a hinge or slide
with the same axis and range; compliant joints get their stiffness and damping, arm
joints and the gripper get position actuators standing in for the servos. Only the
sensor body collides: the arm's geoms are visual, so contact means the sensor touched.
"""

from __future__ import annotations

from dataclasses import dataclass
from xml.etree import ElementTree as ET

from transforms3d.euler import euler2quat

from tactex_common import frames
from tactex_description.geometry import (
    Joint,
    JointKind,
    JointRole,
    OPEN_MANIPULATOR_X,
    RobotGeometry,
)

SENSOR_GEOM = 'sensor_body'
SENSOR_EDGE_GEOM = 'sensor_edge_tip'
IMU_SITE = 'sensor_imu'
# Radius of the sphere at sensor_edge: the rim point that slides stands this far proud.
EDGE_TIP_RADIUS_M = 0.002


@dataclass(frozen=True)
class ServoModel:
    """Position-servo stand-in: stiffness (N m/rad or N/m), joint damping and armature."""

    kp_arm: float = 150.0
    damping_arm: float = 2.0
    armature_arm: float = 0.01
    kp_gripper: float = 200.0


def _fmt(values) -> str:
    return ' '.join(repr(float(v)) for v in values)


def _origin(robot: RobotGeometry, joint: str) -> tuple[float, float, float]:
    return robot.joint(joint).origin_xyz


def _link_geom(body: ET.Element, link: str, robot: RobotGeometry) -> None:
    """Add the visual or collision geometry of one link, sized from the joint origins."""
    visual = {'contype': '0', 'conaffinity': '0', 'group': '1', 'rgba': '0.75 0.75 0.78 1'}
    if link == 'link1':
        x, _, z = _origin(robot, 'joint1')  # the base turret up to joint1
        ET.SubElement(body, 'geom', type='cylinder', size=_fmt((0.025, z)),
                      pos=_fmt((x, 0.0, z)), **visual)
    elif link in ('link3', 'link4', 'link5'):
        # Each arm segment spans from its joint to the next one (link5: to the gripper).
        following = {'link3': 'joint3', 'link4': 'joint4', 'link5': 'gripper'}[link]
        x, _, z = _origin(robot, following)
        radius = {'link3': 0.014, 'link4': 0.013, 'link5': 0.012}[link]
        ET.SubElement(body, 'geom', type='capsule', fromto=_fmt((0, 0, 0, x, 0, z)),
                      size=repr(radius), **visual)
    elif link == 'sensor_mount':
        ET.SubElement(body, 'geom', type='box', size='0.012 0.012 0.010',
                      pos='0 0 -0.008', rgba='0.2 0.4 0.8 1', contype='0', conaffinity='0',
                      group='1')
    elif link == frames.SENSOR:
        # Polyurethane body with the MARG inside: the face and its rim are where the
        # geometry puts sensor_edge (rim radius, face distance past the chip).
        rim_radius, _, face = _origin(robot, 'sensor_edge_fixed')
        ET.SubElement(body, 'site', name=IMU_SITE, size='0.002')
        ET.SubElement(body, 'geom', name=SENSOR_GEOM, type='cylinder',
                      size=_fmt((rim_radius, face / 2)), pos=_fmt((0.0, 0.0, face / 2)),
                      rgba='0.95 0.8 0.2 1', friction='0.6 0.005 0.0001', condim='3')
    elif link == frames.EDGE:
        ET.SubElement(body, 'geom', name=SENSOR_EDGE_GEOM, type='sphere',
                      size=repr(EDGE_TIP_RADIUS_M),
                      rgba='1 0.3 0.1 1', friction='0.6 0.005 0.0001', condim='3')


def _add_joint(body: ET.Element, joint: Joint, servo: ServoModel) -> None:
    kind = 'hinge' if joint.kind is JointKind.REVOLUTE else 'slide'
    attributes = {'name': joint.name, 'type': kind, 'axis': _fmt(joint.axis),
                  'range': _fmt((joint.lower, joint.upper)), 'limited': 'true'}
    if joint.role is JointRole.COMPLIANT:
        attributes.update(stiffness=repr(joint.stiffness), damping=repr(joint.damping),
                          springref='0')
    elif joint.role is JointRole.ARM:
        attributes.update(damping=repr(servo.damping_arm), armature=repr(servo.armature_arm))
    ET.SubElement(body, 'joint', **attributes)


def build_mjcf(robot: RobotGeometry = OPEN_MANIPULATOR_X, *, timestep_s: float = 0.002,
               servo: ServoModel = ServoModel(), worldbody_xml: str = '',
               assets_xml: str = '', sensors_xml: str = '', compliant: bool = True) -> str:
    """Return an MJCF document of `robot`.

    Args:
        robot: the geometry to convert.
        timestep_s: physics step (s).
        servo: gains of the position actuators.
        worldbody_xml: extra elements (a surface, lights) placed in the worldbody.
        assets_xml: extra elements placed in `<asset>` (heightfields, textures).
        sensors_xml: elements placed in `<sensor>` (they may use the site `sensor_imu`).
        compliant: give the sensor body its compliant joints; False welds it to the mount.
    """
    mujoco = ET.Element('mujoco', model=robot.name)
    ET.SubElement(mujoco, 'compiler', angle='radian', inertiafromgeom='false',
                  autolimits='true')
    ET.SubElement(mujoco, 'option', timestep=repr(timestep_s), integrator='implicitfast')
    asset = ET.SubElement(mujoco, 'asset')
    for element in _fragment(assets_xml):
        asset.append(element)
    worldbody = ET.SubElement(mujoco, 'worldbody')
    bodies = {robot.root: worldbody}
    for joint in robot.joints:
        quat = euler2quat(*joint.origin_rpy, axes='sxyz')
        body = ET.SubElement(bodies[joint.parent], 'body', name=joint.child,
                             pos=_fmt(joint.origin_xyz), quat=_fmt(quat))
        bodies[joint.child] = body
        inertial = robot.inertials.get(joint.child)
        if inertial is not None:
            ET.SubElement(body, 'inertial', pos=_fmt(inertial.com_xyz),
                          mass=repr(inertial.mass_kg),
                          diaginertia=_fmt(inertial.inertia_diag))
        if joint.is_moving and (compliant or joint.role is not JointRole.COMPLIANT):
            _add_joint(body, joint, servo)
        _link_geom(body, joint.child, robot)
    for element in _fragment(worldbody_xml):
        worldbody.append(element)
    actuators = ET.SubElement(mujoco, 'actuator')
    equality = ET.SubElement(mujoco, 'equality')
    for joint in robot.joints:
        if joint.mimic_of:
            ET.SubElement(equality, 'joint', joint1=joint.name, joint2=joint.mimic_of)
        elif joint.role in (JointRole.ARM, JointRole.GRIPPER):
            kp = servo.kp_arm if joint.role is JointRole.ARM else servo.kp_gripper
            ET.SubElement(actuators, 'position', name=joint.name, joint=joint.name,
                          kp=repr(kp), ctrlrange=_fmt((joint.lower, joint.upper)),
                          forcerange=_fmt((-joint.effort, joint.effort)))
    sensor = ET.SubElement(mujoco, 'sensor')
    for element in _fragment(sensors_xml):
        sensor.append(element)
    ET.indent(mujoco, space='  ')
    return ET.tostring(mujoco, encoding='unicode') + '\n'


def _fragment(xml: str) -> list[ET.Element]:
    if not xml.strip():
        return []
    return list(ET.fromstring(f'<fragment>{xml}</fragment>'))
