// Copyright 2026 The tactex authors
// SPDX-License-Identifier: Apache-2.0
// LSM9DS0 and MPL115A2 configuration and conversions (see tactex_sensors.h).
#include "tactex_sensors.h"

#include <string.h>

namespace tactex {

float missing_value() {
  float value;
  memcpy(&value, &kMissingBits, sizeof(value));
  return value;
}

namespace lsm9ds0 {
namespace {

// Datasheet sensitivities, indexed by the range enums (which follow the FS bit codes).
constexpr float kAccelMgPerLsb[] = {0.061f, 0.122f, 0.183f, 0.244f, 0.732f};
constexpr float kGyroMdpsPerLsb[] = {8.75f, 17.5f, 70.0f};
constexpr float kMagMgaussPerLsb[] = {0.08f, 0.16f, 0.32f, 0.48f};

uint8_t code(AccelRange range) { return static_cast<uint8_t>(range); }
uint8_t code(GyroRange range) { return static_cast<uint8_t>(range); }
uint8_t code(MagRange range) { return static_cast<uint8_t>(range); }

}  // namespace

void gyro_setup(GyroRange range, RegisterWrite (&writes)[kGyroSetupWrites]) {
  // CTRL_REG1_G: DR=10 (380 Hz), BW=11 (100 Hz), PD=1, Zen=Yen=Xen=1.
  writes[0] = {kRegCtrl1G, 0xBF};
  // CTRL_REG4_G: BDU=1, FS in bits 5:4.
  writes[1] = {kRegCtrl4G, static_cast<uint8_t>(0x80 | (code(range) << 4))};
}

void accel_mag_setup(AccelRange accel, MagRange mag,
                     RegisterWrite (&writes)[kAccelMagSetupWrites]) {
  // CTRL_REG1_XM: AODR=1000 (400 Hz), BDU=1, AZEN=AYEN=AXEN=1.
  writes[0] = {kRegCtrl1XM, 0x8F};
  // CTRL_REG2_XM: ABW=01 (194 Hz anti-alias), AFS in bits 5:3.
  writes[1] = {kRegCtrl2XM, static_cast<uint8_t>(0x40 | (code(accel) << 3))};
  // CTRL_REG5_XM: TEMP_EN=0, M_RES=11 (high), M_ODR=101 (100 Hz).
  writes[2] = {kRegCtrl5XM, 0x74};
  // CTRL_REG6_XM: MFS in bits 6:5.
  writes[3] = {kRegCtrl6XM, static_cast<uint8_t>(code(mag) << 5)};
  // CTRL_REG7_XM: MD=00, continuous conversion (after reset the magnetometer is not).
  writes[4] = {kRegCtrl7XM, 0x00};
}

float accel_scale(AccelRange range) {
  return kAccelMgPerLsb[code(range)] * 1e-3f * kStandardGravity;
}

float gyro_scale(GyroRange range) {
  return kGyroMdpsPerLsb[code(range)] * 1e-3f * kRadiansPerDegree;
}

float mag_scale(MagRange range) {
  return kMagMgaussPerLsb[code(range)] * 1e-3f * kTeslaPerGauss;
}

void convert_xyz(const uint8_t* raw, float scale, float* xyz) {
  for (int axis = 0; axis < 3; ++axis) {
    const int16_t counts = static_cast<int16_t>(raw[2 * axis] | (raw[2 * axis + 1] << 8));
    xyz[axis] = static_cast<float>(counts) * scale;
  }
}

}  // namespace lsm9ds0

namespace mpl115a2 {
namespace {

int16_t signed_word(const uint8_t* raw) { return static_cast<int16_t>((raw[0] << 8) | raw[1]); }

}  // namespace

Coefficients decode_coefficients(const uint8_t* raw) {
  Coefficients c;
  c.a0 = static_cast<float>(signed_word(raw)) / 8.0f;            // 2^3
  c.b1 = static_cast<float>(signed_word(raw + 2)) / 8192.0f;     // 2^13
  c.b2 = static_cast<float>(signed_word(raw + 4)) / 16384.0f;    // 2^14
  // The low 2 bits are not part of c12; 13 fractional + 9 zero-pad bits: 2^22.
  c.c12 = static_cast<float>(signed_word(raw + 6) >> 2) / 4194304.0f;
  return c;
}

uint16_t adc_counts(uint8_t msb, uint8_t lsb) {
  return static_cast<uint16_t>(((msb << 8) | lsb) >> 6);
}

Reading compensate(const Coefficients& c, const uint8_t* raw) {
  const float padc = adc_counts(raw[0], raw[1]);
  const float tadc = adc_counts(raw[2], raw[3]);
  const float pcomp = c.a0 + (c.b1 + c.c12 * tadc) * padc + c.b2 * tadc;
  // 0..1023 counts span 50..115 kPa.
  const float pressure_kpa = pcomp * (65.0f / 1023.0f) + 50.0f;
  return {pressure_kpa * 1000.0f, (tadc - kTadcAt25C) / kTadcPerDegC + 25.0f};
}

}  // namespace mpl115a2
}  // namespace tactex
