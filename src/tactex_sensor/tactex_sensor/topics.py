# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Topic names of the tactile pipeline (design contract), relative as nodes use them."""

IMU_RAW = 'tactile/imu/data_raw'
IMU_FILTERED = 'tactile/imu/data'
MAG = 'tactile/imu/mag'
PRESSURE = 'tactile/pressure'
TEMPERATURE = 'tactile/temperature'
JOINT_STATES = 'joint_states'
JOINT_TRAJECTORY = 'arm/joint_trajectory'
SWEEP_ACTIVE = 'sweep/active'  # std_msgs/Bool: true while the edge slides in contact
RECORDING_METADATA = 'recording/metadata'  # std_msgs/String, JSON: label, trial, surface, ...
GROUND_TRUTH_CONTACT = 'sim/ground_truth/contact'  # geometry_msgs/PoseStamped, z = normal
# PoseStamped: position of the sensor edge, attitude of sensor_link.
GROUND_TRUTH_SENSOR = 'sim/ground_truth/sensor_pose'
GROUND_TRUTH_TEXTURE = 'sim/ground_truth/texture'  # std_msgs/String
