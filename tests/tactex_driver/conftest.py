# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Fixtures of the driver tests: an emulated servo chain and a bus on it."""

import pytest

from tactex_driver.bus import ServoBus
from tactex_driver.servo_emulator import ServoChainEmulator


@pytest.fixture
def chain(tmp_path):
    with ServoChainEmulator(tmp_path / 'dxl') as emulator:
        yield emulator


@pytest.fixture
def bus(chain):
    with ServoBus(str(chain.link)) as servo_bus:
        yield servo_bus
