// Copyright 2026 The tactex authors
// SPDX-License-Identifier: Apache-2.0
// LSM9DS0 and MPL115A2: registers, setup and raw -> SI conversion in plain C++, no Arduino.
//
// Sources: ST LSM9DS0 datasheet (register map, CTRL_REG bit fields, sensitivity table),
// Freescale MPL115A2 datasheet and application note AN3785 (coefficient formats and the
// compensation Pcomp = a0 + (b1 + c12 * Tadc) * Padc + b2 * Tadc).
#ifndef TACTEX_SENSORS_H_
#define TACTEX_SENSORS_H_

#include <stddef.h>
#include <stdint.h>

namespace tactex {

// What a channel of a missing or unresponsive chip carries: the quiet NaN 0x7FC00000.
constexpr uint32_t kMissingBits = 0x7FC00000u;
float missing_value();

constexpr float kStandardGravity = 9.80665f;  // m/s^2 per g
constexpr float kTeslaPerGauss = 1e-4f;
constexpr float kRadiansPerDegree = 0.017453292519943295f;

namespace lsm9ds0 {

// 7-bit I2C addresses with SA0_G and SA0_XM pulled high (the low ones are 0x6A and 0x1E).
constexpr uint8_t kAddressGyro = 0x6B;
constexpr uint8_t kAddressAccelMag = 0x1D;

constexpr uint8_t kRegWhoAmI = 0x0F;        // both dies
constexpr uint8_t kWhoAmIGyro = 0xD4;
constexpr uint8_t kWhoAmIAccelMag = 0x49;
constexpr uint8_t kAutoIncrement = 0x80;    // set in the sub-address to read several registers
constexpr uint8_t kRegCtrl1G = 0x20;        // ODR, bandwidth, power, axes
constexpr uint8_t kRegCtrl4G = 0x23;        // BDU, full scale
constexpr uint8_t kRegOutXLG = 0x28;        // gyro X, Y, Z: 6 bytes, little-endian int16
constexpr uint8_t kRegOutXLM = 0x08;        // magnetometer X, Y, Z
constexpr uint8_t kRegCtrl1XM = 0x20;       // accel ODR, BDU, axes
constexpr uint8_t kRegCtrl2XM = 0x21;       // accel anti-alias bandwidth, full scale
constexpr uint8_t kRegCtrl5XM = 0x24;       // temperature sensor, mag resolution and ODR
constexpr uint8_t kRegCtrl6XM = 0x25;       // mag full scale
constexpr uint8_t kRegCtrl7XM = 0x26;       // mag mode (continuous)
constexpr uint8_t kRegOutXLA = 0x28;        // accel X, Y, Z

enum class AccelRange : uint8_t { k2G, k4G, k6G, k8G, k16G };          // +-g
enum class GyroRange : uint8_t { k245Dps, k500Dps, k2000Dps };         // +-deg/s
enum class MagRange : uint8_t { k2Gauss, k4Gauss, k8Gauss, k12Gauss };  // +-gauss

struct RegisterWrite {
  uint8_t reg;
  uint8_t value;
};

constexpr size_t kGyroSetupWrites = 2;
constexpr size_t kAccelMagSetupWrites = 5;

// Gyro: 380 Hz output rate, 100 Hz cut-off, powered, X/Y/Z on; block data update; `range`.
void gyro_setup(GyroRange range, RegisterWrite (&writes)[kGyroSetupWrites]);
// Accel: 400 Hz, block data update, 194 Hz anti-alias filter, `accel`; magnetometer:
// continuous, high resolution, 100 Hz (its fastest), `mag`.
void accel_mag_setup(AccelRange accel, MagRange mag,
                     RegisterWrite (&writes)[kAccelMagSetupWrites]);

// SI per LSB, from the datasheet sensitivities (mg/LSB, mdps/LSB, mgauss/LSB).
float accel_scale(AccelRange range);  // m/s^2 per LSB
float gyro_scale(GyroRange range);    // rad/s per LSB
float mag_scale(MagRange range);      // T per LSB

// Three little-endian int16 counts (X, Y, Z) times `scale`.
void convert_xyz(const uint8_t* raw, float scale, float* xyz);

}  // namespace lsm9ds0

namespace mpl115a2 {

constexpr uint8_t kAddress = 0x60;
constexpr uint8_t kRegPadcMsb = 0x00;       // Padc MSB, LSB, Tadc MSB, LSB: 4 bytes
constexpr uint8_t kRegA0Msb = 0x04;         // a0, b1, b2, c12, each MSB first: 8 bytes
constexpr uint8_t kCommandConvert = 0x12;   // followed by 0x00: convert pressure and temperature
constexpr uint32_t kConversionUs = 3000;    // the maximum conversion time drivers quote

// Temperature: 472 counts at 25 degC, -5.35 counts/degC, the typical values quoted from the
// MPL115A1 datasheet (Adafruit's driver uses 498 counts); the sensor is not calibrated.
constexpr float kTadcAt25C = 472.0f;
constexpr float kTadcPerDegC = -5.35f;

struct Coefficients {
  float a0;   // signed, 12 integer and 3 fractional bits
  float b1;   // signed, 2 integer and 13 fractional bits
  float b2;   // signed, 1 integer and 14 fractional bits
  float c12;  // signed, 13 fractional bits after 9 zero bits, in the top 14 bits of 16
};

struct Reading {
  float pressure_pa;
  float temperature_c;
};

// Decode the 8 coefficient bytes read from kRegA0Msb.
Coefficients decode_coefficients(const uint8_t* raw);
// The 10-bit ADC value held left-aligned in a register pair.
uint16_t adc_counts(uint8_t msb, uint8_t lsb);
// Compensated pressure and temperature from the 4 bytes read from kRegPadcMsb.
Reading compensate(const Coefficients& coefficients, const uint8_t* raw);

}  // namespace mpl115a2
}  // namespace tactex

#endif  // TACTEX_SENSORS_H_
