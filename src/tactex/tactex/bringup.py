# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Every bring-up check together: ports, the Teensy's stream, the servos, the ROS settings.

`tactex doctor` runs them and prints each with its fix; `tactex launch` and `ros2
launch` of the launch files (`checks:=true`, the default) run the hardware ones first for
the hardware nodes about to start (without sim:=true) and stop with the same lines when
one fails, instead of letting the nodes retry forever.
The configured values come from the nodes' YAML files (config/sensor.yaml,
config/driver.yaml) and the launch's own overrides.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
import os
from pathlib import Path
from typing import Any

import yaml

from tactex_common.bringup import Check, FAIL, OK, port_checks, WARN
from tactex_common.share import share_directory

RMW = 'rmw_fastrtps_cpp'  # the only middleware this workspace installs
DISCOVERY_RANGES = ('SUBNET', 'LOCALHOST', 'OFF', 'SYSTEM_DEFAULT')
SAFE_DOMAIN_IDS = range(0, 102)  # on Linux, higher IDs may collide with ephemeral ports
MAX_DOMAIN_ID = 232
MARKS = {OK: '[ ok ]', WARN: '[warn]', FAIL: '[FAIL]'}


@dataclass(frozen=True)
class Hardware:
    """What the hardware nodes are configured to talk to."""

    sensor_port: str
    sensor_baud: int
    arm_port: str
    arm_baud: int
    servo_ids: tuple[int, ...]


def node_parameters(files: Sequence[str | Path], node: str,
                    overrides: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """`node`'s ros__parameters from YAML parameter files (`/**/node` or `node`), overridden."""
    values: dict[str, Any] = {}
    for path in files:
        document = yaml.safe_load(Path(path).read_text(encoding='utf-8')) or {}
        for key in (f'/**/{node}', node, f'/{node}'):
            values.update((document.get(key) or {}).get('ros__parameters', {}))
    values.update(overrides or {})
    return values


def configured_hardware() -> Hardware:
    """The ports, baud rates and servo IDs of the installed config/sensor.yaml and driver.yaml."""
    config = share_directory('tactex') / 'config'
    sensor = node_parameters([config / 'sensor.yaml'], 'teensy_node')
    arm = node_parameters([config / 'driver.yaml'], 'arm_driver')
    return Hardware(str(sensor['port']), int(sensor['baud']), str(arm['port']),
                    int(arm['baud']), tuple(int(i) for i in arm['servo_ids']))


def sensor_checks(port: str, baud: int, rate_hz: float | None, listen_s: float
                  ) -> list[Check]:
    """The Teensy's port, then (when it may be opened) its stream (its rate when given)."""
    from tactex_sensor.bringup import stream_checks
    checks = port_checks(port, 'Teensy')
    return checks if any(c.failed for c in checks) else \
        checks + stream_checks(port, baud, rate_hz, listen_s)


def arm_checks(port: str, baud: int, ids: Sequence[int]) -> list[Check]:
    """The servo adapter's port, then (when it may be opened) the servos."""
    from tactex_driver.bringup import servo_checks
    from tactex_driver.playback import JointLimits
    checks = port_checks(port, 'servo adapter')
    return checks if any(c.failed for c in checks) else \
        checks + servo_checks(port, baud, tuple(ids), JointLimits.of_robot())


def launch_checks(nodes) -> list[Check]:
    """The hardware checks of the hardware nodes among `nodes` (launching NodeSpecs).

    Each node's port, baud rate and servo IDs are its parameters as it will get them (its
    YAML files, then the launch's values). The Teensy's rate is the firmware's choice, so
    here only its frames are asked for.
    """
    checks = []
    for spec in nodes:
        if spec.executable not in ('teensy_node', 'arm_driver'):
            continue
        files = [p for p in spec.parameters if isinstance(p, (str, Path))]
        overrides = {k: v for p in spec.parameters if isinstance(p, Mapping)
                     for k, v in p.items()}
        values = node_parameters(files, spec.name, overrides)
        if spec.executable == 'teensy_node':
            checks += sensor_checks(str(values['port']), int(values['baud']), None, 1.0)
        else:
            checks += arm_checks(str(values['port']), int(values['baud']),
                                 [int(i) for i in values['servo_ids']])
    return checks


def not_ready_lines(nodes) -> list[str]:
    """What to print when a hardware node among `nodes` fails a check (none: ready).

    The failed and warned checks with their fixes, then one `error:` line; every launch
    path (`tactex launch`, and `ros2 launch` through the launch files) prints these.
    """
    checks = launch_checks(nodes)
    if not any(check.failed for check in checks):
        return []
    return [*lines([check for check in checks if check.status != OK]),
            'error: the hardware is not ready (fixes above; `tactex doctor` checks it all); '
            'launch with sim:=true to simulate it, or checks:=false to start the nodes anyway']


def ros_checks(env: Mapping[str, str] | None = None) -> list[Check]:
    """The ROS domain, discovery and middleware settings of `env` (default: this process's)."""
    env = os.environ if env is None else env
    checks = [_domain_check(env.get('ROS_DOMAIN_ID', '')), _discovery_check(env)]
    rmw = env.get('RMW_IMPLEMENTATION', '')
    checks.append(Check('ROS middleware', OK, f'{rmw or RMW + " (default)"}') if rmw in ('', RMW)
                  else Check('ROS middleware', FAIL, f'RMW_IMPLEMENTATION={rmw}, which this '
                             f'workspace does not install', f'unset it or set it to {RMW}'))
    profile = env.get('FASTDDS_DEFAULT_PROFILES_FILE', '')
    if profile and not Path(profile).is_file():
        checks.append(Check('Fast DDS profile', FAIL, f'FASTDDS_DEFAULT_PROFILES_FILE={profile} '
                            'is not a file', 'unset it (tactex uses config/fastdds_profile.xml)'))
    return checks


def _domain_check(value: str) -> Check:
    if not value:
        return Check('ROS domain', OK, "ROS_DOMAIN_ID unset: domain 0, every machine's default")
    if not value.isdigit() or int(value) > MAX_DOMAIN_ID:
        return Check('ROS domain', FAIL, f'ROS_DOMAIN_ID={value!r} is not a domain',
                     f'give a whole number 0..{SAFE_DOMAIN_IDS[-1]}, the same on every machine '
                     'of the robot')
    if int(value) not in SAFE_DOMAIN_IDS:
        return Check('ROS domain', WARN, f'ROS_DOMAIN_ID={value}: above '
                     f'{SAFE_DOMAIN_IDS[-1]} its ports may collide with the ephemeral ports',
                     f'use 0..{SAFE_DOMAIN_IDS[-1]}')
    return Check('ROS domain', OK, f'ROS_DOMAIN_ID={value}: every node and client must use it')


def _discovery_check(env: Mapping[str, str]) -> Check:
    found = env.get('ROS_AUTOMATIC_DISCOVERY_RANGE', '')
    if env.get('ROS_LOCALHOST_ONLY'):
        return Check('ROS discovery', WARN, 'ROS_LOCALHOST_ONLY is set, which Kilted ignores',
                     'use ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST')
    if found and found not in DISCOVERY_RANGES:
        return Check('ROS discovery', FAIL, f'ROS_AUTOMATIC_DISCOVERY_RANGE={found!r}',
                     f'give one of {", ".join(DISCOVERY_RANGES)}')
    if found == 'OFF' and not env.get('ROS_STATIC_PEERS'):
        return Check('ROS discovery', WARN, 'ROS_AUTOMATIC_DISCOVERY_RANGE=OFF and no '
                     'ROS_STATIC_PEERS: no node finds another, not even on this machine',
                     "use LOCALHOST (tactex launch's default, discovery:=localhost)")
    return Check('ROS discovery', OK, f'{found or "SUBNET (default)"}'
                 + (f', static peers {env["ROS_STATIC_PEERS"]}' if env.get('ROS_STATIC_PEERS')
                    else '') + '; tactex launch uses discovery:=localhost unless told')


def lines(checks: Sequence[Check]) -> list[str]:
    """`[ ok ] name: detail`, with `fix: ...` under each warning or failure."""
    out = []
    for check in checks:
        out.append(f'{MARKS.get(check.status, check.status)} {check.name}: {check.detail}')
        if check.fix and check.status != OK:
            out.append(f'       fix: {check.fix}')
    return out
