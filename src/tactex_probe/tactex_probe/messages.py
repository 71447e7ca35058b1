# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Probe messages <-> the core: goals, contacts, pathways, feedback, trajectories, markers.

Used by probe_node and by the client commands (`tactex probe`, `tactex sweep --pathway`).
"""

from __future__ import annotations

from builtin_interfaces.msg import Duration
from geometry_msgs.msg import Point, Pose, Quaternion, Vector3
import numpy as np
from rclpy.time import Time
from std_msgs.msg import ColorRGBA, Header
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint
from visualization_msgs.msg import Marker, MarkerArray

from tactex_description.geometry import ARM_JOINT_NAMES
from tactex_msgs.action import Probe
from tactex_msgs.msg import Contact
from tactex_msgs.msg import Pathway as PathwayMsg
from tactex_probe.explorer_interface import Feedback
from tactex_probe.normals import quaternion_z_to
from tactex_probe.pathway import FRAME_ID, PARAMETER_RANGES, Pathway, ProbeParameters


def parameters_from_goal(goal) -> ProbeParameters:
    """The core's parameters of a Probe goal.

    Raises:
        ParameterError: a value out of range, or a direction that is not a unit vector.
    """
    return ProbeParameters(
        start=(goal.start.x, goal.start.y, goal.start.z),
        direction=(goal.direction.x, goal.direction.y, goal.direction.z),
        span=goal.span, step=goal.step, approach_height=goal.approach_height,
        descent_speed=goal.descent_speed, max_descent_depth=goal.max_descent_depth,
        force_limit=goal.force_limit)


def goal_message(parameters: ProbeParameters) -> Probe.Goal:
    """A Probe goal of the core's parameters."""
    x, y, z = parameters.start
    dx, dy, dz = parameters.direction
    return Probe.Goal(start=Point(x=x, y=y, z=z), direction=Vector3(x=dx, y=dy, z=dz),
                      **{name: getattr(parameters, name) for name in PARAMETER_RANGES})


def contact_arrays(pathway) -> tuple[np.ndarray, np.ndarray]:
    """(N x 3 positions, N x 3 normals) of a tactex_msgs/Pathway's contacts (N may be 0)."""
    contacts = pathway.contacts
    positions = np.array([[c.position.x, c.position.y, c.position.z] for c in contacts],
                         dtype=float).reshape(-1, 3)
    normals = np.array([[c.normal.x, c.normal.y, c.normal.z] for c in contacts],
                       dtype=float).reshape(-1, 3)
    return positions, normals


def contact_message(record) -> Contact:
    """A tactex_msgs/Contact of a probe record."""
    header = Header(frame_id=FRAME_ID, stamp=Time(nanoseconds=record.stamp_ns).to_msg())
    x, y, z = record.position
    nx, ny, nz = record.normal
    return Contact(header=header, position=Point(x=x, y=y, z=z),
                   normal=Vector3(x=nx, y=ny, z=nz), force_proxy=record.force_proxy,
                   confidence=record.confidence, status=int(record.status))


def pathway_message(pathway: Pathway) -> PathwayMsg:
    """A tactex_msgs/Pathway: the successful contacts and the parameters."""
    goal = goal_message(pathway.parameters)
    return PathwayMsg(
        header=Header(frame_id=pathway.frame_id,
                      stamp=Time(nanoseconds=pathway.stamp_ns).to_msg()),
        contacts=[contact_message(p) for p in pathway.contacts], start=goal.start,
        direction=goal.direction,
        **{name: getattr(pathway.parameters, name) for name in PARAMETER_RANGES})


def feedback_message(feedback: Feedback) -> Probe.Feedback:
    """Probe feedback of the core's."""
    message = Probe.Feedback(phase=int(feedback.phase), probe_index=feedback.probe_index,
                             probe_count=feedback.probe_count,
                             contacts_found=feedback.contacts_found)
    if feedback.last_record is not None:
        message.last_contact = contact_message(feedback.last_record)
    return message


def stop_message() -> JointTrajectory:
    """The arm trajectory without points: the driver stops where it commands the arm now."""
    return JointTrajectory(joint_names=list(ARM_JOINT_NAMES))


def trajectory_message(path) -> JointTrajectory:
    """The arm trajectory of a joint path (times from now; the driver prepends its goal)."""
    return JointTrajectory(joint_names=list(ARM_JOINT_NAMES), points=[
        JointTrajectoryPoint(positions=[float(q) for q in joints],
                             time_from_start=duration_message(int(round(t * 1e9))))
        for t, joints in zip(path.times_s, path.joints, strict=True)])


def marker_message(pathway: Pathway, header: Header) -> MarkerArray:
    """RViz markers of a pathway: points and normals.

    Spheres at the points (green when measured, red when the probe failed), arrows of the
    normals; the first marker clears the previous set.
    """
    markers = [Marker(header=header, ns='probe', action=Marker.DELETEALL)]
    for record in pathway.probes:
        x, y, z = record.position
        colour = ColorRGBA(r=0.1, g=0.8, b=0.2, a=1.0) if record.ok else \
            ColorRGBA(r=0.9, g=0.1, b=0.1, a=1.0)
        markers.append(Marker(header=header, ns='probe/points', id=record.index,
                              type=Marker.SPHERE, action=Marker.ADD,
                              pose=Pose(position=Point(x=x, y=y, z=z),
                                        orientation=Quaternion(w=1.0)),
                              scale=Vector3(x=0.003, y=0.003, z=0.003), color=colour))
        if record.ok:
            tip = [p + 0.02 * n for p, n in zip(record.position, record.normal, strict=True)]
            markers.append(Marker(header=header, ns='probe/normals', id=record.index,
                                  type=Marker.ARROW, action=Marker.ADD,
                                  points=[Point(x=x, y=y, z=z), Point(x=tip[0], y=tip[1],
                                                                      z=tip[2])],
                                  scale=Vector3(x=0.001, y=0.002, z=0.003),
                                  color=ColorRGBA(r=0.1, g=0.3, b=0.9, a=1.0)))
    return MarkerArray(markers=markers)


def orientation_message(normal) -> Quaternion:
    """The orientation whose z axis is `normal` (a contact pose's)."""
    w, x, y, z = quaternion_z_to(normal)
    return Quaternion(w=float(w), x=float(x), y=float(y), z=float(z))


def duration_message(nanoseconds: int) -> Duration:
    """A Duration of nanoseconds (negative: zero)."""
    seconds, rest = divmod(max(int(nanoseconds), 0), 1_000_000_000)
    return Duration(sec=seconds, nanosec=rest)
