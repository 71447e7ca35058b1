// Copyright 2026 The tactex authors
// SPDX-License-Identifier: Apache-2.0
// Runs the Teensy sketch for N timer ticks against fake chips and a simulated USB host.
//
// Usage: sketch_sim [--ticks N] [--start-us T] [--absent gyro|accel_mag|barometer]...
//                   [--appear-tick K] [--stall FROM:COUNT] [--command TICK:CHAR]
// The bytes the host received go to stdout, counters to stderr as key=value lines.
#include <Arduino.h>
#include <IntervalTimer.h>
#include <Wire.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

void setup();
void loop();

namespace {

// What the fake chips measure (sensor frame, SI units); tests/firmware asserts on them.
constexpr double kAccel[3] = {0.5, -1.0, 9.80665};    // m/s^2
constexpr double kGyro[3] = {0.5, -0.25, 1.0};        // rad/s
constexpr double kMag[3] = {2.0e-5, -4.0e-6, 4.3e-5};  // T
constexpr double kPi = 3.14159265358979323846;

// Byte `index` (0..5) of X, Y, Z as little-endian int16 counts of `per_lsb`.
uint8_t xyz_byte(const double* values, double per_lsb, int index) {
  const long count = std::lround(values[index / 2] / per_lsb);
  const uint16_t word = static_cast<uint16_t>(static_cast<int16_t>(count));
  return static_cast<uint8_t>(index % 2 == 0 ? word & 0xFF : word >> 8);
}

// An LSM9DS0 die: a register file where bit 7 of the sub-address turns on auto-increment.
class Lsm9ds0Die : public FakeChip {
 public:
  void write(const uint8_t* data, size_t size) override {
    pointer_ = data[0] & 0x7F;
    increment_ = (data[0] & 0x80) != 0;
    if (size > 1) regs_[pointer_] = data[1];
  }
  uint8_t read() override {
    const uint8_t value = output(pointer_);
    if (increment_) pointer_ = (pointer_ + 1) & 0x7F;
    return value;
  }

 protected:
  virtual uint8_t output(uint8_t reg) = 0;
  uint8_t regs_[128] = {};
  uint8_t pointer_ = 0;
  bool increment_ = false;
};

// Sensitivities from the datasheet table, by full-scale code: udps, ug, ugauss per LSB.
class Gyro : public Lsm9ds0Die {
 public:
  Gyro() {
    regs_[0x0F] = 0xD4;  // WHO_AM_I_G
    regs_[0x20] = 0x07;  // CTRL_REG1_G after reset: powered down
  }

 protected:
  uint8_t output(uint8_t reg) override {
    if (reg < 0x28 || reg > 0x2D) return regs_[reg];
    if ((regs_[0x20] & 0x08) == 0) return 0;
    static const double kUdps[] = {8750, 17500, 70000, 70000};
    const double dps[3] = {kGyro[0] * 180 / kPi, kGyro[1] * 180 / kPi, kGyro[2] * 180 / kPi};
    return xyz_byte(dps, kUdps[(regs_[0x23] >> 4) & 3] * 1e-6, reg - 0x28);
  }
};

class AccelMag : public Lsm9ds0Die {
 public:
  AccelMag() {
    regs_[0x0F] = 0x49;  // WHO_AM_I_XM
    regs_[0x20] = 0x07;  // CTRL_REG1_XM after reset: accel powered down
    regs_[0x26] = 0x02;  // CTRL_REG7_XM: magnetometer not in continuous mode
  }

 protected:
  uint8_t output(uint8_t reg) override {
    if (reg >= 0x28 && reg <= 0x2D) {
      if ((regs_[0x20] >> 4) == 0) return 0;
      static const double kUg[] = {61, 122, 183, 244, 732, 732, 732, 732};
      const double mg[3] = {kAccel[0] / 9.80665e-3, kAccel[1] / 9.80665e-3,
                            kAccel[2] / 9.80665e-3};
      return xyz_byte(mg, kUg[(regs_[0x21] >> 3) & 7] * 1e-3, reg - 0x28);
    }
    if (reg >= 0x08 && reg <= 0x0D) {
      if ((regs_[0x26] & 0x03) != 0) return 0;
      static const double kUgauss[] = {80, 160, 320, 480};
      const double mgauss[3] = {kMag[0] * 1e7, kMag[1] * 1e7, kMag[2] * 1e7};
      return xyz_byte(mgauss, kUgauss[(regs_[0x25] >> 5) & 3] * 1e-3, reg - 0x08);
    }
    return regs_[reg];
  }
};

// An MPL115A2 holding the coefficients and the conversion result of AN3785's example.
class Barometer : public FakeChip {
 public:
  void write(const uint8_t* data, size_t size) override {
    if (data[0] == 0x12 && size == 2) {
      ready_at_us_ = mock::now_us() + 3000.0;  // datasheet: at most 3 ms per conversion
      converted_ = true;
    } else {
      pointer_ = data[0];
    }
  }
  uint8_t read() override {
    if (pointer_ == 0x00) {
      if (!converted_ || mock::now_us() < ready_at_us_) {
        ++early_reads;
      } else {
        ++results_read;
      }
    }
    const uint8_t value = pointer_ < sizeof(regs_) ? regs_[pointer_] : 0;
    ++pointer_;
    return value;
  }
  uint32_t early_reads = 0;
  uint32_t results_read = 0;

 private:
  const uint8_t regs_[12] = {0x66, 0x80, 0x7E, 0xC0, 0x3E, 0xCE,
                             0xB3, 0xF9, 0xC5, 0x17, 0x33, 0xC8};
  uint8_t pointer_ = 0;
  bool converted_ = false;
  double ready_at_us_ = 0.0;
};

struct Options {
  long ticks = 240;
  double start_us = 1e6;
  std::vector<std::string> absent;
  long appear_tick = -1;
  long stall_from = -1;
  long stall_count = 0;
  long command_tick = -1;
  int command = 0;
};

Options parse(int argc, char** argv) {
  Options options;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i];
    const char* value = argv[i + 1];
    if (key == "--ticks") {
      options.ticks = std::atol(value);
    } else if (key == "--start-us") {
      options.start_us = std::atof(value);
    } else if (key == "--absent") {
      options.absent.push_back(value);
    } else if (key == "--appear-tick") {
      options.appear_tick = std::atol(value);
    } else if (key == "--stall") {
      std::sscanf(value, "%ld:%ld", &options.stall_from, &options.stall_count);
    } else if (key == "--command") {
      char command = 0;
      std::sscanf(value, "%ld:%c", &options.command_tick, &command);
      options.command = static_cast<unsigned char>(command);
    } else {
      std::fprintf(stderr, "error: unknown option %s\n", argv[i]);
      std::exit(2);
    }
  }
  return options;
}

}  // namespace

int main(int argc, char** argv) {
  const Options options = parse(argc, argv);
  Gyro gyro;
  AccelMag accel_mag;
  Barometer barometer;
  struct Fake {
    const char* name;
    uint8_t address;
    FakeChip* chip;
  };
  const Fake fakes[] = {{"gyro", 0x6B, &gyro}, {"accel_mag", 0x1D, &accel_mag},
                        {"barometer", 0x60, &barometer}};
  for (const Fake& fake : fakes) {
    const bool absent = std::find(options.absent.begin(), options.absent.end(), fake.name) !=
                        options.absent.end();
    Wire.chips[fake.address] = absent ? nullptr : fake.chip;
  }

  mock::set_now_us(options.start_us);
  setup();
  IntervalTimer* timer = IntervalTimer::running;
  if (timer == nullptr) {
    std::fprintf(stderr, "error: setup() started no timer\n");
    return 1;
  }
  uint32_t starts = IntervalTimer::starts;
  double next_tick_us = timer->started_us + timer->period_us;
  double max_busy_us = 0.0;
  double max_bus_us = 0.0;
  std::vector<uint8_t> received;
  for (long tick = 0; tick < options.ticks; ++tick) {
    if (tick == options.appear_tick) {
      for (const Fake& fake : fakes) Wire.chips[fake.address] = fake.chip;
    }
    if (tick == options.command_tick) {
      Serial.input.push_back(static_cast<uint8_t>(options.command));
    }
    // The interrupt fires on time, even while the loop is still busy with the last tick.
    const double busy_until_us = mock::now_us();
    mock::set_now_us(next_tick_us);
    Serial.service();
    timer->isr();
    mock::set_now_us(std::max(busy_until_us, next_tick_us));
    const double bus_before_us = Wire.bus_us;
    double before_us;
    do {
      before_us = mock::now_us();
      loop();
    } while (mock::now_us() != before_us);
    max_busy_us = std::max(max_busy_us, mock::now_us() - next_tick_us);
    max_bus_us = std::max(max_bus_us, Wire.bus_us - bus_before_us);
    const bool stalled =
        tick >= options.stall_from && tick < options.stall_from + options.stall_count;
    if (!stalled) {
      const std::vector<uint8_t> data = Serial.host_read();
      received.insert(received.end(), data.begin(), data.end());
    }
    if (IntervalTimer::starts != starts) {  // the rate changed: a new tick grid
      starts = IntervalTimer::starts;
      timer = IntervalTimer::running;
      next_tick_us = timer->started_us + timer->period_us;
    } else {
      next_tick_us += timer->period_us;
    }
  }
  std::fwrite(received.data(), 1, received.size(), stdout);
  std::fprintf(stderr, "ticks=%ld\nperiod_us=%.3f\ntimer_priority=%u\nmax_busy_us=%.1f\n"
               "max_bus_us=%.1f\nblocking_writes=%u\nearly_reads=%u\nresults_read=%u\n",
               options.ticks, timer->period_us, timer->priority_, max_busy_us, max_bus_us,
               Serial.blocking_writes, barometer.early_reads, barometer.results_read);
  return 0;
}
