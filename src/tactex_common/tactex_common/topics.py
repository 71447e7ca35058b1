# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Topic and action names of the design contract, relative as nodes use them (one source)."""

# Tactile module (sensor node or simulator), REP-145 names.
IMU_RAW = 'tactile/imu/data_raw'  # sensor_msgs/Imu, no orientation
IMU_FILTERED = 'tactile/imu/data'  # sensor_msgs/Imu with the Madgwick orientation
MAG = 'tactile/imu/mag'  # sensor_msgs/MagneticField (T)
PRESSURE = 'tactile/pressure'  # sensor_msgs/FluidPressure (Pa)
TEMPERATURE = 'tactile/temperature'  # sensor_msgs/Temperature (degC)
# Arm (driver or simulator).
JOINT_STATES = 'joint_states'  # sensor_msgs/JointState
JOINT_TRAJECTORY = 'arm/joint_trajectory'  # trajectory_msgs/JointTrajectory (command)
# Probing, sweeping, recording, classification.
PROBE_CONTACTS = 'probe/contacts'  # geometry_msgs/PoseArray, z axis = outward normal
PROBE_PATHWAY = 'probe/pathway'  # tactex_msgs/Pathway, transient-local
PROBE_MARKERS = 'probe/markers'  # visualization_msgs/MarkerArray
SWEEP_ACTIVE = 'sweep/active'  # std_msgs/Bool: true while the edge slides in contact
SWEEP_MARKERS = 'sweep/markers'  # visualization_msgs/MarkerArray: the planned sweep
RECORDING_METADATA = 'recording/metadata'  # std_msgs/String, JSON: label, trial, surface, ...
TEXTURE_ESTIMATE = 'texture/estimate'  # tactex_msgs/TextureEstimate
TEXTURE_MARKERS = 'texture/markers'  # visualization_msgs/MarkerArray
# diagnostic_msgs/DiagnosticArray from every node, on the one absolute topic that
# diagnostic_aggregator and rqt_robot_monitor read, whatever a node's namespace.
DIAGNOSTICS = '/diagnostics'
# Actions.
PROBE_ACTION = 'probe'  # tactex_msgs/action/Probe
SWEEP_ACTION = 'sweep'  # tactex_msgs/action/Sweep
IDENTIFY_ACTION = 'identify'  # tactex_msgs/action/Identify
# Simulator ground truth.
GROUND_TRUTH_CONTACT = 'sim/ground_truth/contact'  # geometry_msgs/PoseStamped, z = normal
# PoseStamped: position of the sensor edge, attitude of sensor_link.
GROUND_TRUTH_SENSOR = 'sim/ground_truth/sensor_pose'
GROUND_TRUTH_TEXTURE = 'sim/ground_truth/texture'  # std_msgs/String


def diagnostic_name(node: str, task: str) -> str:
    """A DiagnosticStatus name, `/ns/node_name: task`.

    As diagnostic_updater forms it with its `use_fqn` (its default leaves the namespace
    out, which would let two namespaced systems take each other's place).
    """
    return f'{node}: {task}'
