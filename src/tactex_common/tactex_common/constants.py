# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Physical, hardware and numeric constants more than one package needs (SI units)."""

STANDARD_GRAVITY_M_S2 = 9.80665
# Earth's magnetic field in the ENU world frame (T): 20 uT north, 43 uT down (mid-latitude).
EARTH_FIELD_T = (0.0, 2.0e-5, -4.3e-5)
SEA_LEVEL_PRESSURE_PA = 101325.0
# The original work's sliding speed of the sensor edge along the surface (m/s).
SLIDING_SPEED_M_S = 0.015
# Dynamixel IDs of the OpenMANIPULATOR-X servos, joint1..joint4 then the gripper.
SERVO_IDS = (11, 12, 13, 14, 15)
# The largest random seed numpy, scikit-learn and torch all take.
MAX_SEED = 2**32 - 1
# The largest float32 (a protocol frame's and a dataset's number type), as a Python float.
FLOAT32_MAX = 3.4028234663852886e38
