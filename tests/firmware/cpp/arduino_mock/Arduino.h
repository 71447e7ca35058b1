// Copyright 2026 The tactex authors
// SPDX-License-Identifier: Apache-2.0
// Host stand-in for the Teensyduino API the sketch uses: simulated time and the USB Serial.
#ifndef TACTEX_MOCK_ARDUINO_H_
#define TACTEX_MOCK_ARDUINO_H_

#define TACTEX_ARDUINO_MOCK 1

#include <stddef.h>
#include <stdint.h>

#include <deque>
#include <vector>

namespace mock {
double now_us();             // simulated time, microseconds
void set_now_us(double t);
void advance_us(double dt);
}  // namespace mock

uint32_t micros();
uint32_t millis();
void delay(uint32_t ms);
inline void noInterrupts() {}
inline void interrupts() {}

// Teensy 3.x USB serial (cores/teensy3/usb_serial.c): data goes out in 64-byte packets,
// at most 8 queued for the host; a partial packet leaves when send_now() is called or
// 5 ms after the last write. availableForWrite() is the room in the current packet.
class UsbSerial {
 public:
  static constexpr size_t kPacketSize = 64;
  static constexpr size_t kQueueLimit = 8;
  static constexpr double kFlushTimeoutUs = 5000.0;

  void begin(long) {}
  int available() const { return static_cast<int>(input.size()); }
  int read();
  int availableForWrite();
  size_t write(const uint8_t* data, size_t size);
  void send_now();

  // Simulation side.
  void service();                       // the 5 ms flush timer
  std::vector<uint8_t> host_read();     // the host collects every queued packet
  std::deque<uint8_t> input;            // bytes sent by the host
  uint32_t blocking_writes = 0;         // writes that would have waited for the host

 private:
  bool allocate();
  std::vector<uint8_t> packet_;
  bool has_packet_ = false;
  std::deque<std::vector<uint8_t>> queued_;
  double last_write_us_ = 0.0;
};

extern UsbSerial Serial;

#endif  // TACTEX_MOCK_ARDUINO_H_
