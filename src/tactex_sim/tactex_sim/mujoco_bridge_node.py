# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""ROS 2 node standing in for the arm driver and the tactile sensor with a MuJoCo scene.

Same topics and commands as the hardware: joint_states, the raw tactile topics,
arm/joint_trajectory (validated and played exactly as the driver does), arm/stop and
arm/torque; plus /clock (simulated time: run other nodes with use_sim_time) and the
ground truth on sim/ground_truth/*, and diagnostics (the scene, how far it lags, a fault
playing). `patch_texture` may be set while running (one texture
per sweep without a restart), and `fault` plays a fault (`tactex_sim.faults`) until
cleared. `rate_factor` 1 runs in real time, 5 five times faster, 0 as fast as the machine
allows.
"""

from __future__ import annotations

import math
import time

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import PoseStamped
import numpy as np
from rcl_interfaces.msg import (
    FloatingPointRange,
    IntegerRange,
    ParameterDescriptor,
    SetParametersResult,
)
import rclpy
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import FluidPressure, Imu, JointState, MagneticField, Temperature
from std_msgs.msg import String
from std_srvs.srv import SetBool, Trigger
from trajectory_msgs.msg import JointTrajectory

from tactex_common import topics
from tactex_common.ros import COMMAND, SENSOR_DATA, spin, TactexNode
from tactex_driver.arm import ArmController
from tactex_driver.playback import JointLimits
from tactex_sensor.messages import TACTILE_TOPICS
from tactex_sim.errors import SimError
from tactex_sim.faults import FaultPlayer, FAULTS
from tactex_sim.recording import sample_messages, SAMPLE_TOPICS, tactile_messages
from tactex_sim.scene import load_scene, resolve_scene
from tactex_sim.textures import texture as find_texture
from tactex_sim.world import MAX_RATE_FACTOR, Sample, World

# The rclpy classes of the types the simulator emits.
MESSAGE_CLASSES = {'sensor_msgs/msg/Imu': Imu, 'sensor_msgs/msg/MagneticField': MagneticField,
                   'sensor_msgs/msg/FluidPressure': FluidPressure,
                   'sensor_msgs/msg/Temperature': Temperature,
                   'sensor_msgs/msg/JointState': JointState,
                   'geometry_msgs/msg/PoseStamped': PoseStamped, 'std_msgs/msg/String': String}
# Simulated time further behind its rate factor's target than this is reported (WARN).
LAG_WARN_S = 1.0


def _reason(error: SimError) -> str:
    """The message of `error` (str() of an UnknownNameError, a KeyError, adds quotes)."""
    return ' '.join(map(str, error.args))


class MujocoBridgeNode(TactexNode):
    """Steps a scene and serves it as if it were the robot."""

    def __init__(self, **kwargs) -> None:
        super().__init__('mujoco_bridge', **kwargs)
        describe = ParameterDescriptor
        scene_name = self.declare_parameter('scene', 'probe', describe(
            description='scene name under config/scenes/ or a .toml path',
            read_only=True)).value
        seed = self.declare_parameter('seed', -1, describe(
            description="random seed (-1: the scene's)", read_only=True,
            integer_range=[IntegerRange(from_value=-1, to_value=2**63 - 1, step=1)])).value
        self._rate_factor = self.declare_parameter('rate_factor', 1.0, describe(
            description='simulated seconds per wall second (0: as fast as possible)',
            read_only=True, floating_point_range=[FloatingPointRange(
                from_value=0.0, to_value=MAX_RATE_FACTOR)])).value
        start = self.declare_parameter('initial_joints', [0.0, -0.3, 0.3, 1.2, 0.0], describe(
            description='joint1..joint4 (rad) and gripper (m) at start, within the '
                        'joint limits', read_only=True)).value
        texture = self.declare_parameter('patch_texture', '', describe(
            description='texture of every patch ("" keeps the scene\'s); settable while '
                        'running (the next sample feels it)')).value
        fault = self.declare_parameter('fault', '', describe(
            description=f'fault played until set back to "": one of {", ".join(FAULTS[1:])} '
                        '(soak tests; settable while running)')).value
        self._faults = FaultPlayer()
        try:
            self._faults.play(fault)
        except ValueError:
            raise self.refused_parameter('fault', f'one of {", ".join(map(repr, FAULTS))}'
                                         ) from None
        try:
            scene = load_scene(resolve_scene(scene_name))
        except SimError as err:
            raise self.refused_parameter('scene', f'a scene under config/scenes/ or a .toml '
                                                  f'path ({_reason(err)})') from None
        if texture:
            try:
                find_texture(texture)
            except SimError as err:
                raise self.refused_parameter('patch_texture',
                                             f"'' or a texture ({_reason(err)})") from None
        limits = JointLimits.of_robot()
        if len(start) != len(limits.names) or not np.all(
                (np.asarray(start) >= limits.lower) & (np.asarray(start) <= limits.upper)):
            raise self.refused_parameter('initial_joints', ', '.join(
                f'{name} from {low:g} to {high:g}'
                for name, low, high in zip(limits.names, limits.lower, limits.upper,
                                           strict=True)))
        self._world = World(scene, seed=None if seed < 0 else seed,
                            patch_texture=texture or None)
        self._controller = ArmController(limits)
        self._world.place_arm(np.asarray(start, dtype=float))
        self._controller.update_measured(self._world.joint_positions())
        self._controller.torque_on(0.0)
        self._world.controller = self._goal
        self.add_on_set_parameters_callback(self._on_set_parameters)

        self._clock_pub = self.create_publisher(Clock, '/clock', 10)
        sensor_topics = {topic for topic, _ in TACTILE_TOPICS}
        self._publishers_by_topic = {
            topic: self.create_publisher(
                MESSAGE_CLASSES[msgtype], topic,
                SENSOR_DATA if topic in sensor_topics else COMMAND)
            for topic, msgtype in SAMPLE_TOPICS}
        self.create_subscription(JointTrajectory, topics.JOINT_TRAJECTORY, self._on_trajectory,
                                 10)
        self.create_service(Trigger, 'arm/stop', self._on_stop)
        self.create_service(SetBool, 'arm/torque', self._on_torque)
        self._diagnostics_pub = self.create_publisher(DiagnosticArray, topics.DIAGNOSTICS,
                                                      COMMAND)
        self._scene_name, self._samples = scene.name, 0
        self._wall_start = time.monotonic()
        # Twice the sample rate, one sample a tick: a simulator that fell behind catches up
        # at up to twice the rate, and an arm command waits at most one sample.
        period = self._world.period_s / self._rate_factor if self._rate_factor else 0.0
        self.create_timer(period / 2, self._tick)
        self.create_timer(1.0, self._publish_diagnostics)
        self.get_logger().info(f'scene {scene.name!r}, effects {list(scene.effects)}, '
                               f'{scene.sensor_rate_hz:g} Hz, rate factor {self._rate_factor}')

    def _on_set_parameters(self, parameters) -> SetParametersResult:
        for parameter in parameters:
            if parameter.name == 'patch_texture':
                try:
                    self._world.set_patch_texture(parameter.value or None)
                except SimError as err:
                    return SetParametersResult(successful=False, reason=_reason(err))
                self.get_logger().info(f'patch texture {parameter.value or "of the scene"!r}')
            elif parameter.name == 'fault':
                try:
                    self._faults.play(parameter.value)
                except ValueError as err:
                    return SetParametersResult(successful=False, reason=str(err))
                self.get_logger().warning(f'fault {parameter.value!r}' if parameter.value
                                          else 'fault cleared')
        return SetParametersResult(successful=True)

    def _goal(self, sim_time_s: float) -> np.ndarray:
        goal = self._controller.goal(sim_time_s)
        return self._world.joint_positions() if goal is None else goal

    def _tick(self) -> None:
        """Take the next sample when it is due (one a tick, so commands apply in between).

        A burst of samples in one callback would run the arm on its old trajectory through
        all of them while a newer command waits: 50 samples were 0.42 s of simulated time,
        which put the probe node's model of the commanded arm out by as much.
        """
        if self._rate_factor:
            target = (time.monotonic() - self._wall_start) * self._rate_factor
        else:
            target = math.inf
        if self._world.time_s + self._world.period_s <= target:
            sample = self._world.next_sample()
            self._controller.update_measured(self._world.joint_positions())
            self._publish(sample)

    def _publish_diagnostics(self) -> None:
        """The scene, how far simulated time lags its target, and the fault playing (WARN)."""
        lag_s = ((time.monotonic() - self._wall_start) * self._rate_factor - self._world.time_s
                 if self._rate_factor else 0.0)
        behind = lag_s > LAG_WARN_S
        fault = self._faults.fault
        level = DiagnosticStatus.WARN if fault or behind else DiagnosticStatus.OK
        message = (f'fault {fault!r} playing' if fault else
                   f'{lag_s:.1f} s behind its rate factor' if behind else 'simulating')
        self.publish_diagnostics(self._diagnostics_pub, level, 'sim', message, {
            'scene': self._scene_name, 'sim_time_s': f'{self._world.time_s:.3f}',
            'rate_factor': self._rate_factor, 'lag_s': f'{lag_s:.3f}',
            'samples': self._samples, 'fault': fault or 'none',
            'patch_texture': self.get_parameter('patch_texture').value or 'of the scene'},
            hardware_id=f'mujoco:{self._scene_name}')

    def _publish(self, sample: Sample) -> None:
        self._samples += 1
        time_ns = int(round(sample.time_s * 1e9))
        self._clock_pub.publish(Clock(clock=rclpy.time.Time(nanoseconds=time_ns).to_msg()))
        muted = self._faults.muted
        emitted = [message for played, stamp in self._faults.tactile(sample, time_ns)
                   for message in tactile_messages(played, stamp)]
        emitted += sample_messages(sample, time_ns, self._world.joint_positions(),
                                   self._world.joint_velocities(), tactile=False)
        for topic, data in emitted:
            if topic not in muted:
                self._publishers_by_topic[topic].publish(data)

    def _on_trajectory(self, msg: JointTrajectory) -> None:
        ok, report = self._controller.execute_message(msg, self._world.time_s)
        if ok:
            self.get_logger().info(report)
        else:
            self.get_logger().error(report)

    def _on_stop(self, request, response):
        self._controller.stop(self._world.time_s)
        response.success, response.message = True, 'holding'
        return response

    def _on_torque(self, request, response):
        if request.data:
            self._controller.torque_on(self._world.time_s)
        else:
            self._controller.torque_off()
        response.success = True
        response.message = f'torque {"on" if request.data else "off"}'
        return response


def main(args: list[str] | None = None) -> None:
    """Run the bridge until shutdown."""
    spin(MujocoBridgeNode, args)
