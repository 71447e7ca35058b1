# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The demo's stages: launch, probe, sweep and record, convert, train, classify, identify.

`Demo.run()` starts `launch/system.launch.py sim:=true` with the launcher (supervised
processes) and then talks to the nodes only through their interfaces
(`tactex.demo.session`): it probes the uneven surface (the `probe` action; the pathway
is broadcast on probe/pathway and probe/contacts), sweeps each texture along it while
sweep_node records (the `sweep` action with `record: true`; the texture is the bridge's
`patch_texture` parameter), converts the recordings (`tactex convert`), trains with
grouped and stratified cross-validation (`tactex train`), starts the system again with
the checkpoint and classifies fresh sweeps live through classifier_node
(texture/estimate). Identification (`tactex.demo.identification`) has its own sweeps:
each texture under the movements the pathway holds, recorded through the sweep action
apart from the others, converted and trained into a bundle (`tactex train --movements`);
the live system then runs identify_node too, and after the fixed sweeps one Identify goal
per texture chooses movements until its belief is confident. Its figures and thresholds
are `tactex.demo.figures`'.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager, redirect_stderr, redirect_stdout
from dataclasses import dataclass, replace
import json
import math
import os
from pathlib import Path
import random
import re
import shutil
import threading
import time

import numpy as np

from tactex.errors import CommandError
from tactex_common.environment import environment_set

SCENE = 'uneven_texture'
MODEL = 'extratrees'
WINDOW = 128
MARKER = '.tactex-demo'  # marks a folder the demo wrote (replaced by the next run)
STAGES = 10
NODE_START_S = 120.0  # wait for the action servers (a loaded machine starts them slowly)
PROBE_TIMEOUT_S = 900.0
SWEEP_TIMEOUT_S = 240.0
# Shallower draws of the scene's press depth (1.5 +- 0.4 mm) lose the crests of the wave
# for longer than sweep_node's contact_loss_tolerance where the probed surface is off by
# about a millimetre, and the node aborts the sweep.
MIN_PRESS_M = 0.0015
ATTEMPTS = 2  # an aborted probe or sweep goal is tried once more (both are reported)


@dataclass(frozen=True)
class Sizes:
    """How much the demo does."""

    sweeps: int  # recorded sweeps per texture
    live_sweeps: int  # fresh sweeps per texture classified live
    probe_span_m: float
    probe_step_m: float
    folds: int
    textures: tuple[str, ...] = ()  # () : all 12
    rate_factor: float = 1.0  # simulated seconds per wall second
    # Identification: the first movements of config/movements.yaml the pathway holds, each
    # texture swept under each this many times (the bundle's folds), then identified by
    # one Identify goal of at most `identify_budget` movements (the first
    # `identify_textures`; 0: all).
    identify_movements: int = 2
    identify_sweeps: int = 2
    identify_budget: int = 4
    identify_textures: int = 0

    @property
    def texture_names(self) -> list[str]:
        """The textures swept: those named, or all of them."""
        from tactex_sim.textures import TEXTURES
        return list(self.textures or TEXTURES)

    @property
    def identified_textures(self) -> list[str]:
        """The textures identified live: the first `identify_textures` (0: every one)."""
        return self.texture_names[:self.identify_textures or None]


# Simulated twice as fast as real time and at most 3 movements per Identify goal, so that
# the default run with identification keeps the demo's 15 minutes on two cores: in real
# time with 4 it took 24 min 17 s (docs/guides/quick-start.md). The nodes run on /clock,
# so the physics and every simulated second are the same; only the wall time shrinks.
DEFAULT = Sizes(sweeps=3, live_sweeps=1, probe_span_m=0.10, probe_step_m=0.01, folds=3,
                rate_factor=2.0, identify_budget=3)
# Four textures, two alike (the cotton weaves), so that the check can fail; simulated
# 1.5 times faster than real time (two idle cores keep up; the nodes run on /clock).
QUICK = Sizes(sweeps=2, live_sweeps=1, probe_span_m=0.06, probe_step_m=0.01, folds=2,
              textures=('ridged polymer', 'wood', 'open weave cotton', 'tight weave cotton'),
              rate_factor=1.5, identify_textures=3)
PROBE_START_X_M = 0.10
# Probe points 25 mm up: with the 20 mm approach the tilted tool clears the 8 mm wave's
# crests when it moves sideways between points (from 18 mm up it touched them).
PROBE_START_Z_M = 0.025
# Descend at 20 mm/s, not the node's default 5: bench/results/bench_probe.txt measures
# 1.07 deg and 0.25 mm mean errors there against 1.22 deg and 0.18 mm, far inside the
# demo's thresholds, in 63 % of the probing time.
PROBE_DESCENT_M_S = 0.02


@contextmanager
def demo_environment(folder: Path) -> Iterator[None]:
    """A ROS domain of the demo's own (no robot nearby hears it) and logs under --out."""
    with environment_set({'ROS_DOMAIN_ID': str(random.SystemRandom().randint(150, 232)),
                          'ROS_LOG_DIR': str(folder / 'logs' / 'ros'),
                          'ROS_AUTOMATIC_DISCOVERY_RANGE': 'LOCALHOST'}):
        yield


class Demo:
    """The stages, writing into `folder` (staged; moved to `out` when they succeed)."""

    def __init__(self, folder: Path, out: Path, sizes: Sizes, started: float) -> None:
        from tactex_sim.scene import load_scene, resolve_scene
        self.folder = folder
        self.out = out
        self.sizes = sizes
        self.started = started
        self.scene = load_scene(resolve_scene(SCENE))
        self.stage = 0
        self.launcher = None  # the running system's (see system())
        # Samples madgwick_node rejected, per launched system (None: its diagnostics unheard).
        self.madgwick_rejected: dict[str, int | None] = {}
        self.madgwick_bad_stamps: dict[str, int | None] = {}

    def say(self, line: str) -> None:
        """A progress line with the elapsed time."""
        print(f'[{time.monotonic() - self.started:6.0f} s] {line}', flush=True)

    def next_stage(self, line: str) -> None:
        """Announce the next stage."""
        self.stage += 1
        self.say(f'stage {self.stage}/{STAGES}: {line}')

    def run(self) -> tuple[dict, list]:
        """Every stage; the summary and its checks."""
        from tactex.demo.figures import checks
        from tactex.demo.identification import identification_summary
        textures = self.sizes.texture_names
        self.next_stage('launch the system in simulation (launch/system.launch.py sim:=true)')
        with self.system('collect') as (client, alive):
            probe = self.probe(client, alive)
            recorded = self.sweeps(client, alive, textures, self.sizes.sweeps, record=True,
                                   seed=0)
            movements = self.movement_sweeps(client, alive, probe['pathway'], textures,
                                             first_trial=len(recorded))
        data = self.convert()
        metrics = self.train(data)
        bundle = self.train_bundle(movements)
        self.next_stage(f'launch the system again with the checkpoint and the bundle; '
                        f'{self.sizes.live_sweeps} fresh sweep(s) per texture classified live '
                        'by classifier_node')
        with self.system('live', checkpoint=self.folder / 'train' / 'model',
                         identify=(bundle, movements)) as (client, alive):
            # The new probe_node has broadcast nothing: the goals carry the pathway.
            live = self.sweeps(client, alive, textures, self.sizes.live_sweeps, record=False,
                               seed=1, pathway=probe['pathway'])
            identified = self.identify(client, alive, probe['pathway'])
        self.next_stage('figures: summary.json and plots')
        summary = self.summarise(probe, recorded, live, metrics, textures)
        summary['identification'] = identification_summary(
            self.folder / 'identification.png', identified, summary['time_to_decision_s'])
        figures = checks(summary, probe['points'], len(textures),
                         self.scene.sweep.contact_s)
        summary['thresholds'] = {c.key: {'limit': c.limit, 'at_least': c.at_least,
                                         'passed': c.passed} for c in figures}
        finite = {k: None if isinstance(v, float) and not math.isfinite(v) else v
                  for k, v in summary.items()}  # JSON has no NaN
        (self.folder / 'summary.json').write_text(json.dumps(finite, indent=2) + '\n',
                                                  encoding='utf-8')
        return summary, figures

    # -- the launched system --------------------------------------------------------------
    @contextmanager
    def system(self, name: str, *, checkpoint: Path | None = None, client_type=None,
               respawn: tuple[str, ...] = (), identify: tuple[Path, Path] | None = None):
        """Launch system.launch.py sim:=true; yield a client and `alive()`; stop it after.

        `client_type` replaces SystemClient; the nodes named in `respawn` are restarted when
        they exit; `identify` (bundle, movement file) adds identify_node; the launcher is
        `self.launcher` meanwhile.
        """
        from tactex.demo.session import SystemClient
        from tactex.launching.spec import load_launch_file
        from tactex.launching.supervisor import Launcher

        values = {'sim': 'true', 'scene': SCENE, 'rate_factor': f'{self.sizes.rate_factor:g}',
                  'recording_root': str(self.folder / 'bags'),
                  'pathway_file': str(self.folder / 'pathway.json')}
        if checkpoint is not None:
            values['checkpoint'] = str(checkpoint)
        if identify is not None:
            values['bundle'], values['movements'] = (str(path) for path in identify)
        nodes = [replace(spec, respawn=spec.respawn or spec.name in respawn)
                 for spec in load_launch_file('system').node_specs(values)]
        log_path = self.folder / 'logs' / f'{name}.log'
        log_path.parent.mkdir(parents=True, exist_ok=True)
        with log_path.open('w', encoding='utf-8') as log:
            launcher = self.launcher = Launcher(nodes, out=log)
            shown = ' '.join(f'{k}:={v}'.replace(str(self.folder), str(self.out))
                             for k, v in values.items())
            self.say(f'  tactex launch system {shown}'
                     f' ({len(nodes)} nodes: {", ".join(n.name for n in nodes)}; ROS_DOMAIN_ID='
                     f'{os.environ.get("ROS_DOMAIN_ID")}; log logs/{name}.log)')
            stop = threading.Event()
            codes: list[int] = []
            launcher.start()
            watcher = threading.Thread(target=lambda: codes.append(
                launcher.supervise(until=stop.is_set)), daemon=True)
            watcher.start()
            try:
                with (client_type or SystemClient)() as client:
                    client.wait_ready(NODE_START_S, alive=watcher.is_alive)
                    if checkpoint is not None:
                        client.wait_classifier_ready(NODE_START_S, alive=watcher.is_alive)
                    if identify is not None:
                        client.wait_identify_ready(NODE_START_S, alive=watcher.is_alive)
                    yield client, watcher.is_alive
                    self.madgwick_rejected[name] = client.madgwick_rejected()
                    self.madgwick_bad_stamps[name] = client.madgwick_rejected(('dt',))
            except CommandError as err:
                raise CommandError(f'{err} ({_node_failure(log_path)})') from None
            finally:
                stop.set()
                watcher.join()
        if codes != [0]:
            raise CommandError(f'the {name} system stopped: {_node_failure(log_path)}')

    # -- stages ---------------------------------------------------------------------------
    def probe(self, client, alive) -> dict:
        """Probe the line; the broadcast contacts and their errors against the surface."""
        from tactex.demo.figures import pathway_errors
        from tactex.demo.session import ProbeAborted, ProbeLine
        from tactex_probe.messages import contact_arrays
        line = ProbeLine(PROBE_START_X_M, self.sizes.probe_span_m, self.sizes.probe_step_m,
                         start_z_m=PROBE_START_Z_M, descent_speed_m_s=PROBE_DESCENT_M_S)
        self.next_stage(f'probe {line.points} points from x = {1e3 * line.start_x_m:.0f} mm '
                        f'every {1e3 * line.step_m:.0f} mm (the probe action)')
        for attempt in range(1, ATTEMPTS + 1):
            try:
                result, pathway, contacts = client.probe(line, PROBE_TIMEOUT_S, alive)
                break
            except ProbeAborted as err:
                if attempt == ATTEMPTS:
                    raise CommandError(f'probing failed {ATTEMPTS} times: {err}') from None
                self.say(f'  probing aborted: {err}; trying again')
        positions, normals = contact_arrays(pathway)
        normal_deg, position_mm = pathway_errors(positions, normals, self.scene.surface)
        self.say(f'  {len(pathway.contacts)} of {line.points} probes gave a contact, broadcast '
                 f'on probe/pathway and probe/contacts ({len(contacts.poses)} poses); normal '
                 f'error {normal_deg.mean():.2f} deg, position error {position_mm.mean():.2f} mm'
                 ' (mean, against the true surface)')
        return {'points': line.points, 'attempts': attempt, 'pathway': pathway,
                'positions': positions,
                'normals': normals,
                'outcomes': list(result.outcomes), 'normal_deg': normal_deg,
                'position_mm': position_mm}

    def sweeps(self, client, alive, textures: list[str], per_texture: int, *, record: bool,
               seed: int, pathway=None) -> list:
        """Sweep every texture `per_texture` times (drawn speed, press and tilt).

        Without `pathway` the goals leave it empty: sweep_node sweeps the broadcast one.
        """
        from tactex.demo.session import SweepRun
        from tactex_sim.sweep import SweepParameters
        if record:
            self.next_stage(f'sweep each of the {len(textures)} textures {per_texture} times '
                            'along the pathway, recording (the sweep action, record: true)')
        rng = np.random.default_rng([self.scene.seed, seed])
        runs, total, began = [], len(textures) * per_texture, time.monotonic()
        for texture in textures:
            client.set_texture(texture, alive)
            for _ in range(per_texture):
                for attempt in range(ATTEMPTS):
                    drawn = SweepParameters.draw(self.scene, rng)  # a retry draws anew
                    run = client.sweep(SweepRun(texture, len(runs), drawn.speed_m_s),
                                       edge_offset_rad=drawn.edge_offset_rad,
                                       press_depth_m=max(drawn.press_depth_m, MIN_PRESS_M),
                                       record=record,
                                       timeout_s=SWEEP_TIMEOUT_S, alive=alive,
                                       pathway=pathway)
                    run.attempts = attempt + 1
                    if run.status_ok:
                        break
                    self.discard(run.result.recording_path)
                    self.say(f'  sweep {run.trial} ({texture}) {run.result.message}; its '
                             'recording is discarded')
                if not run.status_ok:
                    raise CommandError(f'sweep {run.trial} ({texture}) failed '
                                       f'{ATTEMPTS} times: {run.result.message}')
                runs.append(run)
                done = len(runs)
                left = (time.monotonic() - began) / done * (total - done)
                self.say(f'  [{done}/{total}] {_sweep_line(run)}  (about {left:.0f} s left)')
        return runs

    def discard(self, recording: str) -> None:
        """Remove an aborted sweep's recording (only one under this demo's bags/)."""
        path = Path(recording)
        if recording and path.is_dir() and (self.folder / 'bags') in path.parents:
            shutil.rmtree(path)

    def convert(self) -> Path:
        """`tactex convert` the recordings into windows."""
        from tactex.cli import main
        from tactex_classify.data.dataset import Dataset
        data = self.folder / 'dataset.npz'
        self.next_stage(f'convert the recordings (tactex convert bags --window {WINDOW})')
        self.command(['convert', str(self.folder / 'bags'), '--out', str(data),
                       '--window', str(WINDOW)], 'convert', main)
        dataset = Dataset.load(data)
        skipped = re.findall(r'skipped (.+)$', (self.folder / 'logs' / 'convert.log').read_text(
            encoding='utf-8'), re.MULTILINE)
        note = f'; {len(skipped)} recording(s) skipped, e.g. {skipped[0]}' if skipped else ''
        self.say(f'  {len(dataset.X)} windows of {WINDOW} samples from '
                 f'{len(np.unique(dataset.trial))} recordings at '
                 f'{dataset.info["sampling_rate_hz"]:.0f} Hz (dataset.npz){note}')
        return data

    def train(self, data: Path) -> dict:
        """`tactex train` with grouped and stratified CV, keeping the deployable model."""
        from tactex.cli import main
        self.next_stage(f'train {MODEL}, {self.sizes.folds}-fold CV grouped by recording and '
                        'stratified (tactex train)')
        self.command(['train', str(data), '--model', MODEL, '--folds', str(self.sizes.folds),
                       '--out', str(self.folder / 'train')], 'train', main)
        metrics = json.loads((self.folder / 'train' / 'metrics.json').read_text(
            encoding='utf-8'))
        grouped, stratified = (_accuracy(metrics, s) for s in ('grouped', 'stratified'))
        self.say(f'  accuracy {100 * grouped:.1f} % grouped by recording (honest), '
                 f'{100 * stratified:.1f} % stratified (leaky); report train/report.md')
        return {'grouped': grouped, 'stratified': stratified}

    def movement_sweeps(self, client, alive, pathway, textures: list[str], *,
                        first_trial: int) -> Path:
        """Each texture swept under the movements the pathway holds, recorded apart; their file.

        The recordings go to movement_bags/ (not the fixed sweeps' training data); the
        movements, the first `identify_movements` of config/movements.yaml that the pathway
        holds, are written to movements.yaml for the bundle and identify_node.
        """
        from tactex.demo.identification import fitting_movements, record_movement_sweeps
        from tactex.launching.spec import config_path
        from tactex_description.movements import load_movements, movements_yaml
        movements = fitting_movements(pathway, load_movements(config_path('movements.yaml')),
                                      self.sizes.identify_movements)
        path = self.folder / 'movements.yaml'
        path.write_text(movements_yaml(movements), encoding='utf-8')
        self.next_stage(f'sweep each texture under {len(movements.movements)} movements '
                        f'({", ".join(movements.names)}) {self.sizes.identify_sweeps} times on '
                        "each movement's part of the pathway, recording (for identification)")
        record_movement_sweeps(self, client, alive, pathway, movements, textures,
                               self.sizes.identify_sweeps, attempts=ATTEMPTS,
                               timeout_s=SWEEP_TIMEOUT_S, first_trial=first_trial,
                               keep=self.folder / 'movement_bags')
        return path

    def train_bundle(self, movements: Path) -> Path:
        """`tactex convert` the movement sweeps and `tactex train --movements` the bundle."""
        from tactex.cli import main
        from tactex_description.movements import load_movements
        data, run = self.folder / 'movement_dataset.npz', self.folder / 'identify'
        self.next_stage(f'train the identification bundle: {MODEL} per movement, calibrated '
                        'out of fold (tactex convert; tactex train --movements)')
        self.command(['convert', str(self.folder / 'movement_bags'), '--out', str(data),
                      '--window', str(load_movements(movements).window)], 'convert_movements',
                     main)
        self.command(['train', str(data), '--movements', str(movements), '--model', MODEL,
                      '--folds', str(self.sizes.identify_sweeps), '--out', str(run)],
                     'train_bundle', main)
        said = (self.folder / 'logs' / 'train_bundle.log').read_text(encoding='utf-8')
        for line in re.findall(r'^(\S+: .+ out of fold.+)$', said, re.MULTILINE):
            self.say(f'  {line}')
        return run / 'bundle'

    def identify(self, client, alive, pathway) -> list[dict]:
        """One Identify goal per texture identified, on `pathway`; the goals' rows."""
        from tactex.demo.identification import identify_each
        from tactex_classify.identification.selection import LIVE_DEFAULT
        textures = self.sizes.identified_textures
        self.next_stage(f'identify {len(textures)} textures: one Identify goal each '
                        f'({LIVE_DEFAULT}, at most {self.sizes.identify_budget} movements), '
                        'identify_node choosing the movements')
        return identify_each(self, client, alive, textures, pathway=pathway,
                             budget_movements=self.sizes.identify_budget)

    def command(self, argv: list[str], name: str, main) -> None:
        """Run a tactex subcommand with its output in logs/NAME.log."""
        log = self.folder / 'logs' / f'{name}.log'
        with log.open('w', encoding='utf-8') as stream, redirect_stdout(stream), \
                redirect_stderr(stream):
            code = main(argv)
        if code:
            errors = re.findall(r'^error: (.+)$', log.read_text(encoding='utf-8'), re.MULTILINE)
            raise CommandError(f'tactex {name} failed: {errors[-1] if errors else code}')

    def summarise(self, probe: dict, recorded: list, live: list, metrics: dict,
                  textures: list[str]) -> dict:
        """summary.json's figures, and the plots."""
        from tactex.demo import figures as report
        sweeps = [run.result for run in recorded]
        speed_errors = [abs(r.speed_mean - run.speed_m_s) / run.speed_m_s
                        for r, run in zip(sweeps, recorded, strict=True)]
        live_sweeps = [report.LiveSweep(run.label, tuple(run.estimates)) for run in live]
        figures = report.live_figures(live_sweeps)
        summary = {
            'contacts': len(probe['positions']),
            'probe_points': probe['points'],
            'probe_attempts': probe['attempts'],
            'normal_error_deg_mean': _mean(probe['normal_deg']),
            'position_error_mm_mean': _mean(probe['position_mm']),
            'contact_fraction': _mean([r.contact_fraction for r in sweeps]),
            'sliding_speed_error': _mean(speed_errors),
            'sweeps_recorded': len(recorded),
            'sweep_attempts': sum(run.attempts for run in (*recorded, *live)),
            'cv_accuracy_grouped': metrics['grouped'],
            'cv_accuracy_stratified': metrics['stratified'],
            'live_accuracy': figures['live_accuracy'],
            'live_sweeps': figures['live_sweeps'],
            'live_decided': figures['live_decided'],
            'time_to_decision_s': figures['time_to_decision_s'],
            'madgwick_rejected': _total(self.madgwick_rejected.values()),
            'madgwick_bad_stamps': _total(self.madgwick_bad_stamps.values()),
            'sizes': vars(self.sizes) | {'textures': textures, 'model': MODEL},
        }
        report.plot_pathway(self.folder / 'pathway.png', probe['positions'], probe['normals'],
                            self.scene.surface)
        report.plot_sweeps(self.folder / 'sweep.png', [(run.label, run.feedback)
                                                       for run in recorded],
                           report.path_length(probe['positions']), recorded[0].speed_m_s)
        report.plot_confusion(self.folder / 'confusion.png',
                              report.confusion(live_sweeps, textures), textures)
        longest = max((e.contact_s for s in live_sweeps for e in s.estimates), default=1.0)
        times = np.linspace(0.0, longest, 60)
        report.plot_accuracy_against_time(
            self.folder / 'accuracy_vs_contact_time.png', times,
            report.accuracy_against_contact_time(live_sweeps, times), 1 / len(textures))
        summary['wall_s'] = time.monotonic() - self.started
        return summary


def _total(counts) -> float:
    """The sum of `counts`; NaN when one is unknown (None) or there is none."""
    counts = list(counts)
    return math.nan if not counts or None in counts else float(sum(counts))


def _accuracy(metrics: dict, scheme: str) -> float:
    """A scheme's accuracy from tactex train's metrics.json."""
    try:
        return float(metrics['schemes'][scheme]['accuracy'])
    except (KeyError, TypeError, ValueError):
        raise CommandError(f'train/metrics.json has no {scheme} accuracy') from None


def _mean(values) -> float:
    values = np.asarray(values, dtype=float)
    return float(values.mean()) if values.size else float('nan')


def _sweep_line(run) -> str:
    result = run.result
    text = (f'{run.label} #{run.trial}: contact {100 * result.contact_fraction:.0f} %, speed '
            f'{1e3 * result.speed_mean:.1f} mm/s (asked {1e3 * run.speed_m_s:.1f})')
    if run.estimates:
        decided = [e for e in run.estimates if e.decided]
        final = decided[0] if decided else run.estimates[-1]
        text += (f'; classified {final.label!r} '
                 f'{"after" if decided else "undecided after"} {final.contact_s:.1f} s')
    return text


def _node_failure(log_path: Path) -> str:
    """The launcher's error line of a log; the failed node's last lines go to stdout.

    The log itself is removed with the rest of the unfinished --out, so what it says about
    the failure is shown here.
    """
    text = log_path.read_text(encoding='utf-8', errors='replace') if log_path.exists() else ''
    found = re.findall(r'\[launch\] error: node (\S+) (.+)', text)
    if not found:
        return 'no node reported an error'
    name, what = found[-1]
    lines = [line for line in text.splitlines() if line.startswith(f'[{name}] ')]
    print(f'last lines of {name}:', *lines[-15:], sep='\n  ', flush=True)
    return f'node {name} {what}'


