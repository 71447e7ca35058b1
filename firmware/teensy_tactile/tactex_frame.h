// Copyright 2026 The tactex authors
// SPDX-License-Identifier: Apache-2.0
// Wire protocol version 1 (frame layout, CRC-16/CCITT-FALSE, counters) in plain C++, no Arduino.
//
// One 56-byte little-endian frame per sample: sync A5 5A, version 1, payload length 50,
// uint16 sequence, uint32 device time (us), accel (m/s^2), gyro (rad/s), magnetic field
// (T), pressure (Pa), temperature (degC) as float32, CRC-16/CCITT-FALSE of bytes 2..53.
// The Python twin is tactex_sensor/protocol.py; tests/firmware checks they agree bit for bit.
#ifndef TACTEX_FRAME_H_
#define TACTEX_FRAME_H_

#include <stddef.h>
#include <stdint.h>

namespace tactex {

constexpr uint8_t kSync0 = 0xA5;
constexpr uint8_t kSync1 = 0x5A;
constexpr uint8_t kProtocolVersion = 1;
constexpr uint8_t kPayloadLength = 50;
constexpr size_t kFrameSize = 56;

// One sample as it travels on the wire (SI units, sensor frame).
struct Sample {
  uint16_t sequence;        // one per timer tick, sent or not; wraps at 2^16
  uint32_t device_time_us;  // micros() at the timer tick that started the sample; wraps at 2^32
  float accel[3];           // m/s^2
  float gyro[3];            // rad/s
  float mag[3];             // T
  float pressure_pa;        // Pa
  float temperature_c;      // degC
};

// CRC-16/CCITT-FALSE: poly 0x1021, init 0xFFFF, no reflection, xorout 0.
uint16_t crc16_ccitt_false(const uint8_t* data, size_t length);

// Write the frame of `sample` into `frame` (kFrameSize bytes), little-endian on any host.
void encode_frame(const Sample& sample, uint8_t* frame);

// The sequence number of the timer tick with zero-based index `tick` (wraps at 2^16).
constexpr uint16_t sequence_of_tick(uint32_t tick) {
  return static_cast<uint16_t>(tick & 0xFFFFu);
}

// Microseconds from `since_us` to `now_us` on the wrapping uint32 micros() counter.
constexpr uint32_t elapsed_us(uint32_t now_us, uint32_t since_us) { return now_us - since_us; }

// Host -> device: a single byte selects the frame rate; 0 for a byte that is no command.
constexpr uint8_t kCommandRate120Hz = '1';
constexpr uint8_t kCommandRate350Hz = '3';
constexpr uint16_t rate_of_command(uint8_t command) {
  return command == kCommandRate120Hz ? 120 : command == kCommandRate350Hz ? 350 : 0;
}

}  // namespace tactex

#endif  // TACTEX_FRAME_H_
