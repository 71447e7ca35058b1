// Copyright 2026 The tactex authors
// SPDX-License-Identifier: Apache-2.0
// The LSM9DS0 ranges the firmware selects. Written by tools/write_firmware_ranges.py
// from tactex_common/chips.py, which the simulator and the Madgwick filter read too:
// change them there, not here.
#ifndef TACTEX_RANGES_H_
#define TACTEX_RANGES_H_

#include "tactex_sensors.h"

namespace tactex {
namespace ranges {

constexpr lsm9ds0::AccelRange kAccel = lsm9ds0::AccelRange::k4G;
constexpr lsm9ds0::GyroRange kGyro = lsm9ds0::GyroRange::k245Dps;
constexpr lsm9ds0::MagRange kMag = lsm9ds0::MagRange::k2Gauss;

}  // namespace ranges
}  // namespace tactex

#endif  // TACTEX_RANGES_H_
