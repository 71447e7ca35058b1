// Copyright 2026 The tactex authors
// SPDX-License-Identifier: Apache-2.0
// Host stand-in for Teensy's Wire: a simulated I2C bus that charges bus time bit by bit.
#ifndef TACTEX_MOCK_WIRE_H_
#define TACTEX_MOCK_WIRE_H_

#include <stddef.h>
#include <stdint.h>

#include <vector>

// A simulated chip: a write transaction (first byte: register or command), then reads.
class FakeChip {
 public:
  virtual ~FakeChip() = default;
  virtual void write(const uint8_t* data, size_t size) = 0;
  virtual uint8_t read() = 0;
};

class TwoWire {
 public:
  void begin() { clock_hz_ = 100000; }  // Teensy's Wire.begin() starts at 100 kHz
  void setClock(uint32_t hz) { clock_hz_ = hz; }
  void beginTransmission(uint8_t address);
  size_t write(uint8_t data);
  uint8_t endTransmission() { return endTransmission(1); }
  uint8_t endTransmission(uint8_t send_stop);
  uint8_t requestFrom(uint8_t address, uint8_t quantity);
  int available() const { return static_cast<int>(rx_.size() - rx_index_); }
  int read() { return rx_index_ < rx_.size() ? rx_[rx_index_++] : -1; }

  // Simulation side.
  FakeChip* chips[128] = {};  // by 7-bit address; nullptr: nobody acknowledges
  double bus_us = 0.0;        // bus time spent so far

 private:
  void charge(uint32_t bits);
  uint32_t clock_hz_ = 0;
  uint8_t address_ = 0;
  std::vector<uint8_t> tx_;
  std::vector<uint8_t> rx_;
  size_t rx_index_ = 0;
};

extern TwoWire Wire;

#endif  // TACTEX_MOCK_WIRE_H_
