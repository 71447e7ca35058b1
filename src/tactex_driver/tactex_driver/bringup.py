# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Bring-up checks of the servo chain: IDs, baud rate, models, supply, temperature, limits.

Reads the servos' control tables (XM430-W350, Protocol 2.0) and compares them with the
driver's configuration (config/driver.yaml) and the robot description's joint limits;
nothing is written, torque is left as it is.
"""

from __future__ import annotations

from collections.abc import Sequence
import math

from tactex_common.bringup import Check, FAIL, OK, WARN
from tactex_driver import control_table as ct
from tactex_driver.bus import ServoBus
from tactex_driver.errors import CommunicationError
from tactex_driver.playback import JointLimits

WIZARD = 'DYNAMIXEL Wizard 2.0 (scan, then edit the control table with torque off)'
ARM_JOINTS = 4  # joint1..joint4 run in position mode, where the position limits apply
TEMPERATURE_MARGIN_C = 10.0  # warn this close to the servo's temperature limit
LOW_SUPPLY_V = 11.1  # a 3S battery nearly empty; the arm sags under load below this


def servo_checks(port: str, baud: int, ids: Sequence[int], limits: JointLimits, *,
                 port_handler=None) -> list[Check]:
    """The checks of the servos `ids` on `port` (see the module docstring).

    `port_handler` is for tests (dynamixel-sdk's PortHandler otherwise).
    """
    try:
        with ServoBus(port, baud=baud, ids=ids, port_handler=port_handler) as bus:
            models = bus.answering()
            if not models:
                return [_silent_chain(port, baud, ids, port_handler)]
            checks = [_id_check(ids, models), _model_check(models)]
            answering = sorted(models)
            checks += [_supply_check(bus, answering), _temperature_check(bus, answering),
                       _error_check(bus, answering)]
            checks.append(_limit_check(bus, [i for i in ids[:ARM_JOINTS] if i in models],
                                       ids, limits))
            return checks
    except CommunicationError as err:
        return [Check('servo bus', FAIL, str(err), 'close whatever holds the port (a running '
                      'arm_driver, DYNAMIXEL Wizard) and check the cable')]


def _silent_chain(port, baud, ids, port_handler) -> Check:
    """No servo answered at `baud`: where do they answer, if anywhere?"""
    for other in ct.BAUD_RATES.values():
        if other == baud:
            continue
        try:
            with ServoBus(port, baud=other, ids=ids, port_handler=port_handler) as bus:
                if bus.answering():
                    return Check('servo IDs', FAIL, f'no servo answers at {baud} baud; they '
                                 f'answer at {other}', f'set baud: {other} in config/driver.yaml, '
                                 f'or set every servo to {baud} baud with {WIZARD}')
        except CommunicationError:
            continue
    return Check('servo IDs', FAIL, f'no servo of {list(ids)} answers on {port} at any baud '
                 'rate', 'is the arm powered (12 V, the U2D2 power hub switched on) and the '
                 'chain cabled from the U2D2? Scan with ' + WIZARD)


def _id_check(ids: Sequence[int], models: dict[int, int]) -> Check:
    missing = [i for i in ids if i not in models]
    if missing:
        return Check('servo IDs', FAIL, f'servo(s) {missing} do not answer (answering: '
                     f'{sorted(models)})', 'check the cable into and out of that servo, and its '
                     f'ID with {WIZARD}; config/driver.yaml servo_ids lists the IDs expected')
    return Check('servo IDs', OK, f'{list(ids)} answer')


def _model_check(models: dict[int, int]) -> Check:
    wrong = {i: m for i, m in models.items() if m != ct.XM430_W350_MODEL}
    if wrong:
        return Check('servo models', FAIL, f'model numbers {wrong}; the driver speaks to the '
                     f'XM430-W350 (model {ct.XM430_W350_MODEL})', 'use XM430-W350 servos '
                     "(the OpenMANIPULATOR-X's), or adapt tactex_driver.control_table")
    return Check('servo models', OK, f'XM430-W350 (model {ct.XM430_W350_MODEL}) each')


def _supply_check(bus: ServoBus, ids: list[int]) -> Check:
    volts = {i: v * ct.VOLT_PER_UNIT for i, v in
             bus.read_unsigned(ct.PRESENT_INPUT_VOLTAGE, 2, ids).items()}
    low, high = ct.SUPPLY_RANGE_V
    lowest = min(volts.values())
    found = f'{lowest:.1f} to {max(volts.values()):.1f} V at the servos'
    if lowest < low or max(volts.values()) > high:
        return Check('servo supply', FAIL, f'{found}, outside {low:g}-{high:g} V',
                     f"use the arm's {ct.RECOMMENDED_V:g} V supply (5 A or more)")
    if lowest < LOW_SUPPLY_V:
        return Check('servo supply', WARN, f'{found}, low under load',
                     f'charge the battery or use the {ct.RECOMMENDED_V:g} V supply')
    return Check('servo supply', OK, found)


def _temperature_check(bus: ServoBus, ids: list[int]) -> Check:
    present = bus.read_unsigned(ct.PRESENT_TEMPERATURE, 1, ids)
    limit = bus.read_unsigned(ct.TEMPERATURE_LIMIT, 1, ids)
    margin = {i: limit[i] - present[i] for i in ids}
    hottest = min(margin, key=margin.get)
    found = f'hottest servo {hottest} at {present[hottest]} degC (its limit {limit[hottest]})'
    if margin[hottest] <= 0:
        return Check('servo temperature', FAIL, found, 'let it cool with torque off; an '
                     'overheated servo drops torque and latches an error')
    if margin[hottest] < TEMPERATURE_MARGIN_C:
        return Check('servo temperature', WARN, found, 'lower the load or let it cool')
    return Check('servo temperature', OK, found)


def _error_check(bus: ServoBus, ids: list[int]) -> Check:
    errors = {i: e for i, e in bus.read_unsigned(ct.HARDWARE_ERROR_STATUS, 1, ids).items()
              if e}
    if errors:
        named = {i: ct.describe_hardware_error(e) for i, e in errors.items()}
        return Check('servo errors', FAIL, f'latched hardware errors {named}', 'remove the '
                     'cause (load, supply, heat), then power-cycle the arm or reboot the servo '
                     '(arm_driver reboots a faulted servo when it recovers)')
    return Check('servo errors', OK, 'no latched hardware error')


def _limit_check(bus: ServoBus, joints: list[int], ids: Sequence[int],
                 limits: JointLimits) -> Check:
    """The servos' position limits must allow every angle the URDF allows."""
    if not joints:
        return Check('joint limits', WARN, 'no joint servo answered to compare', '')
    highest = bus.read_unsigned(ct.MAX_POSITION_LIMIT, 4, joints)
    lowest = bus.read_unsigned(ct.MIN_POSITION_LIMIT, 4, joints)
    narrow = []
    for servo in joints:
        index = list(ids).index(servo)
        low, high = (float(ct.position_to_rad(lowest[servo])),
                     float(ct.position_to_rad(highest[servo])))
        want_low, want_high = float(limits.lower[index]), float(limits.upper[index])
        if low > want_low + ct.RAD_PER_COUNT or high < want_high - ct.RAD_PER_COUNT:
            narrow.append(f'servo {servo} ({limits.names[index]}) stops at '
                          f'[{low:.2f}, {high:.2f}] rad, the URDF allows '
                          f'[{want_low:.2f}, {want_high:.2f}] (Min/Max Position Limit '
                          f'{math.floor(ct.rad_to_position(want_low))}/'
                          f'{math.ceil(ct.rad_to_position(want_high))} counts or wider)')
    if narrow:
        return Check('joint limits', FAIL, '; '.join(narrow), 'set those Min/Max Position '
                     f'Limits (addresses 52/48) with {WIZARD}: a pose the servo refuses '
                     'stops the arm short of where the planner sent it')
    return Check('joint limits', OK, f"the servos allow the URDF's range of joint1..joint"
                 f'{len(joints)}')
