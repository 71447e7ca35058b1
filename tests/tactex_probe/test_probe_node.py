# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""probe_node: a goal in simulation yields the pathway; a servo dropping out aborts it.

With the simulator and Madgwick a Probe goal yields contacts, feedback and a pathway
(latched, and in its file); a servo that falls silent aborts the goal with the reason.
"""

import itertools
import math
from pathlib import Path
import re
import signal
import subprocess
import sys
import threading
import time

import pytest
from support.processes import stop, wait_for

pytest.importorskip('tactex_msgs', reason='tactex_msgs is not built in this environment')

pytestmark = [pytest.mark.integration, pytest.mark.ros]
BIN = Path(sys.executable).parent


def spin_in_background(context, nodes):
    from rclpy.executors import SingleThreadedExecutor
    executor = SingleThreadedExecutor(context=context)
    for node in nodes:
        executor.add_node(node)
    thread = threading.Thread(target=executor.spin, daemon=True)
    thread.start()
    return executor, thread


def goal(x, span, approach=0.02):
    from geometry_msgs.msg import Point, Vector3

    from tactex_msgs.action import Probe
    return Probe.Goal(start=Point(x=x, y=0.0, z=0.018), direction=Vector3(x=1.0), span=span,
                      step=0.01, approach_height=approach, descent_speed=0.005,
                      max_descent_depth=0.025, force_limit=3.0)


@pytest.mark.slow
def test_probe_goal_in_simulation_broadcasts_the_pathway(ros_context, tmp_path):
    from geometry_msgs.msg import PoseArray
    import rclpy
    from transforms3d.quaternions import quat2mat

    from tactex.launching.environment import ros_environment
    from tactex_common.goals import GoalSender
    from tactex_common.ros import LATCHED
    from tactex_msgs.action import Probe
    from tactex_msgs.msg import Pathway as PathwayMsg
    from tactex_probe.pathway import ContactStatus, Pathway
    from tactex_sim.scene import load_scene, resolve_scene

    # The three nodes run as processes of their own, as `tactex launch probe sim:=true`
    # would start them.
    env = ros_environment()
    sim_time = ['-p', 'use_sim_time:=true']
    logs = {name: open(tmp_path / f'{name}.log', 'w') for name in ('bridge', 'madgwick', 'probe')}
    nodes = [subprocess.Popen([BIN / 'mujoco_bridge', '--ros-args', '-p', 'scene:=probe',
                               '-p', 'rate_factor:=0.5'], env=env, stderr=logs['bridge']),
             subprocess.Popen([BIN / 'madgwick_node', '--ros-args', *sim_time], env=env,
                              stderr=logs['madgwick']),
             subprocess.Popen([BIN / 'probe_node', '--ros-args', *sim_time, '-p',
                               f'pathway_file:={tmp_path / "pathway.json"}'], env=env,
                              stderr=logs['probe'])]
    client_node = rclpy.create_node('probe_client', context=ros_context)
    poses, late = [], []
    client_node.create_subscription(PoseArray, 'probe/contacts', poses.append, LATCHED)
    sender = GoalSender(client_node, Probe, 'probe')
    executor, thread = spin_in_background(ros_context, [client_node])
    try:
        assert sender.client.wait_for_server(timeout_sec=30.0)
        feedback = []
        # The node refuses goals until the simulator listens for arm commands; a goal
        # sent before discovery settled may get no answer at all (sent again then).
        deadline = time.monotonic() + 30.0
        while True:
            handle = sender.answer(goal(0.185, 0.01), feedback.append, answer_s=5.0,
                                   timeout_s=30.0)
            assert handle is not None  # a hang guard on a loaded machine
            if handle.accepted or time.monotonic() > deadline:
                break
            time.sleep(1.0)
        assert handle.accepted
        result_future = handle.get_result_async()
        assert wait_for(result_future.done, 240), 'the probe goal did not finish'
        result = result_future.result().result
        saved = Pathway.load(tmp_path / 'pathway.json')
        assert result.message == '', (result.message, (tmp_path / 'bridge.log').read_text())
        assert list(result.outcomes) == [p.status for p in saved.probes]
        assert list(result.outcomes) == [ContactStatus.OK] * 2, [p.detail for p in saved.probes]
        # Sensible normals: the accuracy thresholds are the closed-loop library test's
        # (tests/tactex_probe); here they are only meant to be the surface's.
        surface = load_scene(resolve_scene('probe')).surface
        for contact in result.pathway.contacts:
            nx, nz = surface.normal(contact.position.x)
            error = math.degrees(math.acos(min(1.0, nx * contact.normal.x
                                               + nz * contact.normal.z)))
            assert error < 8.0, (contact, error)
            assert abs(contact.position.z - surface.height(contact.position.x)) < 0.002
        assert {f.feedback.phase for f in feedback} >= {0, 1, 2, 3}
        assert feedback[-1].feedback.contacts_found == 2
        # Within a long phase (a descent takes seconds) the latest feedback is sent again.
        changes = sum(a.feedback.phase != b.feedback.phase
                      for a, b in itertools.pairwise(feedback))
        assert len(feedback) > 2 * (changes + 1)
        assert wait_for(lambda: poses and len(poses[-1].poses) == 2, 5)
        orientation = poses[-1].poses[0].orientation
        z_axis = quat2mat([orientation.w, orientation.x, orientation.y, orientation.z])[:, 2]
        first = result.pathway.contacts[0].normal
        assert z_axis == pytest.approx([first.x, first.y, first.z], abs=1e-6)
        client_node.create_subscription(PathwayMsg, 'probe/pathway', late.append, LATCHED)
        assert wait_for(lambda: late, 10) and len(late[-1].contacts) == 2  # transient-local
        logs['probe'].flush()
        logged = (tmp_path / 'probe.log').read_text()
        assert 'probe 1/2: OK at (' in logged and 'probe 2/2: OK at (' in logged
        assert re.search(r'probe goal succeeded: 2 of 2 probes touched in [\d.]+ s; pathway '
                         r'in \S*pathway.json', logged), logged
    finally:
        executor.shutdown()
        client_node.destroy_node()
        stop(nodes, signal.SIGINT)
        for log in logs.values():
            log.close()


def test_servo_dropout_aborts_the_goal_with_the_reason(ros_context, tmp_path):
    import rclpy
    from rclpy.action import ActionClient
    from rclpy.parameter import Parameter
    from sensor_msgs.msg import FluidPressure, Imu, JointState
    from trajectory_msgs.msg import JointTrajectory

    from tactex_common.ros import COMMAND, SENSOR_DATA
    from tactex_msgs.action import Probe
    from tactex_msgs.msg import Pathway as PathwayMsg
    from tactex_probe.closed_loop import start_joints
    from tactex_probe.messages import parameters_from_goal
    from tactex_probe.probe_node import ProbeNode

    probe = ProbeNode(context=ros_context, parameter_overrides=[
        Parameter('pathway_file', value=str(tmp_path / 'pathway.json'))])
    robot = rclpy.create_node('fake_robot', context=ros_context)
    joints_pub = robot.create_publisher(JointState, 'joint_states', COMMAND)
    imu_pub = robot.create_publisher(Imu, 'tactile/imu/data', SENSOR_DATA)
    pressure_pub = robot.create_publisher(FluidPressure, 'tactile/pressure', SENSOR_DATA)
    goal_message = goal(0.18, 0.0)
    arm = list(start_joints(parameters_from_goal(goal_message))) + [0.0]
    servo_alive = threading.Event()
    servo_alive.set()

    def publish():
        stamp = robot.get_clock().now().to_msg()
        if servo_alive.is_set():
            state = JointState(name=['joint1', 'joint2', 'joint3', 'joint4', 'gripper'],
                               position=arm)
            state.header.stamp = stamp
            joints_pub.publish(state)
        imu = Imu()
        imu.header.stamp = stamp
        imu.linear_acceleration.z = -9.81  # the sensor faces down, as the joints say
        imu.orientation.x, imu.orientation.w = 1.0, 0.0
        imu_pub.publish(imu)
        pressure_pub.publish(FluidPressure(header=imu.header, fluid_pressure=101325.0))

    robot.create_timer(0.01, publish)
    robot.create_subscription(JointTrajectory, 'arm/joint_trajectory', lambda _: None, COMMAND)
    client = ActionClient(robot, Probe, 'probe')
    executor, thread = spin_in_background(ros_context, [probe, robot])
    try:
        assert client.wait_for_server(timeout_sec=10.0)
        assert wait_for(lambda: probe.inputs_heard and probe.arm_listening, 10)
        sent = client.send_goal_async(goal_message)
        assert wait_for(sent.done, 10) and sent.result().accepted
        time.sleep(1.0)
        servo_alive.clear()  # the servos fall silent mid-probe
        result_future = sent.result().get_result_async()
        assert wait_for(result_future.done, 20)
        response = result_future.result()
        assert response.status == 6  # GoalStatus.STATUS_ABORTED
        assert 'no joint state' in response.result.message
        assert isinstance(response.result.pathway, PathwayMsg)
    finally:
        executor.shutdown()
        probe.destroy_node()
        robot.destroy_node()


def test_a_goal_of_bad_values_is_aborted_with_the_reason_a_client_can_read(ros_context,
                                                                           tmp_path):
    import rclpy
    from rclpy.parameter import Parameter
    from trajectory_msgs.msg import JointTrajectory

    from tactex_common.goals import GoalSender
    from tactex_msgs.action import Probe
    from tactex_probe.probe_node import ProbeNode

    node = ProbeNode(context=ros_context, parameter_overrides=[
        Parameter('pathway_file', value=str(tmp_path / 'pathway.json'))])
    arm = rclpy.create_node('arm_stand_in', context=ros_context)  # listens for commands
    arm.create_subscription(JointTrajectory, 'arm/joint_trajectory', lambda m: None, 10)
    client = rclpy.create_node('probe_client', context=ros_context)
    sender = GoalSender(client, Probe, 'probe')
    executor, thread = spin_in_background(ros_context, [node, arm, client])
    try:
        assert sender.client.wait_for_server(timeout_sec=30.0)
        assert wait_for(lambda: node.arm_listening, 30)
        bad = goal(0.185, 0.01)
        bad.step = 0.0
        handle = sender.answer(bad, answer_s=10.0, timeout_s=30.0)
        assert handle is not None and handle.accepted  # a refusal would carry no reason
        result = handle.get_result_async()
        assert wait_for(result.done, 30)
        assert result.result().status == 6  # ABORTED
        assert result.result().result.message.startswith('not probed: step must be in')
        again = sender.answer(goal(0.185, 0.01), answer_s=10.0, timeout_s=30.0)
        assert again.accepted  # the aborted goal left the node free
        again.cancel_goal_async()
    finally:
        executor.shutdown()
        for each in (node, arm, client):
            each.destroy_node()
