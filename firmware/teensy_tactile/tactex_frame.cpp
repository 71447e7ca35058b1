// Copyright 2026 The tactex authors
// SPDX-License-Identifier: Apache-2.0
// Wire protocol version 1: CRC and frame encoding (see tactex_frame.h).
#include "tactex_frame.h"

#include <string.h>

namespace tactex {
namespace {

void put_u16(uint8_t* out, uint16_t value) {
  out[0] = static_cast<uint8_t>(value);
  out[1] = static_cast<uint8_t>(value >> 8);
}

void put_u32(uint8_t* out, uint32_t value) {
  for (int i = 0; i < 4; ++i) out[i] = static_cast<uint8_t>(value >> (8 * i));
}

void put_f32(uint8_t* out, float value) {
  uint32_t bits;
  static_assert(sizeof(bits) == sizeof(value), "float must be IEEE-754 binary32");
  memcpy(&bits, &value, sizeof(bits));
  put_u32(out, bits);
}

}  // namespace

uint16_t crc16_ccitt_false(const uint8_t* data, size_t length) {
  uint16_t crc = 0xFFFF;
  for (size_t i = 0; i < length; ++i) {
    crc = static_cast<uint16_t>(crc ^ (static_cast<uint16_t>(data[i]) << 8));
    for (int bit = 0; bit < 8; ++bit) {
      crc = (crc & 0x8000u) ? static_cast<uint16_t>((crc << 1) ^ 0x1021u)
                            : static_cast<uint16_t>(crc << 1);
    }
  }
  return crc;
}

void encode_frame(const Sample& sample, uint8_t* frame) {
  frame[0] = kSync0;
  frame[1] = kSync1;
  frame[2] = kProtocolVersion;
  frame[3] = kPayloadLength;
  put_u16(frame + 4, sample.sequence);
  put_u32(frame + 6, sample.device_time_us);
  const float values[11] = {sample.accel[0], sample.accel[1], sample.accel[2],
                            sample.gyro[0],  sample.gyro[1],  sample.gyro[2],
                            sample.mag[0],   sample.mag[1],   sample.mag[2],
                            sample.pressure_pa, sample.temperature_c};
  for (int i = 0; i < 11; ++i) put_f32(frame + 10 + 4 * i, values[i]);
  put_u16(frame + 54, crc16_ccitt_false(frame + 2, 52));
}

}  // namespace tactex
