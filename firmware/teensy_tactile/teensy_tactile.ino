// Copyright 2026 The tactex authors
// SPDX-License-Identifier: Apache-2.0
// Tactile module firmware for a Teensy 3.2: LSM9DS0 + MPL115A2 on I2C, wire protocol v1 on USB.
//
// A hardware timer (IntervalTimer, a PIT channel) ticks at the frame rate. Its interrupt
// only stamps micros() and counts the tick; the main loop then samples the chips over I2C
// (never inside the interrupt), converts to SI units and writes one frame, and only when
// the USB transmit buffer has room for all 56 bytes: a slow host costs frames, never time.
// Every tick owns a sequence number, sent or not, so the host counts each missing frame as
// lost. A chip that does not answer sends NaN in its channels and is retried once a second.
// The host can switch the rate with one byte: '1' for 120 Hz, '3' for 350 Hz.

#include <Arduino.h>
#include <IntervalTimer.h>
#include <Wire.h>

#include "tactex_frame.h"
#include "tactex_ranges.h"
#include "tactex_sensors.h"

#if !defined(__MK20DX256__) && !defined(TACTEX_ARDUINO_MOCK)
#error "teensy_tactile is written for the Teensy 3.2 (Tools > Board > Teensy 3.2 / 3.1)"
#endif

// ------------------------------------------------------------------ configuration

#ifndef TACTEX_RATE_HZ
#define TACTEX_RATE_HZ 120  // frames per second after power-on
#endif
static_assert(TACTEX_RATE_HZ >= 1 && TACTEX_RATE_HZ <= 350, "TACTEX_RATE_HZ must be 1..350");

// The ranges of tactex_common/chips.py (tactex_ranges.h is written from it): sweeps and
// texture vibration stay inside them, and the simulator and the Madgwick filter use them.
const tactex::lsm9ds0::AccelRange kAccelRange = tactex::ranges::kAccel;
const tactex::lsm9ds0::GyroRange kGyroRange = tactex::ranges::kGyro;
const tactex::lsm9ds0::MagRange kMagRange = tactex::ranges::kMag;
const uint32_t kI2cClockHz = 400000;
const uint32_t kCheckIntervalUs = 1000000;  // retry silent chips, re-check live ones
// Above systick (32) and USB (112): the interrupt stamps the tick, not the end of a USB job.
const uint8_t kTimerPriority = 16;

// An I2C chip and whether it answered last time.
struct Chip {
  uint8_t address;
  bool up;
};

// ------------------------------------------------------------------ state

IntervalTimer g_timer;
volatile uint32_t g_tick_count = 0;  // ticks since the timer started (written by the ISR)
volatile uint32_t g_tick_us = 0;     // micros() at the latest tick (written by the ISR)
uint32_t g_ticks_handled = 0;
uint16_t g_rate_hz = 0;
uint32_t g_last_check_us = 0;

Chip g_gyro = {tactex::lsm9ds0::kAddressGyro, false};
Chip g_accel_mag = {tactex::lsm9ds0::kAddressAccelMag, false};
Chip g_barometer = {tactex::mpl115a2::kAddress, false};
tactex::lsm9ds0::RegisterWrite g_gyro_setup[tactex::lsm9ds0::kGyroSetupWrites];
tactex::lsm9ds0::RegisterWrite g_accel_mag_setup[tactex::lsm9ds0::kAccelMagSetupWrites];
float g_accel_scale = 0.0f;
float g_gyro_scale = 0.0f;
float g_mag_scale = 0.0f;
tactex::mpl115a2::Coefficients g_coefficients;
// The latest barometer result: NaN while the chip is down or before its first conversion.
tactex::mpl115a2::Reading g_pressure = {tactex::missing_value(), tactex::missing_value()};
uint32_t g_conversion_started_us = 0;

// ------------------------------------------------------------------ timer

void on_tick() {
  g_tick_us = micros();
  g_tick_count = g_tick_count + 1;
}

void start_timer(uint16_t rate_hz) {
  g_timer.end();
  g_rate_hz = rate_hz;
  g_timer.priority(kTimerPriority);
  g_timer.begin(on_tick, 1e6f / rate_hz);
}

// ------------------------------------------------------------------ I2C

bool read_registers(const Chip& chip, uint8_t reg, uint8_t* data, uint8_t count) {
  Wire.beginTransmission(chip.address);
  Wire.write(reg);
  if (Wire.endTransmission(false) != 0) return false;  // repeated start: no stop in between
  if (Wire.requestFrom(chip.address, count) != count) return false;
  for (uint8_t i = 0; i < count; ++i) data[i] = static_cast<uint8_t>(Wire.read());
  return true;
}

bool write_register(const Chip& chip, uint8_t reg, uint8_t value) {
  Wire.beginTransmission(chip.address);
  Wire.write(reg);
  Wire.write(value);
  return Wire.endTransmission() == 0;
}

// ------------------------------------------------------------------ chips

void setup_lsm9ds0_die(Chip& chip, uint8_t who_am_i,
                       const tactex::lsm9ds0::RegisterWrite* writes, size_t count) {
  uint8_t id = 0;
  chip.up = read_registers(chip, tactex::lsm9ds0::kRegWhoAmI, &id, 1) && id == who_am_i;
  for (size_t i = 0; chip.up && i < count; ++i) {
    chip.up = write_register(chip, writes[i].reg, writes[i].value);
  }
}

// A live die must still hold its first setup register (a power glitch resets it).
void check_lsm9ds0_die(Chip& chip, uint8_t who_am_i,
                       const tactex::lsm9ds0::RegisterWrite* writes, size_t count) {
  uint8_t value = 0;
  if (chip.up && read_registers(chip, writes[0].reg, &value, 1) && value == writes[0].value) {
    return;
  }
  setup_lsm9ds0_die(chip, who_am_i, writes, count);
}

void lose_barometer() {
  g_barometer.up = false;
  g_pressure.pressure_pa = g_pressure.temperature_c = tactex::missing_value();
}

bool start_conversion() {
  g_conversion_started_us = micros();
  return write_register(g_barometer, tactex::mpl115a2::kCommandConvert, 0x00);
}

void setup_barometer() {
  uint8_t raw[8];
  g_barometer.up = read_registers(g_barometer, tactex::mpl115a2::kRegA0Msb, raw, sizeof(raw));
  if (g_barometer.up) {
    g_coefficients = tactex::mpl115a2::decode_coefficients(raw);
    g_barometer.up = start_conversion();
  }
}

void check_chips() {
  check_lsm9ds0_die(g_gyro, tactex::lsm9ds0::kWhoAmIGyro, g_gyro_setup,
                    tactex::lsm9ds0::kGyroSetupWrites);
  check_lsm9ds0_die(g_accel_mag, tactex::lsm9ds0::kWhoAmIAccelMag, g_accel_mag_setup,
                    tactex::lsm9ds0::kAccelMagSetupWrites);
  if (!g_barometer.up) setup_barometer();
}

// ------------------------------------------------------------------ sampling

void read_xyz(Chip& chip, uint8_t reg, float scale, float* xyz) {
  uint8_t raw[6];
  if (chip.up && read_registers(chip, reg | tactex::lsm9ds0::kAutoIncrement, raw, 6)) {
    tactex::lsm9ds0::convert_xyz(raw, scale, xyz);
    return;
  }
  chip.up = false;
  xyz[0] = xyz[1] = xyz[2] = tactex::missing_value();
}

// Collect the finished conversion and start the next one; between results the last
// reading is repeated (a conversion takes longer than a tick at 350 Hz).
void update_pressure() {
  if (!g_barometer.up) return;
  if (tactex::elapsed_us(micros(), g_conversion_started_us) < tactex::mpl115a2::kConversionUs) {
    return;
  }
  uint8_t raw[4];
  if (read_registers(g_barometer, tactex::mpl115a2::kRegPadcMsb, raw, sizeof(raw)) &&
      start_conversion()) {
    g_pressure = tactex::mpl115a2::compensate(g_coefficients, raw);
  } else {
    lose_barometer();
  }
}

void send_frame(const tactex::Sample& sample) {
  // Teensy 3.x: the room left in the current 64-byte USB packet, 0 once the host stops
  // reading and 8 packets wait. Writing only what fits never blocks.
  if (Serial.availableForWrite() < static_cast<int>(tactex::kFrameSize)) return;
  uint8_t frame[tactex::kFrameSize];
  tactex::encode_frame(sample, frame);
  Serial.write(frame, sizeof(frame));
  Serial.send_now();  // queue the packet now, so the next frame starts a fresh one
}

void sample_tick(uint32_t tick, uint32_t stamp_us) {
  tactex::Sample sample;
  sample.sequence = tactex::sequence_of_tick(tick);
  sample.device_time_us = stamp_us;
  read_xyz(g_accel_mag, tactex::lsm9ds0::kRegOutXLA, g_accel_scale, sample.accel);
  read_xyz(g_gyro, tactex::lsm9ds0::kRegOutXLG, g_gyro_scale, sample.gyro);
  read_xyz(g_accel_mag, tactex::lsm9ds0::kRegOutXLM, g_mag_scale, sample.mag);
  update_pressure();
  sample.pressure_pa = g_pressure.pressure_pa;
  sample.temperature_c = g_pressure.temperature_c;
  send_frame(sample);
}

void poll_commands() {
  while (Serial.available() > 0) {
    const uint16_t rate_hz = tactex::rate_of_command(static_cast<uint8_t>(Serial.read()));
    if (rate_hz != 0 && rate_hz != g_rate_hz) start_timer(rate_hz);
  }
}

// ------------------------------------------------------------------ Arduino entry points

void setup() {
  Serial.begin(250000);  // USB: the line rate is ignored, and nothing waits for a host
  Wire.begin();
  Wire.setClock(kI2cClockHz);
  g_accel_scale = tactex::lsm9ds0::accel_scale(kAccelRange);
  g_gyro_scale = tactex::lsm9ds0::gyro_scale(kGyroRange);
  g_mag_scale = tactex::lsm9ds0::mag_scale(kMagRange);
  tactex::lsm9ds0::gyro_setup(kGyroRange, g_gyro_setup);
  tactex::lsm9ds0::accel_mag_setup(kAccelRange, kMagRange, g_accel_mag_setup);
  delay(10);  // LSM9DS0 boot after power-on
  check_chips();
  delay(5);  // first barometer conversion and first LSM9DS0 samples ready for frame 0
  g_last_check_us = micros();
  start_timer(TACTEX_RATE_HZ);
}

void loop() {
  poll_commands();
  noInterrupts();
  const uint32_t ticks = g_tick_count;
  const uint32_t stamp_us = g_tick_us;
  interrupts();
  if (ticks == g_ticks_handled) return;
  // Ticks the loop fell behind on are not sampled: their sequence numbers are skipped,
  // so the host counts them as lost frames.
  g_ticks_handled = ticks;
  sample_tick(ticks - 1, stamp_us);
  if (tactex::elapsed_us(stamp_us, g_last_check_us) >= kCheckIntervalUs) {
    g_last_check_us = stamp_us;
    check_chips();
  }
}
