# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Soak test: the launched system in simulation for M minutes, with a fault every period.

`launch/system.launch.py sim:=true` runs through the launcher with a checkpoint (given,
or trained first from a few `tactex sim collect` sweeps), as `tactex demo` runs it, and
this script drives it only through its interfaces: each loop probes a short line, then
sweeps it SWEEPS_PER_PROBE times recording bags while classifier_node classifies live (a
loop whose probe fails sweeps the last probed pathway). It loops for --minutes and on
until every scheduled fault was played (at most half as long again).

Every period (default 60 s) one fault is injected, in rotation (`--faults` picks the
kinds): sensor unplug (the tactile topics stop), CRC burst (NaN tactile samples), servo
silence (joint_states stop), each for FAULT_S seconds through the bridge's `fault`
parameter, madgwick_node killed with SIGKILL (the launcher respawns it), then the live
stream's faults (tactex_sim.faults: overflow, clock jump, burst, stamp jitter, frozen,
saturated), those that spoil windows played over a whole sweep (from its goal to its
result). A fault is recovered from when the silenced stream carries a finite sample
again, the killed node runs again and is back on the graph, or, for a live-stream fault,
classifier_node has counted it and its diagnostics are OK again.

Reported: windows expected (cut by classifier_node) / classified / counted as dropped /
skipped for a fault, summed over the classifier's lives, beside the windows `tactex
convert` cuts from the recordings afterwards (a cross-check); decided estimates per 10
minutes; bags written / readable (every message of every recording read back and
decoded); resident memory of every node, sampled every 5 s, and its growth per hour
(least squares, each process's first minute left out). Exit 1 on any unaccounted loss:
expected != classified + dropped + skipped, an unreadable bag, a fault not injected or
not recovered from, or a node that died for good. Writes --out (default out/soak; an
existing non-empty folder is refused): summary.json, table.txt, memory.png, the node
logs and the recordings.

    nice .venv/bin/python bench/soak.py --minutes 60
"""

from __future__ import annotations

import argparse
from contextlib import contextmanager
from dataclasses import replace
import json
import os
from pathlib import Path
import queue
import signal
import sys
import threading
import time

import numpy as np

from tactex.cli import CommandParser, guarded
from tactex.cli import main as tactex
from tactex.demo.pipeline import (
    DEFAULT,
    Demo,
    demo_environment,
    MIN_PRESS_M,
    PROBE_START_X_M,
    PROBE_START_Z_M,
    WINDOW,
)
from tactex.errors import CommandError
from tactex.options import check_output_folder, number, staged_folder
from tactex.soak import bookkeeping as soak
from tactex_common import topics
from tactex_common.stopping import raise_on_stop_signals

KILLED = 'madgwick_node'  # restarted by the launcher (respawn) after SIGKILL
PROBE_SPAN_M = 0.04  # five probe points: a sweep long enough for a few 1 s windows
TEXTURES = ('wood', 'ridged polymer')  # the trained checkpoint's classes, swept in turn
FAULT_S = 3.0  # how long a stream fault lasts
RECOVERY_S = 30.0  # a fault not recovered from within this long after it ends is a loss
RSS_PERIOD_S = 5.0
MAX_MINUTES = 7 * 24 * 60
WARMUP_S = 60.0  # each process's first minute is left out of its memory growth fit
PROBE_TIMEOUT_S = 300.0
SWEEP_TIMEOUT_S = 120.0
SILENCED = {'sensor_unplug': topics.IMU_RAW, 'crc_burst': topics.IMU_RAW,
            'servo_silence': topics.JOINT_STATES}
# Live-stream faults: the classifier counters that count each (any one of them).
COUNTED_BY = {'overflow': ('faults_invalid',),
              'clock_jump': ('faults_resyncs', 'faults_off_timeline'),
              'burst': ('faults_refused', 'faults_resyncs'), 'stamp_jitter': (),
              'frozen': ('faults_frozen',), 'saturated': ('faults_saturated',)}
IN_SWEEP = ('burst', 'frozen', 'saturated')  # spoil windows: played over a whole sweep
SWEEP_WAIT_S = 240.0  # two loops
SWEEPS_PER_PROBE = 3  # sweeps of each probed pathway, the textures in turn
# The loop runs on past --minutes until every scheduled fault was played (a fault that
# spoils windows waits for a sweep), up to this factor of the minutes.
MAX_OVERRUN = 1.5


def parse(argv: list[str] | None) -> argparse.Namespace:
    """The command line."""
    parser = CommandParser(prog='bench/soak.py', description=__doc__.split('\n\n')[0])
    parser.add_argument('--minutes', type=number(at_most=MAX_MINUTES), required=True,
                        help=f'how long to loop, at most {MAX_MINUTES} (a week); faults are '
                             'injected within it')
    parser.add_argument('--out', type=Path, default=Path('out/soak'),
                        help='new folder for the summary, table, plot, logs and bags')
    parser.add_argument('--checkpoint', type=Path, default=None,
                        help=f'RUN/model of tactex train over {", ".join(TEXTURES)} '
                             '(default: train one first from 4 simulated sweeps)')
    parser.add_argument('--fault-period', type=number(at_least=10.0), default=60.0,
                        help='seconds between faults (default 60)')
    parser.add_argument('--faults', type=fault_kinds, default=soak.FAULTS,
                        help=f'comma-separated kinds, in rotation (default all: '
                             f'{",".join(soak.FAULTS)})')
    parser.add_argument('--rate-factor', type=number(at_most=10.0), default=1.0,
                        help='simulated seconds per wall second (default 1)')
    return parser.parse_args(argv)


def fault_kinds(text: str) -> tuple[str, ...]:
    """`--faults`: known kinds, comma-separated (argparse turns ValueError into an error)."""
    kinds = tuple(kind.strip() for kind in text.split(','))
    unknown = [kind for kind in kinds if kind not in soak.FAULTS]
    if unknown or not kinds:
        raise argparse.ArgumentTypeError(f'unknown fault {", ".join(unknown)!s}; the kinds are '
                                         f'{",".join(soak.FAULTS)}')
    return kinds


class Soak:
    """One soak run inside `demo`'s folder."""

    def __init__(self, demo: Demo, minutes: float, period_s: float,
                 kinds: tuple[str, ...] = soak.FAULTS) -> None:
        self.demo, self.minutes = demo, minutes
        self.schedule = soak.fault_schedule(minutes * 60, period_s, kinds)
        self.faults: list[soak.FaultRecord] = []
        self.memory: dict[str, list[tuple[float, int]]] = {}
        self.counts = dict.fromkeys(('loops', 'probes_sent', 'probes_ok', 'sweeps_sent',
                                     'sweeps_ok'), 0)
        self.done = threading.Event()
        self.looped = threading.Event()  # the loop has ended: no sweep will come
        # A fault that spoils windows, handed from the injector to the loop's next sweep,
        # and back: when it was cleared and how long it played.
        self._sweep_fault: queue.Queue[str] = queue.Queue()
        self._sweep_fault_played: queue.Queue[tuple[float, str]] = queue.Queue()
        self.started = 0.0

    def elapsed(self) -> float:
        """Seconds since the system was up."""
        return time.monotonic() - self.started

    def checkpoint(self) -> Path:
        """Train a small checkpoint from simulated sweeps of TEXTURES (tactex commands)."""
        folder = self.demo.folder
        (folder / 'logs').mkdir()
        self.demo.say(f'training a checkpoint: tactex sim collect {len(TEXTURES)} textures x 2 '
                      'sweeps, convert, train extratrees')
        self.demo.command(['sim', 'collect', '--sweeps', '2', '--textures', *TEXTURES,
                            '--out', str(folder / 'train_bags')], 'collect', tactex)
        self.demo.command(['convert', str(folder / 'train_bags'), '--out',
                            str(folder / 'train.npz'), '--window', str(WINDOW)], 'convert',
                          tactex)
        self.demo.command(['train', str(folder / 'train.npz'), '--model', 'extratrees',
                            '--folds', '2', '--cv', 'grouped', '--out', str(folder / 'train')],
                           'train', tactex)
        return folder / 'train' / 'model'

    def run(self, checkpoint: Path) -> dict:
        """Loop until the minutes are up; the summary."""
        from tactex.soak.session import SoakClient
        with self.demo.system('soak', checkpoint=checkpoint, client_type=SoakClient,
                              respawn=(KILLED,)) as (client, alive):
            self.started = time.monotonic()
            workers = [threading.Thread(target=self._sample_memory, daemon=True),
                       threading.Thread(target=self._inject_faults, args=(client, alive),
                                        daemon=True)]
            for worker in workers:
                worker.start()
            try:
                self._loop(client, alive)
            finally:
                self.looped.set()
            workers[1].join()
            self._settle(client)
            windows, lives = client.windows()
            decisions = [t - self.started for t in client.decisions]
            self.done.set()
            workers[0].join()
        return self._summary(windows, lives, decisions) | self._windows_in_bags()

    def _windows_in_bags(self) -> dict:
        """What `tactex convert` cuts from the recordings: a cross-check, not accounted.

        The live count is larger by the windows of probe contacts (not recorded).
        """
        from tactex_classify.data.dataset import Dataset
        data = self.demo.folder / 'bag_windows.npz'
        try:
            self.demo.command(['convert', str(self.demo.folder / 'bags'), '--out', str(data),
                               '--window', str(WINDOW)], 'convert_bags', tactex)
        except CommandError as err:
            return {'windows_in_bags': 0, 'windows_in_bags_note': str(err)}
        return {'windows_in_bags': len(Dataset.load(data).X), 'windows_in_bags_note': ''}

    def _loop(self, client, alive) -> None:
        from tactex.demo.session import ProbeLine, SweepRun
        from tactex_sim.sweep import SweepParameters
        line = ProbeLine(PROBE_START_X_M, PROBE_SPAN_M, DEFAULT.probe_step_m,
                         start_z_m=PROBE_START_Z_M)
        rng = np.random.default_rng(self.demo.scene.seed)
        pathway = None  # the newest probed pathway: swept again when a probe fails
        while self.elapsed() < self.minutes * 60 or self._faults_to_come():
            loop = self.counts['loops'] = self.counts['loops'] + 1
            notes = []
            try:
                self.counts['probes_sent'] += 1
                try:
                    _, pathway, _ = client.probe(line, PROBE_TIMEOUT_S, alive)
                    self.counts['probes_ok'] += 1
                except CommandError as err:
                    if pathway is None or not alive():
                        raise
                    notes.append(f'probe failed ({err}), the last pathway swept')
                for _ in range(SWEEPS_PER_PROBE):
                    trial = self.counts['sweeps_sent'] = self.counts['sweeps_sent'] + 1
                    texture = TEXTURES[trial % len(TEXTURES)]
                    client.set_texture(texture, alive)
                    drawn = SweepParameters.draw(self.demo.scene, rng)
                    with self._fault_over_sweep(client, alive):
                        run = client.sweep(SweepRun(texture, trial, drawn.speed_m_s),
                                           edge_offset_rad=drawn.edge_offset_rad,
                                           press_depth_m=max(drawn.press_depth_m,
                                                             MIN_PRESS_M),
                                           record=True, timeout_s=SWEEP_TIMEOUT_S,
                                           alive=alive, pathway=pathway)
                    self.counts['sweeps_ok'] += run.status_ok
                    notes.append(f'sweep {texture}: ' + (
                        run.result.message or
                        f'{100 * run.result.contact_fraction:.0f} % in contact') +
                        f', {len(run.estimates)} estimates')
                note = '; '.join(notes)
            except CommandError as err:  # an aborted or lost goal: the next loop tries again
                if not alive():
                    raise
                note = f'{"sweep" if pathway else "probe"} failed: {err}'
                time.sleep(1.0)  # a fault still playing fails the next goal at once too
            windows, lives = client.windows()
            self.demo.say(f'loop {loop}: {note}; windows {windows["windows_cut"]} expected, '
                          f'{windows["windows_classified"]} classified, '
                          f'{windows["windows_dropped"]} dropped; faults '
                          f'{len(self.faults)}/{len(self.schedule)}')

    @contextmanager
    def _fault_over_sweep(self, client, alive):
        """Play a fault the injector handed over (if any) from goal to result of a sweep."""
        try:
            fault = self._sweep_fault.get_nowait()
        except queue.Empty:
            yield
            return
        client.set_bridge_parameter('fault', fault, alive)
        started = time.monotonic()
        try:
            yield
        finally:
            client.set_bridge_parameter('fault', '', alive)
            cleared = time.monotonic()
            self._sweep_fault_played.put((cleared, f'{cleared - started:.1f} s over a sweep'))

    def _faults_to_come(self) -> bool:
        """Whether scheduled faults are still to be played (within the overrun allowed)."""
        return (len(self.faults) < len(self.schedule)
                and self.elapsed() < self.minutes * 60 * MAX_OVERRUN)

    def _inject_faults(self, client, alive) -> None:
        for at_s, fault in self.schedule:
            while self.elapsed() < at_s:
                time.sleep(0.2)
            self.demo.say(f'fault at {self.elapsed():.0f} s: {fault}')
            try:
                record = (self._kill(client, at_s) if fault == 'node_kill'
                          else self._live_fault(client, alive, at_s, fault)
                          if fault in COUNTED_BY
                          else self._stream_fault(client, alive, at_s, fault))
            except CommandError as err:
                record = soak.FaultRecord(at_s, fault, False, str(err))
            self.faults.append(record)
            self.demo.say(f'  {fault}: {"recovered" if record.recovered else "NOT recovered"}'
                          f' ({record.detail})')

    def _stream_fault(self, client, alive, at_s: float, fault: str) -> soak.FaultRecord:
        client.set_bridge_parameter('fault', fault, alive)
        time.sleep(FAULT_S)
        client.set_bridge_parameter('fault', '', alive)
        cleared = time.monotonic()
        back = _within(RECOVERY_S, lambda: client.heard_since(SILENCED[fault], cleared))
        return soak.FaultRecord(at_s, fault, back is not None,
                                f'{SILENCED[fault]} silent or bad for {FAULT_S:g} s; ' +
                                (f'back {back:.1f} s after' if back is not None else
                                 f'still silent {RECOVERY_S:g} s after'))

    def _live_fault(self, client, alive, at_s: float, fault: str) -> soak.FaultRecord:
        before, _ = client.windows()
        if fault in IN_SWEEP:  # the loop plays it over its next sweep
            self._sweep_fault.put(fault)
            # Taken by a sweep (the queue is empty again), or no sweep will come.
            _within(SWEEP_WAIT_S, lambda: self._sweep_fault.empty() or self.looped.is_set())
            try:
                self._sweep_fault.get_nowait()  # not taken by a sweep: withdrawn
                return soak.FaultRecord(at_s, fault, False, f'no sweep ran within '
                                        f'{SWEEP_WAIT_S:g} s to play it in')
            except queue.Empty:  # taken: played over the sweep under way
                cleared, played = self._sweep_fault_played.get(timeout=SWEEP_TIMEOUT_S + 30)
        else:
            client.set_bridge_parameter('fault', fault, alive)
            time.sleep(FAULT_S)
            client.set_bridge_parameter('fault', '', alive)
            cleared, played = time.monotonic(), f'{FAULT_S:g} s'
        counters = COUNTED_BY[fault]

        def counted() -> str:
            after, _ = client.windows()
            return ', '.join(f'{after[c] - before[c]} {c.removeprefix("faults_")}'
                             for c in counters if after[c] > before[c])
        back = _within(RECOVERY_S, lambda: (counted() or not counters)
                       and client.classifier_ok_since(cleared))
        return soak.FaultRecord(at_s, fault, back is not None, (
            f'played {played}; counted: {counted() or "nothing"}; ' +
            (f'diagnostics OK {back:.1f} s after' if back is not None else
             f'not counted and OK {RECOVERY_S:g} s after')))

    def _kill(self, client, at_s: float) -> soak.FaultRecord:
        launcher = self.demo.launcher
        before, pid = launcher.restarts(KILLED), launcher.pids[KILLED]
        os.kill(pid, signal.SIGKILL)
        back = _within(RECOVERY_S, lambda: launcher.restarts(KILLED) > before
                       and client.on_graph(KILLED))
        return soak.FaultRecord(at_s, 'node_kill', back is not None, (
            f'{KILLED} (pid {pid}) killed; ' + (
                f'respawned as pid {launcher.pids[KILLED]}, on the graph {back:.1f} s after'
                if back is not None else f'not back {RECOVERY_S:g} s after')))

    def _sample_memory(self) -> None:
        while not self.done.wait(0 if not self.memory else RSS_PERIOD_S):
            launcher = self.demo.launcher
            for name, pid in launcher.pids.items():
                rss = soak.rss_bytes(pid)
                life = f'{name} (life {launcher.restarts(name) + 1})' if name == KILLED else name
                if rss is not None:
                    self.memory.setdefault(life, []).append((self.elapsed(), rss))

    def _settle(self, client) -> None:
        """Wait for the classifier's counters to agree (its windows in flight), up to 10 s."""
        def agreed() -> bool:
            w, _ = client.windows()
            return w['windows_cut'] == soak.windows_accounted(w)
        time.sleep(2.0)  # a diagnostics period after the last sweep
        _within(10.0, agreed)

    def _summary(self, windows: dict, lives: int, decisions: list[float]) -> dict:
        bags = sorted(p for p in (self.demo.folder / 'bags').glob('*') if p.is_dir())
        unreadable = {p.name: why for p in bags if (why := soak.read_back(p))}
        memory = soak.memory_report(self.memory, warmup_s=WARMUP_S)
        summary = {'minutes': self.minutes, **self.counts, 'windows': windows,
                   'classifier_lives': lives, 'bags_written': len(bags),
                   'decisions_per_10_min': soak.per_period(decisions, 600.0,
                                                           self.elapsed()),
                   'bags_readable': len(bags) - len(unreadable), 'unreadable': unreadable,
                   'faults': [vars(f) for f in self.faults],
                   'faults_scheduled': len(self.schedule), 'memory': memory,
                   'wall_s': time.monotonic() - self.demo.started}
        summary['losses'] = soak.losses(windows, len(bags), summary['bags_readable'],
                                        self.faults, len(self.schedule))
        return summary


def _within(timeout_s: float, condition) -> float | None:
    """Seconds until `condition()` held, polled every 0.1 s (None: not within timeout_s)."""
    started = time.monotonic()
    while time.monotonic() - started < timeout_s:
        if condition():
            return time.monotonic() - started
        time.sleep(0.1)
    return None


def run(args: argparse.Namespace) -> int:
    """Train (if needed), soak, write the report; 1 on any unaccounted loss."""
    out = check_output_folder(args.out)
    checkpoint = args.checkpoint
    if checkpoint is not None and not (checkpoint / 'checkpoint.json').is_file():
        raise CommandError(f'--checkpoint {checkpoint}: no checkpoint.json there; give the '
                           'model/ folder of a tactex train run')
    started = time.monotonic()
    with staged_folder(out) as folder, demo_environment(folder):
        demo = Demo(folder, out, replace(DEFAULT, rate_factor=args.rate_factor), started)
        job = Soak(demo, args.minutes, args.fault_period, args.faults)
        summary = job.run(checkpoint.resolve() if checkpoint else job.checkpoint())
        (folder / 'summary.json').write_text(json.dumps(summary, indent=2) + '\n',
                                             encoding='utf-8')
        (folder / 'table.txt').write_text(soak.table(summary), encoding='utf-8')
        soak.plot_memory(folder / 'memory.png', job.memory, job.faults)
    print(f'\nsoak summary ({out}/summary.json, table.txt, memory.png):')
    print(soak.table(summary), end='')
    return 1 if summary['losses'] else 0


def main(argv: list[str] | None = None) -> int:
    """Entry point: one `error:` line and exit code 1 on bad input, 128+n on a signal."""
    raise_on_stop_signals()
    args = parse(argv)
    return guarded(lambda: run(args))


if __name__ == '__main__':
    sys.exit(main())
