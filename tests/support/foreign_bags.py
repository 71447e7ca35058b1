# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Recordings as others write them, and files that lie about being one: all generated here.

ROS 1 bags and zstd-compressed rosbag2 folders come from rosbags' own converter applied
to a `bagfactory` recording, so one recording exists in every format; the files that lie
(truncated, unindexed, empty, text, FIFO, huge record lengths, non-ROS MCAP) are cut from
or written beside them.
"""

import json
import os
from pathlib import Path
import shutil
import struct

import numpy as np
from rosbags.convert.converter import convert
from rosbags.rosbag1 import Writer as Ros1Writer
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.rosbag2.enums import CompressionFormat, CompressionMode
from rosbags.typesys import get_typestore, Stores

from support.bagfactory import TS, vector
from tactex_common.interfaces import typestore

ROS1 = get_typestore(Stores.ROS1_NOETIC)


def converted(source: Path, target: Path, *, compress: str | None = None,
              mode: str = 'file') -> Path:
    """A rosbag2 folder rewritten by rosbags' converter into `target`.

    A ROS 1 bag when `target` ends in .bag (compress: bz2 or lz4), else a rosbag2 MCAP
    folder (compress: zstd, in `mode` file or message).
    """
    ros1 = target.suffix == '.bag'
    target.parent.mkdir(parents=True, exist_ok=True)
    convert([source], target, dst_storage='mcap', dst_version=9, compress=compress,
            compress_mode=mode, default_typestore=typestore(),
            typestore=ROS1 if ros1 else None, exclude_topics=(), include_topics=(),
            exclude_msgtypes=(), include_msgtypes=())
    return target


def bare(source: Path, target: Path, suffix: str = '.mcap') -> Path:
    """The storage file of a rosbag2 folder, alone, without its metadata.yaml."""
    (storage,) = source.glob(f'*{suffix}')
    target.parent.mkdir(parents=True, exist_ok=True)
    shutil.copy(storage, target)
    return target


def truncated(source: Path, target: Path, fraction: float = 0.5) -> Path:
    """The first `fraction` of a file: a recording cut off in the middle (of a chunk)."""
    data = source.read_bytes()
    target.write_bytes(data[:int(len(data) * fraction)])
    return target


def imu_only(path: Path, header_ns, log_ns, *, topics=('/tactile/imu/data_raw',),
             ros1: bool = False, chunk_bytes: int | None = None) -> Path:
    """IMU messages with the given header stamps and log times on each of `topics`.

    Stamps of 0 are what a driver that never sets them publishes. A ROS 1 bag's chunks
    close after `chunk_bytes` (rosbags' default: 1 MiB).
    """
    store = ROS1 if ros1 else TS
    writer = Ros1Writer(path) if ros1 else Writer(path, version=9,
                                                  storage_plugin=StoragePlugin.MCAP)
    if chunk_bytes is not None:
        writer.chunk_threshold = chunk_bytes
    with writer:
        connections = [writer.add_connection(topic, 'sensor_msgs/msg/Imu', typestore=store)
                       for topic in topics]
        types = store.types
        for i, (stamp, logged) in enumerate(zip(header_ns, log_ns, strict=True)):
            sec, nanosec = divmod(int(stamp), 10**9)
            stamp_msg = types['builtin_interfaces/msg/Time'](sec=sec, nanosec=nanosec)
            head = (types['std_msgs/msg/Header'](seq=i, stamp=stamp_msg, frame_id='imu')
                    if ros1 else types['std_msgs/msg/Header'](stamp=stamp_msg, frame_id='imu'))
            message = types['sensor_msgs/msg/Imu'](
                header=head,
                orientation=types['geometry_msgs/msg/Quaternion'](x=0.0, y=0.0, z=0.0, w=1.0),
                orientation_covariance=np.zeros(9),
                angular_velocity=vector(0, 0, i, types), angular_velocity_covariance=np.zeros(9),
                linear_acceleration=vector(i, 0, 9.81, types),
                linear_acceleration_covariance=np.zeros(9))
            data = (store.serialize_ros1 if ros1 else store.serialize_cdr)(
                message, 'sensor_msgs/msg/Imu')
            for connection in connections:
                writer.write(connection, int(logged), data)
    return path


def zeros_bag(path: Path, size: int, compression: str, topic: str = '/bomb') -> Path:
    """One std_msgs/String of `size` zero bytes: a block that inflates far beyond its size.

    A ROS 1 bag with bz2 or lz4 chunks, or a rosbag2 folder of zstd messages ('zstd').
    """
    text = '\0' * size
    if compression == 'zstd':
        writer = Writer(path, version=9, storage_plugin=StoragePlugin.MCAP)
        writer.set_compression(CompressionMode.MESSAGE, CompressionFormat.ZSTD)
        store, serialize = TS, TS.serialize_cdr
    else:
        writer = Ros1Writer(path)
        writer.set_compression(Ros1Writer.CompressionFormat[compression.upper()])
        store, serialize = ROS1, ROS1.serialize_ros1
    with writer:
        connection = writer.add_connection(topic, 'std_msgs/msg/String', typestore=store)
        writer.write(connection, 1, serialize(store.types['std_msgs/msg/String'](data=text),
                                              'std_msgs/msg/String'))
    return path


def huge_record_bag(path: Path) -> Path:
    """A ROS 1 bag whose first record header claims 4 GB."""
    path.write_bytes(b'#ROSBAG V2.0\n' + struct.pack('<I', 0xFFFFFFF0) + bytes(64))
    return path


def non_ros_mcap(path: Path) -> Path:
    """An MCAP file as Foxglove writes it for JSON data: no ROS profile, json messages."""
    from mcap.writer import Writer as McapWriter
    with open(path, 'wb') as stream:
        writer = McapWriter(stream)
        writer.start(profile='', library='test')
        schema = writer.register_schema('Imu', 'jsonschema', json.dumps(
            {'type': 'object'}).encode())
        channel = writer.register_channel('/imu', 'json', schema)
        for i in range(10):
            writer.add_message(channel, log_time=i, publish_time=i,
                               data=json.dumps({'ax': i}).encode())
        writer.finish()
    return path


def custom_type_bag(path: Path) -> Path:
    """A ROS 1 bag whose only tactile topic has a message type of its own."""
    store = get_typestore(Stores.ROS1_NOETIC)
    from rosbags.typesys import get_types_from_msg
    store.register(get_types_from_msg('float64 ax\nfloat64 ay\nfloat64 az\nuint32 p',
                                      'lab_msgs/msg/Tactile'))
    with Ros1Writer(path) as writer:
        connection = writer.add_connection('/tactile/raw', 'lab_msgs/msg/Tactile',
                                           typestore=store)
        for i in range(20):
            writer.write(connection, 10**9 + i * 10**7, store.serialize_ros1(
                store.types['lab_msgs/msg/Tactile'](ax=1.0, ay=2.0, az=3.0, p=i),
                'lab_msgs/msg/Tactile'))
    return path


def lying_files(folder: Path, ros1_bag: Path) -> dict[str, Path]:
    """Files named like recordings that are not readable ones, by what is wrong."""
    folder.mkdir(parents=True, exist_ok=True)
    files = {
        'truncated': truncated(ros1_bag, folder / 'truncated.bag'),
        'active': truncated(ros1_bag, folder / 'unclosed.bag.active', 0.9),
        'empty': folder / 'empty.bag',
        'text': folder / 'text.bag',
        'fifo': folder / 'fifo.bag',
        'huge': huge_record_bag(folder / 'huge.bag'),
        'foxglove': non_ros_mcap(folder / 'foxglove.mcap'),
    }
    files['empty'].write_bytes(b'')
    files['text'].write_text('this is not a bag\n' * 20)
    os.mkfifo(files['fifo'])
    return files

