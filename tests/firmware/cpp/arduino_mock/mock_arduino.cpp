// Copyright 2026 The tactex authors
// SPDX-License-Identifier: Apache-2.0
// The simulated time, USB serial, timer and I2C bus behind the mock Arduino headers.
#include <Arduino.h>
#include <IntervalTimer.h>
#include <Wire.h>

namespace mock {
namespace {
double g_now_us = 0.0;
}  // namespace

double now_us() { return g_now_us; }
void set_now_us(double t) { g_now_us = t; }
void advance_us(double dt) { g_now_us += dt; }
}  // namespace mock

uint32_t micros() { return static_cast<uint32_t>(static_cast<uint64_t>(mock::now_us())); }
uint32_t millis() { return static_cast<uint32_t>(static_cast<uint64_t>(mock::now_us() / 1000)); }
void delay(uint32_t ms) { mock::advance_us(1000.0 * ms); }

// ------------------------------------------------------------------ USB serial

UsbSerial Serial;

int UsbSerial::read() {
  if (input.empty()) return -1;
  const int byte = input.front();
  input.pop_front();
  return byte;
}

bool UsbSerial::allocate() {
  if (!has_packet_) {
    if (queued_.size() >= kQueueLimit) return false;
    packet_.clear();
    has_packet_ = true;
  }
  return true;
}

int UsbSerial::availableForWrite() {
  return allocate() ? static_cast<int>(kPacketSize - packet_.size()) : 0;
}

size_t UsbSerial::write(const uint8_t* data, size_t size) {
  size_t written = 0;
  while (written < size) {
    if (!allocate()) {
      ++blocking_writes;  // the real core would wait up to 70 ms here
      break;
    }
    while (written < size && packet_.size() < kPacketSize) packet_.push_back(data[written++]);
    if (packet_.size() == kPacketSize) send_now();
  }
  last_write_us_ = mock::now_us();
  return written;
}

void UsbSerial::send_now() {
  if (has_packet_ && !packet_.empty()) queued_.push_back(packet_);
  has_packet_ = false;
}

void UsbSerial::service() {
  if (has_packet_ && !packet_.empty() && mock::now_us() - last_write_us_ >= kFlushTimeoutUs) {
    send_now();
  }
}

std::vector<uint8_t> UsbSerial::host_read() {
  std::vector<uint8_t> data;
  for (const auto& packet : queued_) data.insert(data.end(), packet.begin(), packet.end());
  queued_.clear();
  return data;
}

// ------------------------------------------------------------------ timer

IntervalTimer* IntervalTimer::running = nullptr;
uint32_t IntervalTimer::starts = 0;

bool IntervalTimer::begin(void (*handler)(), float period) {
  isr = handler;
  period_us = period;
  started_us = mock::now_us();
  running = this;
  ++starts;
  return true;
}

void IntervalTimer::end() {
  if (running == this) running = nullptr;
}

// ------------------------------------------------------------------ I2C bus

TwoWire Wire;

void TwoWire::charge(uint32_t bits) {
  const double dt = bits * 1e6 / clock_hz_;
  bus_us += dt;
  mock::advance_us(dt);
}

void TwoWire::beginTransmission(uint8_t address) {
  address_ = address;
  tx_.clear();
}

size_t TwoWire::write(uint8_t data) {
  tx_.push_back(data);
  return 1;
}

// Bits on the bus: START 1, each byte 8 + ACK, STOP 1 (a repeated START counts as a START).
uint8_t TwoWire::endTransmission(uint8_t send_stop) {
  FakeChip* chip = chips[address_ & 0x7F];
  if (chip == nullptr) {
    charge(1 + 9 + 1);  // address NACKed, the driver sends STOP
    return 2;
  }
  charge(1 + 9 * (1 + static_cast<uint32_t>(tx_.size())) + (send_stop ? 1 : 0));
  chip->write(tx_.data(), tx_.size());
  return 0;
}

uint8_t TwoWire::requestFrom(uint8_t address, uint8_t quantity) {
  rx_.clear();
  rx_index_ = 0;
  FakeChip* chip = chips[address & 0x7F];
  if (chip == nullptr) {
    charge(1 + 9 + 1);
    return 0;
  }
  charge(1 + 9 + 9 * static_cast<uint32_t>(quantity) + 1);
  for (uint8_t i = 0; i < quantity; ++i) rx_.push_back(chip->read());
  return quantity;
}
