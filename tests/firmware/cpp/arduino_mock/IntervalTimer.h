// Copyright 2026 The tactex authors
// SPDX-License-Identifier: Apache-2.0
// Host stand-in for Teensy's IntervalTimer: remembers the ISR and period for the simulator.
#ifndef TACTEX_MOCK_INTERVALTIMER_H_
#define TACTEX_MOCK_INTERVALTIMER_H_

#include <stdint.h>

class IntervalTimer {
 public:
  bool begin(void (*isr)(), float period_us);
  void end();
  void priority(uint8_t level) { priority_ = level; }

  // Simulation side: the running timer, when it started and how often it was started.
  static IntervalTimer* running;
  void (*isr)() = nullptr;
  float period_us = 0.0f;
  double started_us = 0.0;
  uint8_t priority_ = 128;
  static uint32_t starts;
};

#endif  // TACTEX_MOCK_INTERVALTIMER_H_
