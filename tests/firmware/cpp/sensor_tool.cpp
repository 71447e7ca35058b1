// Copyright 2026 The tactex authors
// SPDX-License-Identifier: Apache-2.0
// Host program around the firmware's sensor maths, for tests/firmware/test_sensors.py.
//
// Reads one request per line and answers with one line; floats in C99 hex (%a), exact:
//   accel|gyro|mag RANGE X Y Z  -> the SI values of int16 counts at range code RANGE
//   setup ACCEL GYRO MAG        -> the register writes (REG=VALUE, hex) of both dies
//   mpl115a2 B0 .. B11          -> a0 b1 b2 c12 Padc Tadc Pa degC of registers 0x00..0x0B
//   missing                     -> the bit pattern of a missing channel
#include <cinttypes>
#include <cstdio>
#include <cstring>

#include "tactex_sensors.h"

namespace {

namespace lsm = tactex::lsm9ds0;
namespace mpl = tactex::mpl115a2;

void xyz(const char* kind, unsigned range, int x, int y, int z) {
  const int counts[3] = {x, y, z};
  uint8_t raw[6];
  for (int i = 0; i < 3; ++i) {
    const uint16_t word = static_cast<uint16_t>(static_cast<int16_t>(counts[i]));
    raw[2 * i] = static_cast<uint8_t>(word & 0xFF);
    raw[2 * i + 1] = static_cast<uint8_t>(word >> 8);
  }
  float scale = 0.0f;
  if (std::strcmp(kind, "accel") == 0) {
    scale = lsm::accel_scale(static_cast<lsm::AccelRange>(range));
  } else if (std::strcmp(kind, "gyro") == 0) {
    scale = lsm::gyro_scale(static_cast<lsm::GyroRange>(range));
  } else if (std::strcmp(kind, "mag") == 0) {
    scale = lsm::mag_scale(static_cast<lsm::MagRange>(range));
  }
  float si[3];
  lsm::convert_xyz(raw, scale, si);
  std::printf("%a %a %a\n", si[0], si[1], si[2]);
}

void setup(unsigned accel, unsigned gyro, unsigned mag) {
  lsm::RegisterWrite gyro_writes[lsm::kGyroSetupWrites];
  lsm::RegisterWrite accel_mag_writes[lsm::kAccelMagSetupWrites];
  lsm::gyro_setup(static_cast<lsm::GyroRange>(gyro), gyro_writes);
  lsm::accel_mag_setup(static_cast<lsm::AccelRange>(accel), static_cast<lsm::MagRange>(mag),
                       accel_mag_writes);
  for (const auto& w : gyro_writes) std::printf("g%02x=%02x ", w.reg, w.value);
  for (const auto& w : accel_mag_writes) std::printf("xm%02x=%02x ", w.reg, w.value);
  std::printf("\n");
}

void barometer(const uint8_t* regs) {
  const mpl::Coefficients c = mpl::decode_coefficients(regs + mpl::kRegA0Msb);
  const mpl::Reading r = mpl::compensate(c, regs + mpl::kRegPadcMsb);
  std::printf("%a %a %a %a %u %u %a %a\n", c.a0, c.b1, c.b2, c.c12,
              mpl::adc_counts(regs[0], regs[1]), mpl::adc_counts(regs[2], regs[3]),
              r.pressure_pa, r.temperature_c);
}

}  // namespace

int main() {
  char kind[16];
  while (std::scanf("%15s", kind) == 1) {
    if (std::strcmp(kind, "setup") == 0) {
      unsigned accel, gyro, mag;
      if (std::scanf("%u %u %u", &accel, &gyro, &mag) != 3) return 1;
      setup(accel, gyro, mag);
    } else if (std::strcmp(kind, "mpl115a2") == 0) {
      uint8_t regs[12];
      for (uint8_t& r : regs) {
        if (std::scanf("%" SCNx8, &r) != 1) return 1;
      }
      barometer(regs);
    } else if (std::strcmp(kind, "missing") == 0) {
      uint32_t bits;
      const float value = tactex::missing_value();
      std::memcpy(&bits, &value, sizeof(bits));
      std::printf("%08" PRIx32 "\n", bits);
    } else {
      unsigned range;
      int x, y, z;
      if (std::scanf("%u %d %d %d", &range, &x, &y, &z) != 4) return 1;
      xyz(kind, range, x, y, z);
    }
    std::fflush(stdout);
  }
  return 0;
}
