# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The one source of truth for the robot's geometry: frames, joints, limits and compliance.

Every other artefact (URDF, MJCF, kinematics, driver limits) is derived from
`OPEN_MANIPULATOR_X`. Units are SI (m, rad, kg, N, s) as in REP-103.

Arm values are ROBOTIS's OpenMANIPULATOR-X (RM-X52-TNM) description. Position limits
are ROBOTIS's (joint1 +-0.9 pi, joint2 -0.57..0.5 pi, joint3 -0.3..0.44 pi, joint4
-0.57..0.65 pi). The velocity limit of the arm joints is 2.0 rad/s: the XM430-W350
turns 4.8 rad/s unloaded at 12 V, and tactile exploration never needs more than a
fraction of that, so the limit keeps a margin for the compliant sensor. Planned
trajectories also keep the arm joints within 4.0 rad/s^2 (URDF has no acceleration
limit; the value is ours): full speed in half a second, gentle on the compliant body.

The tactile module sits on a 3D-printed mount held by the gripper. Its compliant
polyurethane body is modelled as revolute joints about x, y, z followed by a
prismatic joint along z (the sensor's outward axis), each with a stiffness and a
damping; `sensor_link` is the MARG chip and `sensor_edge` the point of the face rim
that slides on the surface during a sweep.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import enum
import math

from tactex_common import frames


class JointKind(enum.Enum):
    """How a joint moves."""

    REVOLUTE = 'revolute'
    PRISMATIC = 'prismatic'
    FIXED = 'fixed'


class JointRole(enum.Enum):
    """What a joint is for: the driver commands ARM and GRIPPER, the body bends COMPLIANT."""

    ARM = 'arm'
    GRIPPER = 'gripper'
    COMPLIANT = 'compliant'
    STRUCTURE = 'structure'


Vector3 = tuple[float, float, float]


@dataclass(frozen=True)
class Inertial:
    """Mass (kg), centre of mass (m, in the link frame) and principal inertia (kg m^2)."""

    mass_kg: float
    com_xyz: Vector3
    inertia_diag: Vector3


@dataclass(frozen=True)
class Joint:
    """A joint from `parent` to `child` link, with limits in rad (m for prismatic)."""

    name: str
    parent: str
    child: str
    kind: JointKind
    role: JointRole
    origin_xyz: Vector3
    origin_rpy: Vector3 = (0.0, 0.0, 0.0)
    axis: Vector3 = (0.0, 0.0, 1.0)
    lower: float = 0.0
    upper: float = 0.0
    velocity: float = 0.0
    acceleration: float = 0.0
    effort: float = 0.0
    stiffness: float = 0.0
    damping: float = 0.0
    mimic_of: str | None = None

    @property
    def is_moving(self) -> bool:
        """True for revolute and prismatic joints."""
        return self.kind is not JointKind.FIXED


@dataclass(frozen=True)
class RobotGeometry:
    """A tree of links and joints, rooted at `root`."""

    name: str
    root: str
    joints: tuple[Joint, ...]
    inertials: dict[str, Inertial] = field(default_factory=dict)

    def joint(self, name: str) -> Joint:
        """Return the joint called `name`.

        Raises:
            KeyError: no such joint; the message lists the known ones.
        """
        for joint in self.joints:
            if joint.name == name:
                return joint
        known = ', '.join(j.name for j in self.joints)
        raise KeyError(f'no joint {name!r}; known joints: {known}')

    @property
    def links(self) -> tuple[str, ...]:
        """All link names, root first, in tree order."""
        return (self.root,) + tuple(j.child for j in self.joints)

    def chain_to(self, link: str) -> tuple[Joint, ...]:
        """Return the joints from the root down to `link`, root side first.

        Raises:
            KeyError: no such link; the message lists the known ones.
        """
        by_child = {j.child: j for j in self.joints}
        if link != self.root and link not in by_child:
            raise KeyError(f'no link {link!r}; known links: {", ".join(self.links)}')
        chain = []
        while link != self.root:
            joint = by_child[link]
            chain.append(joint)
            link = joint.parent
        return tuple(reversed(chain))


ARM_JOINT_NAMES = ('joint1', 'joint2', 'joint3', 'joint4')
GRIPPER_JOINT_NAME = 'gripper'
JOINT_STATE_NAMES = ARM_JOINT_NAMES + (GRIPPER_JOINT_NAME,)
COMPLIANT_JOINT_NAMES = ('sensor_roll', 'sensor_pitch', 'sensor_yaw', 'sensor_press')

ARM_VELOCITY_LIMIT = 2.0  # rad/s, see module docstring
ARM_ACCELERATION_LIMIT = 4.0  # rad/s^2, see module docstring
ARM_EFFORT_LIMIT = 4.1  # N m, XM430-W350 stall torque at 12 V

_PI = math.pi


def _arm_joint(name: str, parent: str, child: str, origin_xyz: Vector3, axis: Vector3,
               lower_pi: float, upper_pi: float) -> Joint:
    """A servo joint of the arm, its position limits given in multiples of pi."""
    return Joint(name, parent, child, JointKind.REVOLUTE, JointRole.ARM, origin_xyz, axis=axis,
                 lower=lower_pi * _PI, upper=upper_pi * _PI, velocity=ARM_VELOCITY_LIMIT,
                 acceleration=ARM_ACCELERATION_LIMIT, effort=ARM_EFFORT_LIMIT)

OPEN_MANIPULATOR_X = RobotGeometry(
    name='open_manipulator_x_tactile',
    root=frames.WORLD,
    joints=(
        Joint('world_fixed', frames.WORLD, frames.BASE, JointKind.FIXED, JointRole.STRUCTURE,
              (0.0, 0.0, 0.0)),
        Joint('base_fixed', frames.BASE, 'link1', JointKind.FIXED, JointRole.STRUCTURE,
              (0.0, 0.0, 0.0)),
        _arm_joint('joint1', 'link1', 'link2', (0.012, 0.0, 0.017), (0.0, 0.0, 1.0), -0.9, 0.9),
        _arm_joint('joint2', 'link2', 'link3', (0.0, 0.0, 0.0595), (0.0, 1.0, 0.0), -0.57, 0.5),
        _arm_joint('joint3', 'link3', 'link4', (0.024, 0.0, 0.128), (0.0, 1.0, 0.0), -0.3, 0.44),
        _arm_joint('joint4', 'link4', 'link5', (0.124, 0.0, 0.0), (0.0, 1.0, 0.0), -0.57, 0.65),
        Joint('gripper', 'link5', 'gripper_link', JointKind.PRISMATIC, JointRole.GRIPPER,
              (0.0817, 0.021, 0.0), axis=(0.0, 1.0, 0.0),
              lower=-0.010, upper=0.019, velocity=0.05, effort=10.0),
        Joint('gripper_sub', 'link5', 'gripper_link_sub', JointKind.PRISMATIC,
              JointRole.GRIPPER, (0.0817, -0.021, 0.0), axis=(0.0, -1.0, 0.0),
              lower=-0.010, upper=0.019, velocity=0.05, effort=10.0, mimic_of='gripper'),
        Joint('end_effector_fixed', 'link5', 'end_effector_link', JointKind.FIXED,
              JointRole.STRUCTURE, (0.126, 0.0, 0.0)),
        # The printed mount extends 30 mm past the gripper centre; its z axis is the
        # tool's forward axis, so the sensor presses along +z of sensor_mount.
        Joint('sensor_mount_fixed', 'end_effector_link', 'sensor_mount', JointKind.FIXED,
              JointRole.STRUCTURE, (0.030, 0.0, 0.0), origin_rpy=(0.0, _PI / 2, 0.0)),
        Joint('sensor_roll', 'sensor_mount', 'sensor_roll_link', JointKind.REVOLUTE,
              JointRole.COMPLIANT, (0.0, 0.0, 0.0), axis=(1.0, 0.0, 0.0),
              lower=-0.35, upper=0.35, velocity=10.0, effort=1.0,
              stiffness=0.30, damping=0.004),
        Joint('sensor_pitch', 'sensor_roll_link', 'sensor_pitch_link', JointKind.REVOLUTE,
              JointRole.COMPLIANT, (0.0, 0.0, 0.0), axis=(0.0, 1.0, 0.0),
              lower=-0.35, upper=0.35, velocity=10.0, effort=1.0,
              stiffness=0.30, damping=0.004),
        Joint('sensor_yaw', 'sensor_pitch_link', 'sensor_yaw_link', JointKind.REVOLUTE,
              JointRole.COMPLIANT, (0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0),
              lower=-0.20, upper=0.20, velocity=10.0, effort=1.0,
              stiffness=0.20, damping=0.003),
        # Negative travel compresses the body towards the mount.
        Joint('sensor_press', 'sensor_yaw_link', frames.SENSOR, JointKind.PRISMATIC,
              JointRole.COMPLIANT, (0.0, 0.0, 0.012), axis=(0.0, 0.0, 1.0),
              lower=-0.006, upper=0.0, velocity=0.5, effort=20.0,
              stiffness=600.0, damping=3.0),
        # Face 10 mm beyond the MARG chip, rim radius 15 mm, in the arm's plane.
        Joint('sensor_edge_fixed', frames.SENSOR, frames.EDGE, JointKind.FIXED,
              JointRole.STRUCTURE, (0.015, 0.0, 0.010)),
    ),
    inertials={
        'link1': Inertial(0.0795, (-0.0003, 0.0, 0.0190), (2.3e-5, 2.9e-5, 2.1e-5)),
        'link2': Inertial(0.0984, (0.0, 0.0009, 0.0286), (3.5e-5, 3.2e-5, 1.9e-5)),
        'link3': Inertial(0.1385, (0.0103, 0.0004, 0.1018), (3.3e-4, 3.4e-4, 6.0e-5)),
        'link4': Inertial(0.1325, (0.0909, 0.0004, 0.0), (3.1e-5, 1.8e-4, 1.9e-4)),
        'link5': Inertial(0.1437, (0.0442, 0.0, 0.0089), (8.0e-5, 7.5e-5, 9.3e-5)),
        'gripper_link': Inertial(0.0100, (0.0, 0.0, 0.0), (1.0e-6, 1.0e-6, 1.0e-6)),
        'gripper_link_sub': Inertial(0.0100, (0.0, 0.0, 0.0), (1.0e-6, 1.0e-6, 1.0e-6)),
        'sensor_mount': Inertial(0.0200, (0.0, 0.0, -0.010), (4.0e-6, 4.0e-6, 2.0e-6)),
        'sensor_roll_link': Inertial(0.0010, (0.0, 0.0, 0.0), (1.0e-8, 1.0e-8, 1.0e-8)),
        'sensor_pitch_link': Inertial(0.0010, (0.0, 0.0, 0.0), (1.0e-8, 1.0e-8, 1.0e-8)),
        'sensor_yaw_link': Inertial(0.0010, (0.0, 0.0, 0.0), (1.0e-8, 1.0e-8, 1.0e-8)),
        frames.SENSOR: Inertial(0.0150, (0.0, 0.0, 0.004), (1.2e-6, 1.2e-6, 1.7e-6)),
    },
)

# The compliant body's travel along its axis: no body compresses further, welded or not.
PRESS_TRAVEL_M = -OPEN_MANIPULATOR_X.joint('sensor_press').lower
