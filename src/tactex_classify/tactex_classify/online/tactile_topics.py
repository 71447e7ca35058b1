# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The tactile topics a live node subscribes to, by stream role, and their queue."""

from rclpy.qos import QoSProfile
from sensor_msgs.msg import FluidPressure, Imu, MagneticField

from tactex_common import topics
from tactex_common.ros import SENSOR_DATA

ROLE_TOPICS = {'imu': (Imu, topics.IMU_RAW), 'mag': (MagneticField, topics.MAG),
               'pressure': (FluidPressure, topics.PRESSURE)}
# Sensor-data QoS (best effort, volatile) with a deep queue: a busy executor catches up
# on up to 0.7 s of a 350 Hz stream instead of losing samples (each loss is a gap).
SENSOR_QUEUE = QoSProfile(depth=256, reliability=SENSOR_DATA.reliability,
                          durability=SENSOR_DATA.durability, history=SENSOR_DATA.history)
