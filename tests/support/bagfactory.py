# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Write small rosbag2 recordings with chosen stamps and values, for the converter tests."""

import json
from pathlib import Path
import sqlite3

import numpy as np
from rosbags.rosbag2 import StoragePlugin, Writer

from tactex_common.interfaces import typestore

TS = typestore()  # ROS 2 Kilted's standard types and tactex_msgs
T = TS.types


def header(ns):
    sec, nanosec = divmod(int(ns), 10**9)
    return T['std_msgs/msg/Header'](stamp=T['builtin_interfaces/msg/Time'](
        sec=sec, nanosec=nanosec), frame_id='sensor_link')


def vector(x, y, z, types=None):
    """A geometry_msgs/Vector3 of the ROS 2 types, or of another typestore's `types`."""
    return (types or T)['geometry_msgs/msg/Vector3'](x=float(x), y=float(y), z=float(z))


def write_bag(path: Path, stamps_ns, values, *, mag_stamps_ns=None, pressure_stamps_ns=None,
              active=None, metadata=None, joint_speed=None, joint_positions=None,
              namespace='/', names=None,
              truth=None, estimates=None, storage=StoragePlugin.MCAP, live_order=False,
              unreadable_imu_from=None, log_ns=None):
    """Write a recording of `values` (n, 10), channel order, at header `stamps_ns`.

    Mag and pressure may use their own stamps (an empty list: no such topic); `active`
    lists (start_ns, end_ns) spans for sweep/active; `metadata` goes to
    recording/metadata as JSON. `joint_speed` (one value per sample) writes joint_states
    for joint1 alone; `joint_positions` ((n, 4) per sample) writes the four arm joints
    (with `joint_speed` as joint1's velocity, if given). Topics live under `namespace`
    ('/left_arm/', or '' for names without the leading slash), or take the names of
    `names` (role -> topic).
    `truth` (contact: bool per sample, edge_m: (n, 3), texture: name per sample) writes
    the simulator's ground-truth topics; `estimates` lists tactex_msgs/TextureEstimate
    messages for texture/estimate. IMU messages are logged one nanosecond apart after the
    first stamp (arrival order only), or with `live_order` at their stamps, interleaved with
    the other streams as a live recorder logs them. IMU messages from index
    `unreadable_imu_from` on are cut short: they cannot be decoded. `log_ns` (one per
    sample) logs each sample of every sensor stream at that time instead (streams sharing
    the IMU's stamps), as a recorder on a clock of its own does.
    """
    values = np.asarray(values, dtype=float)
    mag_stamps_ns = stamps_ns if mag_stamps_ns is None else mag_stamps_ns
    pressure_stamps_ns = stamps_ns if pressure_stamps_ns is None else pressure_stamps_ns
    names = names or {}
    writer = Writer(path, version=9, storage_plugin=storage)
    with writer:
        def connect(topic, kind, role=None):
            return writer.add_connection(names.get(role, namespace + topic), kind, typestore=TS)

        imu = connect('tactile/imu/data_raw', 'sensor_msgs/msg/Imu', 'imu')
        if len(mag_stamps_ns):
            mag = connect('tactile/imu/mag', 'sensor_msgs/msg/MagneticField', 'mag')
        pressure = connect('tactile/pressure', 'sensor_msgs/msg/FluidPressure', 'pressure')
        if truth is not None:
            write_truth(writer, connect, stamps_ns, truth)
        if metadata is not None:
            meta = connect('recording/metadata', 'std_msgs/msg/String')
            writer.write(meta, int(stamps_ns[0]), TS.serialize_cdr(
                T['std_msgs/msg/String'](data=json.dumps(metadata)), 'std_msgs/msg/String'))
        if active is not None:
            segment = connect('sweep/active', 'std_msgs/msg/Bool')
            for start, end in active:
                for stamp, state in ((start, True), (end, False)):
                    writer.write(segment, int(stamp), TS.serialize_cdr(
                        T['std_msgs/msg/Bool'](data=state), 'std_msgs/msg/Bool'))
        if joint_speed is not None or joint_positions is not None:
            joints = connect('joint_states', 'sensor_msgs/msg/JointState')
        if estimates is not None:
            estimate = connect('texture/estimate', 'tactex_msgs/msg/TextureEstimate')
            for message in estimates:
                writer.write(estimate, _ns(message.header.stamp), TS.serialize_cdr(
                    message, 'tactex_msgs/msg/TextureEstimate'))
        for i, stamp in enumerate(stamps_ns):
            row = values[i]
            message = T['sensor_msgs/msg/Imu'](
                header=header(stamp),
                orientation=T['geometry_msgs/msg/Quaternion'](x=0.0, y=0.0, z=0.0, w=1.0),
                orientation_covariance=np.array([-1.0] + [0.0] * 8),
                angular_velocity=vector(*row[3:6]), angular_velocity_covariance=np.zeros(9),
                linear_acceleration=vector(*row[0:3]),
                linear_acceleration_covariance=np.zeros(9))
            # Logged in arrival order; the header carries the sensor's own stamp.
            logged = int(stamp) if live_order else int(stamps_ns[0]) + i
            logged = logged if log_ns is None else int(log_ns[i])
            data = TS.serialize_cdr(message, 'sensor_msgs/msg/Imu')
            cut = unreadable_imu_from is not None and i >= unreadable_imu_from
            writer.write(imu, logged, data[:20] if cut else data)
            if joint_speed is not None or joint_positions is not None:
                arm = joint_positions is not None
                writer.write(joints, int(stamp), TS.serialize_cdr(T['sensor_msgs/msg/JointState'](
                    header=header(stamp),
                    name=['joint1', 'joint2', 'joint3', 'joint4'] if arm else ['joint1'],
                    position=np.asarray(joint_positions[i], float) if arm else np.zeros(1),
                    velocity=np.array([joint_speed[i]]) if joint_speed is not None
                    else np.zeros(0), effort=np.zeros(0)), 'sensor_msgs/msg/JointState'))

        def logged_at(stream_stamps, i, stamp):
            shared = log_ns is not None and stream_stamps is stamps_ns
            return int(log_ns[i]) if shared else int(stamp)

        for i, stamp in enumerate(mag_stamps_ns):
            writer.write(mag, logged_at(mag_stamps_ns, i, stamp), TS.serialize_cdr(
                T['sensor_msgs/msg/MagneticField'](
                header=header(stamp), magnetic_field=vector(*values[i, 6:9]),
                magnetic_field_covariance=np.zeros(9)), 'sensor_msgs/msg/MagneticField'))
        for i, stamp in enumerate(pressure_stamps_ns):
            writer.write(pressure, logged_at(pressure_stamps_ns, i, stamp), TS.serialize_cdr(
                T['sensor_msgs/msg/FluidPressure'](
                header=header(stamp), fluid_pressure=float(values[i, 9]), variance=0.0),
                'sensor_msgs/msg/FluidPressure'))
    return path


def strip_type_definitions(path: Path):
    """Remove the type definitions from a sqlite3 bag, as ROS 2 Humble writes it."""
    (database,) = path.glob('*.db3')
    with sqlite3.connect(database) as connection:
        connection.execute('DELETE FROM message_definitions')
    connection.close()
    return path


def _ns(stamp):
    return int(stamp.sec) * 10**9 + int(stamp.nanosec)


def write_truth(writer, connect, stamps_ns, truth):
    """The simulator's ground truth at each sample stamp."""
    contact = connect('sim/ground_truth/contact', 'geometry_msgs/msg/PoseStamped')
    edge = connect('sim/ground_truth/sensor_pose', 'geometry_msgs/msg/PoseStamped')
    texture = connect('sim/ground_truth/texture', 'std_msgs/msg/String')
    for i, stamp in enumerate(stamps_ns):
        x, y, z = (float(v) for v in truth['edge_m'][i])
        pose = T['geometry_msgs/msg/PoseStamped'](header=header(stamp), pose=T[
            'geometry_msgs/msg/Pose'](position=T['geometry_msgs/msg/Point'](x=x, y=y, z=z),
                                      orientation=T['geometry_msgs/msg/Quaternion'](
                                          x=0.0, y=0.0, z=0.0, w=1.0)))
        data = TS.serialize_cdr(pose, 'geometry_msgs/msg/PoseStamped')
        if truth['contact'][i]:
            writer.write(contact, int(stamp), data)
        writer.write(edge, int(stamp), data)
        writer.write(texture, int(stamp), TS.serialize_cdr(
            T['std_msgs/msg/String'](data=truth['texture'][i]), 'std_msgs/msg/String'))


def ramp(count, start_ns=10**12, period_ns=8_333_333):
    """Stamps and values where channel c of sample i is i + 1000 c (baro + 101 kPa).

    Every channel is distinct, so a swapped channel cannot round-trip, and every sample is
    easy to trace.
    """
    stamps = start_ns + np.arange(count, dtype=np.int64) * period_ns
    values = np.arange(count, dtype=float)[:, None] + 1000.0 * np.arange(10)
    values[:, 9] += 101_000.0
    return stamps, values
