// Copyright 2026 The tactex authors
// SPDX-License-Identifier: Apache-2.0
// Host program around the firmware's framing code, for tests/firmware/test_framing.py.
//
// `frame_tool encode`: reads one sample per line, TICK TIME_US and 11 float32 bit patterns
// in hex (accel x y z, gyro x y z, mag x y z, pressure, temperature), and writes their
// frames to stdout. `frame_tool crc`: writes the CRC-16/CCITT-FALSE of stdin as hex.
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <vector>

#include "tactex_frame.h"

namespace {

float from_bits(uint32_t bits) {
  float value;
  std::memcpy(&value, &bits, sizeof(value));
  return value;
}

int encode() {
  uint32_t tick, time_us, bits[11];
  while (std::scanf("%" SCNu32 " %" SCNu32, &tick, &time_us) == 2) {
    for (uint32_t& b : bits) {
      if (std::scanf("%" SCNx32, &b) != 1) return 1;
    }
    tactex::Sample sample;
    sample.sequence = tactex::sequence_of_tick(tick);
    sample.device_time_us = time_us;
    for (int i = 0; i < 3; ++i) {
      sample.accel[i] = from_bits(bits[i]);
      sample.gyro[i] = from_bits(bits[3 + i]);
      sample.mag[i] = from_bits(bits[6 + i]);
    }
    sample.pressure_pa = from_bits(bits[9]);
    sample.temperature_c = from_bits(bits[10]);
    uint8_t frame[tactex::kFrameSize];
    tactex::encode_frame(sample, frame);
    std::fwrite(frame, 1, sizeof(frame), stdout);
  }
  return 0;
}

int crc() {
  std::vector<uint8_t> data;
  int c;
  while ((c = std::getchar()) != EOF) data.push_back(static_cast<uint8_t>(c));
  std::printf("%04x\n", tactex::crc16_ccitt_false(data.data(), data.size()));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::strcmp(argv[1], "encode") == 0) return encode();
  if (argc == 2 && std::strcmp(argv[1], "crc") == 0) return crc();
  std::fprintf(stderr, "usage: frame_tool encode|crc\n");
  return 2;
}
