# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The Foxglove live view: what it shows, what it serves, and a WebSocket client's view of it.

The arm's transforms compose to the robot description's forward kinematics; the pathway
is a sphere per contact with an arrow along its normal; only the packages' own files are
served; the layout names only channels the view has. A WebSocket client connected to a
running view_node sees every channel with its schema and decodes the messages published
on the ROS side.
"""

import asyncio
import base64
import json
import math
from pathlib import Path
import re
import socket
import subprocess
import sys
import time

import numpy as np
import pytest
from support.foxglove_client import subscribe_all
from support.processes import stop, wait_for
from transforms3d.quaternions import quat2mat

from tactex.view.channels import (
    asset,
    channel_name,
    frame_transforms,
    JSON_CHANNELS,
    layout_path,
    PATHWAY_CHANNEL,
    pathway_scene,
    TF_CHANNEL,
)
from tactex_description.geometry import OPEN_MANIPULATOR_X
from tactex_description.kinematics import forward_kinematics

BIN = Path(sys.executable).parent
ARM = {'joint1': 0.3, 'joint2': -0.4, 'joint3': 0.5, 'joint4': 0.2}
CHANNELS = {TF_CHANNEL, PATHWAY_CHANNEL, *map(channel_name, JSON_CHANNELS)}


def protobuf_class(name: str, descriptors: bytes):
    """The message class `name` of a serialised FileDescriptorSet (as Foxglove schemas are)."""
    from google.protobuf import descriptor_pb2, descriptor_pool, message_factory
    pool = descriptor_pool.DescriptorPool()
    for file in descriptor_pb2.FileDescriptorSet.FromString(descriptors).file:
        pool.Add(file)
    return message_factory.GetMessageClass(pool.FindMessageTypeByName(name))


def decoded(message):
    """A Foxglove message as the protobuf a client decodes from the wire."""
    schema = message.get_schema()
    return protobuf_class(schema.name, schema.data).FromString(message.encode())


def matrix(transform) -> np.ndarray:
    out = np.eye(4)
    r, t = transform.rotation, transform.translation
    out[:3, :3] = quat2mat([r.w, r.x, r.y, r.z])
    out[:3, 3] = [t.x, t.y, t.z]
    return out


def test_the_arm_transforms_compose_to_the_forward_kinematics():
    by_child = {t.child_frame_id: t for t in decoded(frame_transforms(ARM, 5)).transforms}
    frame, pose = 'sensor_edge', np.eye(4)
    while frame in by_child:
        pose = matrix(by_child[frame]) @ pose
        frame = by_child[frame].parent_frame_id
    assert frame == 'world'
    np.testing.assert_allclose(pose, forward_kinematics(ARM, 'sensor_edge'), atol=1e-9)
    assert by_child['link2'].timestamp.nanos == 5


def test_the_pathway_is_a_sphere_per_contact_and_an_arrow_along_each_normal():
    points = [[0.10, 0.0, 0.010], [0.11, 0.0, 0.012]]
    normals = [[0.0, 0.0, 1.0], [-0.6, 0.0, 0.8]]
    update = decoded(pathway_scene(points, normals, 'base_link', 7))
    [entity] = update.entities
    assert entity.frame_id == 'base_link' and update.deletions[0].id == entity.id
    assert [s.pose.position.x for s in entity.spheres] == [0.10, 0.11]
    for arrow, normal in zip(entity.arrows, normals, strict=True):
        q = arrow.pose.orientation
        np.testing.assert_allclose(quat2mat([q.w, q.x, q.y, q.z])[:, 0], normal, atol=1e-12)


def test_forwarding_keeps_one_message_a_period_and_starts_anew_when_stamps_go_back():
    from types import SimpleNamespace

    from builtin_interfaces.msg import Time

    from tactex.view.server import ViewNode
    view = SimpleNamespace(_sample_period_ns=10, _last_sample_ns={})

    def due(stamp, period=None):
        return ViewNode._due(view, 'joint_states', SimpleNamespace(stamp=Time(
            sec=0, nanosec=stamp)), period)
    # The arm's transforms at their own period; a simulator restart or a looped bag sends
    # stamps back, which are forwarded at once (they waited for the old high mark).
    assert [due(s, 100) for s in (1000, 1050, 1100, 0, 50, 100)] == [
        True, False, True, True, False, True]
    assert [due(s) for s in (200, 205, 210)] == [True, False, True]


def test_only_the_packages_own_files_are_served():
    urdf = asset('package://tactex_description/urdf/open_manipulator_x_tactile.urdf')
    assert urdf.startswith(b'<?xml') and b'sensor_edge' in urdf
    for uri in ('package://tactex_description/../../../etc/passwd', 'file:///etc/passwd',
                'package://rclpy/__init__.py', 'package://tactex/', 'https://example.com/x',
                'package://tactex_description/urdf/missing.urdf'):
        assert asset(uri) is None, uri


def test_the_layout_shows_only_channels_the_view_has_and_a_urdf_it_serves():
    text = layout_path().read_text()
    layout = json.loads(text)
    named = {re.match(r'(/[a-z_/]+?)(\.|$)', path).group(1)
             for path in re.findall(r'"(/[a-z_/]+[^"]*)"', text)}
    assert named and named <= CHANNELS, named - CHANNELS
    urdf = layout['configById']['3D!arm']['layers']['urdf']['url']
    assert asset(urdf) is not None
    panels = set(layout['configById'])
    assert set(re.findall(r'"([A-Za-z0-9]+![a-z]+)"', json.dumps(layout['layout']))) == panels


# -- a WebSocket client of a running view_node --------------------------------------------
def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(('127.0.0.1', 0))
        return probe.getsockname()[1]


def decoder(channel: dict):
    """A function from a message's bytes to something indexable, per the channel's schema."""
    if channel['encoding'] == 'json':
        return json.loads
    return protobuf_class(channel['schemaName'], base64.b64decode(channel['schema'])).FromString


@pytest.mark.integration
@pytest.mark.ros
def test_a_websocket_client_sees_every_channel_with_its_schema_and_the_messages(
        ros_context, tmp_path):
    from geometry_msgs.msg import Point, Vector3
    from sensor_msgs.msg import FluidPressure, Imu, JointState
    from std_msgs.msg import Bool

    from tactex.launching.environment import ros_environment
    from tactex_common.ros import COMMAND, LATCHED
    from tactex_msgs.msg import Contact, Pathway, TextureEstimate
    port = free_port()
    log = tmp_path / 'view.log'
    with open(log, 'w') as out:
        view = subprocess.Popen([BIN / 'tactex', 'view', '--namespace', 'left', '--port',
                                 str(port)], stdout=out, stderr=subprocess.STDOUT,
                                env=ros_environment())
    import rclpy
    node = rclpy.create_node('view_source', namespace='/left', context=ros_context)
    raw = node.create_publisher(Imu, 'tactile/imu/data_raw', COMMAND)
    pressure = node.create_publisher(FluidPressure, 'tactile/pressure', COMMAND)
    joints = node.create_publisher(JointState, 'joint_states', COMMAND)
    pathway = node.create_publisher(Pathway, 'probe/pathway', LATCHED)
    estimate = node.create_publisher(TextureEstimate, 'texture/estimate', COMMAND)
    active = node.create_publisher(Bool, 'sweep/active', COMMAND)  # sweep_node's QoS

    def publish():
        stamp = node.get_clock().now().to_msg()
        sample = Imu()
        sample.header.stamp = stamp
        sample.linear_acceleration = Vector3(x=0.1, y=0.2, z=9.8)
        sample.angular_velocity = Vector3(x=math.nan, y=0.0, z=0.5)
        for _ in range(3):
            sample.header.stamp = node.get_clock().now().to_msg()
            raw.publish(sample)
            pressure.publish(FluidPressure(header=sample.header, fluid_pressure=101325.0))
            joints.publish(JointState(header=sample.header, name=list(ARM),
                                      position=list(ARM.values())))
            estimate.publish(TextureEstimate(header=sample.header, label='wood', class_id=1,
                                             confidence=0.75, class_names=['cork', 'wood'],
                                             probabilities=[0.25, 0.75], decided=True))
            time.sleep(0.1)
        for _ in range(5):  # 1 ms apart: above max_rate_hz (60), none of these is forwarded
            sample.header.stamp.nanosec = (sample.header.stamp.nanosec + 1_000_000) % 10**9
            raw.publish(sample)
        pathway.publish(Pathway(contacts=[Contact(position=Point(x=0.1, z=0.01),
                                                  normal=Vector3(z=1.0))]))
        active.publish(Bool(data=True))

    try:
        assert wait_for(lambda: f'ws://127.0.0.1:{port}' in log.read_text(), 30), \
            log.read_text()
        # Discovery of the ROS side: the view subscribes to each topic (a fixed wait lost
        # the samples on a loaded machine).
        assert wait_for(lambda: all(publisher.get_subscription_count() for publisher in
                                    (raw, pressure, joints, estimate, active)), 30)
        channels, payloads = asyncio.run(subscribe_all(
            port, 4.0, channels_expected=len(CHANNELS), ready=publish))
    finally:
        node.destroy_node()
        stop([view])
    received: dict[str, list] = {}
    for channel, payload in payloads:
        received.setdefault(channel['topic'], []).append(decoder(channel)(payload))
    assert set(channels) == CHANNELS
    assert channels[TF_CHANNEL]['schemaName'] == 'foxglove.FrameTransforms'
    assert channels[PATHWAY_CHANNEL]['schemaName'] == 'foxglove.SceneUpdate'
    assert channels['/tactile/imu/data_raw']['schemaName'] == 'tactex.ImuSample'
    assert channels['/tactile/imu/data_raw']['schemaEncoding'] == 'jsonschema'
    assert len(received['/tactile/imu/data_raw']) == 3
    imu = received['/tactile/imu/data_raw'][0]
    assert imu['linear_acceleration'] == pytest.approx({'x': 0.1, 'y': 0.2, 'z': 9.8})
    assert imu['angular_velocity']['x'] is None  # NaN travels as null: valid JSON
    assert received['/tactile/pressure'][0] == {'fluid_pressure': 101325.0}
    assert received['/sweep/active'] == [{'active': True}]
    assert received['/texture/estimate'][0]['probabilities'] == {'cork': 0.25, 'wood': 0.75}
    transforms = {t.child_frame_id: t for t in received[TF_CHANNEL][0].transforms}
    q = transforms[OPEN_MANIPULATOR_X.joint('joint1').child].rotation  # about z
    assert 2 * math.atan2(q.z, q.w) == pytest.approx(ARM['joint1'])
    [entity] = received[PATHWAY_CHANNEL][-1].entities
    assert len(entity.spheres) == 1 and entity.frame_id == 'base_link'
