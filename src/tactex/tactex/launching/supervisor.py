# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Run a launch file's node set as supervised processes, where ROS 2 launch is not installed.

Every node runs with the tactex middleware settings and the launch file's discovery
range; its output lines are prefixed with its name. A node that exits is restarted when
it asked for `respawn`; otherwise the launcher stops the others and reports it. SIGINT,
SIGTERM or SIGHUP stops every node: SIGINT first (rclpy shuts down cleanly and bags are closed),
SIGTERM after `grace_s`, SIGKILL before `kill_after_s`. The children are also told by the
kernel to exit if the launcher itself is killed (Linux parent-death signal).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
import ctypes
from dataclasses import dataclass
import json
import os
from pathlib import Path
import shutil
import signal
import subprocess
import sys
import threading
import time
from typing import Any, TextIO

from tactex.launching.environment import ros_environment
from tactex.launching.spec import DISCOVERY_RANGE, LaunchError, NodeSpec
from tactex_common.stopping import on_stop_signals

_PR_SET_PDEATHSIG = 1


def find_executable(package: str, executable: str) -> str:
    """Path of a node's console script: colcon's lib/<package>/, else beside this Python.

    Raises:
        LaunchError: not installed; the message says how to install it.
    """
    for prefix in filter(None, os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep)):
        candidate = Path(prefix) / 'lib' / package / executable
        if candidate.is_file():
            return str(candidate)
    candidate = Path(sys.executable).parent / executable
    if candidate.is_file():
        return str(candidate)
    found = shutil.which(executable)
    if found:
        return found
    fix = ('install the workspace (make test, or colcon build and source it)'
           if package.startswith('tactex') else 'it comes with a full ROS 2 install: source it')
    raise LaunchError(f'cannot find the executable {executable!r} of package {package!r}; {fix}')


def _yaml_value(value: Any) -> str:
    """A parameter value as `-p name:=value` spells it (YAML).

    Text of several lines (a URDF) and empty text are quoted (a JSON string is a YAML
    string), so they stay text (rcl refuses `-p name:=`); a one-line string is YAML-typed,
    as ros2 launch types it.
    """
    if isinstance(value, str) and ('\n' in value or not value):
        return json.dumps(value)
    if isinstance(value, bool):
        return 'true' if value else 'false'
    if isinstance(value, (list, tuple)):
        return '[' + ', '.join(_yaml_value(v) for v in value) + ']'
    return str(value)


def node_command(spec: NodeSpec, namespace: str = '') -> list[str]:
    """The command line that starts `spec` (name, namespace, parameters, remappings)."""
    command = [find_executable(spec.package, spec.executable), *spec.arguments, '--ros-args',
               '-r', f'__node:={spec.name}']
    if namespace:
        command += ['-r', f'__ns:=/{namespace.strip("/")}']
    for parameters in spec.parameters:
        if isinstance(parameters, Mapping):
            for name, value in parameters.items():
                command += ['-p', f'{name}:={_yaml_value(value)}']
        else:
            command += ['--params-file', str(parameters)]
    for source, target in spec.remappings:
        command += ['-r', f'{source}:={target}']
    return command


def _prepare_child() -> None:
    """In the child: die with the launcher; ignore SIGINT until the node takes it over.

    The kernel sends SIGTERM when the launcher dies, even by SIGKILL. A node still
    importing when the launch stops (another node failed at start) would print a
    KeyboardInterrupt traceback on SIGINT; ignored, the SIGTERM that follows `grace_s`
    later ends it quietly. A node's own handlers (tactex_common.ros.spin, rclcpp) take
    SIGINT over once it runs.
    """
    libc = ctypes.CDLL(None, use_errno=True)
    libc.prctl(_PR_SET_PDEATHSIG, signal.SIGTERM)
    signal.signal(signal.SIGINT, signal.SIG_IGN)


@dataclass
class _Running:
    spec: NodeSpec
    process: subprocess.Popen
    restarts: int = 0


class Launcher:
    """Start, watch and stop a node set.

    Args:
        nodes: what to run.
        namespace: applied to every node.
        discovery: 'localhost' or 'subnet' (ROS_AUTOMATIC_DISCOVERY_RANGE).
        out: where the prefixed output lines go.
        grace_s: how long nodes get to exit after SIGINT before SIGTERM.
        kill_after_s: when a node still running is killed (SIGKILL).
    """

    def __init__(self, nodes: Sequence[NodeSpec], *, namespace: str = '',
                 discovery: str = 'localhost', out: TextIO = sys.stdout, grace_s: float = 3.0,
                 kill_after_s: float = 4.5) -> None:
        if discovery not in DISCOVERY_RANGE:
            raise LaunchError(f'discovery must be one of {", ".join(DISCOVERY_RANGE)}, '
                              f'got {discovery!r}')
        names = [spec.name for spec in nodes]
        if len(set(names)) != len(names):
            raise LaunchError(f'node names must be unique, got {names}')
        self._specs = list(nodes)
        self._commands = {spec.name: node_command(spec, namespace) for spec in nodes}
        env = ros_environment()
        env['ROS_AUTOMATIC_DISCOVERY_RANGE'] = DISCOVERY_RANGE[discovery]
        env['PYTHONUNBUFFERED'] = '1'
        self._env = env
        self._out = out
        self._out_lock = threading.Lock()
        self._grace_s = grace_s
        self._kill_after_s = kill_after_s
        self._running: dict[str, _Running] = {}
        self._stopping = threading.Event()
        self._readers: list[threading.Thread] = []

    @property
    def pids(self) -> dict[str, int]:
        """Process id of each running node."""
        return {name: r.process.pid for name, r in self._running.items()}

    def _say(self, line: str) -> None:
        with self._out_lock:
            self._out.write(line if line.endswith('\n') else line + '\n')
            self._out.flush()

    def _start(self, spec: NodeSpec) -> subprocess.Popen:
        process = subprocess.Popen(self._commands[spec.name], env=self._env,
                                   stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                   stderr=subprocess.STDOUT, text=True, errors='replace',
                                   preexec_fn=_prepare_child)
        reader = threading.Thread(target=self._copy_output, args=(spec.name, process),
                                  daemon=True)
        reader.start()
        self._readers.append(reader)
        self._say(f'[launch] started {spec.name} (pid {process.pid})')
        return process

    def _copy_output(self, name: str, process: subprocess.Popen) -> None:
        for line in process.stdout:
            self._say(f'[{name}] {line.rstrip()}')

    def start(self) -> None:
        """Start every node."""
        for spec in self._specs:
            self._running[spec.name] = _Running(spec, self._start(spec))

    def request_stop(self) -> None:
        """Ask `supervise` to shut everything down (safe from a signal handler)."""
        self._stopping.set()

    def supervise(self, *, poll_s: float = 0.1,
                  until: Callable[[], bool] = lambda: False) -> int:
        """Watch the nodes until a stop is requested, `until()` holds, or a node dies.

        Returns:
            0 after a requested stop; 1 when a node exited without `respawn`.
        """
        failure = ''
        while not self._stopping.is_set() and not until():
            for name, running in self._running.items():
                code = running.process.poll()
                if code is None:
                    continue
                if running.spec.respawn:
                    self._say(f'[launch] {name} exited with code {code}; respawning in '
                              f'{running.spec.respawn_delay_s:g} s')
                    if self._stopping.wait(running.spec.respawn_delay_s):
                        break
                    running.process = self._start(running.spec)
                    running.restarts += 1
                else:
                    failure = f'node {name} exited with code {code}'
                    break
            if failure:
                break
            self._stopping.wait(poll_s)
        self.stop()
        if failure:
            self._say(f'[launch] error: {failure}; stopped the others')
            return 1
        return 0

    def stop(self) -> None:
        """SIGINT every node, then SIGTERM after grace_s, SIGKILL before kill_after_s."""
        started = time.monotonic()
        for signal_number, deadline in ((signal.SIGINT, self._grace_s),
                                        (signal.SIGTERM, self._kill_after_s),
                                        (signal.SIGKILL, self._kill_after_s + 1.0)):
            alive = [r.process for r in self._running.values() if r.process.poll() is None]
            for process in alive:
                try:
                    process.send_signal(signal_number)
                except ProcessLookupError:
                    pass
            while alive and time.monotonic() - started < deadline:
                alive = [p for p in alive if p.poll() is None]
                time.sleep(0.02)
            if not alive:
                break
        for reader in self._readers:
            reader.join(timeout=1.0)

    def restarts(self, name: str) -> int:
        """How often `name` was respawned."""
        return self._running[name].restarts


def run_launch(nodes: Sequence[NodeSpec], values: Mapping[str, str], *,
               out: TextIO = sys.stdout) -> int:
    """Run a node set until SIGINT, SIGTERM or SIGHUP (exit 0) or a node dies (exit 1)."""
    launcher = Launcher(nodes, namespace=values.get('namespace', ''),
                        discovery=values.get('discovery', 'localhost'), out=out)
    with on_stop_signals(lambda _signum: launcher.request_stop()):
        try:
            launcher.start()
            return launcher.supervise()
        finally:
            launcher.stop()
