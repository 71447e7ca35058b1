# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The channel order of this system's recordings and datasets (the one source).

Accelerometer (m/s^2), gyroscope (rad/s), magnetometer (T) in `sensor_link`, then the
barometer (Pa). Datasets name their channels in the sidecar; this order is the default
for the system's own recordings.
"""

ACCEL = ('ax', 'ay', 'az')
GYRO = ('gx', 'gy', 'gz')
MAG = ('mx', 'my', 'mz')
BARO = ('baro',)
CHANNELS = ACCEL + GYRO + MAG + BARO
