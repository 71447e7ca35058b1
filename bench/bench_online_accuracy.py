# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Accuracy against contact time of classifier_node on held-out simulated sweeps, fed live.

Simulated sweeps over the 12 textures (`uneven_texture`, 120 Hz) are collected twice,
with different seeds: one set trains the model (`tactex convert` windows of 128, hop
64), the other is held out; a deep model trains as bench_textures.py trains it (the
`modern` profile, per-window scaling, at most 80 epochs). Each held-out bag is played to
a running classifier_node as it was recorded (its CDR bytes on the raw tactile topics,
sweep/active, and /clock, the node on simulated time), faster than real time. The node
runs with threshold 1 (it never decides, so it publishes the evidence of every window);
the decision a node with threshold t makes is its first estimate whose confidence
exceeds t, identical up to that window (a second node run live at the default threshold
checks this sweep by sweep). A sweep with no such estimate is decided at its end (as
TEASER forces a decision).

Per threshold: accuracy of the decisions, median contact seconds at decision, earliness
(the share of the sweep's windowed contact used), and the harmonic mean of accuracy and
1 - earliness (TEASER, Schafer & Leser 2020); the same for deciding from the first window
and from the whole sweep. The reference, in the same run: the converter's windows of the
held-out bags classified offline by the same model (window accuracy and whole-recording
decisions by summed log-probabilities).
"""

from __future__ import annotations

import argparse
from dataclasses import replace
import json
import os
from pathlib import Path
import random
import subprocess
import sys
import tempfile
import time

import numpy as np

from tactex.launching.environment import ros_environment

BIN = Path(sys.executable).parent
RESULTS = Path(__file__).parent / 'results'
WINDOW, HOP = 128, 64
THRESHOLDS = (0.5, 0.7, 0.9, 0.95, 0.99, 0.999, 0.9999, 1 - 1e-5, 1 - 1e-6, 1 - 1e-8)
DEFAULT_THRESHOLD = 0.99
FLAG_SETTLE_S = 0.05  # the nodes drain their queues around each sweep/active message
FED_TOPICS = ('imu', 'mag', 'pressure', 'active')
# The nodes' diagnostics counters kept beside the measures (with every faults_* value).
COUNTERS = ('windows_cut', 'windows_classified', 'windows_dropped', 'samples_late',
            'samples_dropped', 'resets')


def collect_sets(scratch: Path, train_sweeps: int, test_sweeps: int) -> tuple[Path, Path]:
    """Training and held-out bags (the held-out scene has another seed)."""
    from tactex_sim.collect import collect
    from tactex_sim.scene import load_scene, resolve_scene
    scene = load_scene(resolve_scene('uneven_texture'))
    started = time.monotonic()

    def progress(line: str) -> None:
        print(f'[{time.monotonic() - started:6.0f} s] {line}', flush=True)
    collect(scene, train_sweeps, scratch / 'train', progress=progress)
    collect(replace(scene, seed=scene.seed + 1000), test_sweeps, scratch / 'test',
            progress=progress)
    return scratch / 'train', scratch / 'test'


def train(model: str, train_bags: Path, folder: Path, epochs: int, profile: str,
          scaling: str) -> Path:
    """Convert the training bags and fit the model on every window; its checkpoint.

    A deep model trains with `profile` and `scaling` (early stopping, where the profile
    has it, on training recordings held out of the fit).
    """
    from tactex_classify.data.dataset import convert
    from tactex_classify.training.deep_classifier import TrainingConfig
    from tactex_classify.training.estimators import build_estimator
    data = convert([train_bags], window=WINDOW, hop=HOP, progress=lambda line: None)
    estimator = build_estimator(TrainingConfig.for_profile(profile, model=model, epochs=epochs,
                                                           scaling=scaling))
    estimator.fit(data.X, data.y, data.classes, groups=data.trial, channels=data.channels)
    print(f'{model}: trained on {len(data.X)} windows of {len(np.unique(data.trial))} sweeps',
          flush=True)
    return estimator.save(folder / model, hop=HOP,
                          sampling_rate_hz=data.info['sampling_rate_hz'])


def offline_reference(checkpoint: Path, test_bags: Path) -> dict:
    """The same model on the converter's windows of the held-out bags."""
    from tactex_classify.data.dataset import convert
    from tactex_classify.evaluation.cross_validation import sequence_accuracy
    from tactex_classify.models.checkpoint import load_checkpoint
    from tactex_classify.online.evidence import log_probabilities
    info, estimator = load_checkpoint(checkpoint)
    data = convert([test_bags], window=WINDOW, hop=HOP, progress=lambda line: None)
    index = [list(info.classes).index(name) for name in data.classes]
    proba = estimator.predict_proba(data.X)[:, index]
    whole = [int(np.argmax(log_probabilities(proba[data.trial == t]).sum(axis=0))
                 == data.y[data.trial == t][0]) for t in np.unique(data.trial)]
    return {'window_accuracy': float(np.mean(proba.argmax(axis=1) == data.y)),
            'whole_sweep_accuracy': float(np.mean(whole)),
            'sequence': {str(k): v['accuracy'] for k, v in sequence_accuracy(data, proba).items()}}


def bag_messages(path: Path) -> tuple[str, list[tuple[int, str, bytes]]]:
    """The label and (log_ns, role, CDR bytes) of the fed topics, in log order."""
    from rosbags.highlevel import AnyReader

    from tactex_classify.data.bags import TOPIC_ROLES
    from tactex_common.interfaces import typestore
    roles = {f'/{TOPIC_ROLES[r][0]}': r for r in (*FED_TOPICS, 'metadata')}
    messages, label = [], None
    with AnyReader([path], default_typestore=typestore()) as reader:
        for connection, log_ns, raw in reader.messages():
            role = roles.get(connection.topic)
            if role == 'metadata':
                label = json.loads(reader.deserialize(raw, connection.msgtype).data)['label']
            elif role is not None:
                messages.append((log_ns, role, bytes(raw)))
    return label, messages


class Feeder:
    """Publishes bags' bytes and /clock, paced at `speed` times real time; records estimates."""

    def __init__(self, context, speed: float) -> None:
        from diagnostic_msgs.msg import DiagnosticArray
        import rclpy
        from rclpy.qos import qos_profile_sensor_data
        from rosgraph_msgs.msg import Clock
        from sensor_msgs.msg import FluidPressure, Imu, MagneticField
        from std_msgs.msg import Bool

        from tactex_classify.data.bags import TOPIC_ROLES
        from tactex_common.ros import COMMAND
        from tactex_msgs.msg import TextureEstimate
        self.node = rclpy.create_node('bench_online_accuracy', context=context)
        self.speed = speed
        kinds = {'imu': Imu, 'mag': MagneticField, 'pressure': FluidPressure, 'active': Bool}
        self.publishers = {role: self.node.create_publisher(
            kinds[role], TOPIC_ROLES[role][0],
            COMMAND if role == 'active' else qos_profile_sensor_data) for role in kinds}
        self.clock = self.node.create_publisher(Clock, '/clock', 10)
        self.clock_type = Clock
        self.estimates: dict[str, list] = {'texture/estimate': [], 'texture/estimate_check': []}
        for topic, received in self.estimates.items():
            self.node.create_subscription(TextureEstimate, topic, received.append, 1000)
        self.diagnostics: dict[str, dict] = {}
        self.node.create_subscription(DiagnosticArray, 'diagnostics', self._on_diagnostics, 50)
        self.executor = rclpy.executors.SingleThreadedExecutor(context=context)
        self.executor.add_node(self.node)

    def _on_diagnostics(self, message) -> None:
        for status in message.status:
            self.diagnostics[status.name] = {kv.key: kv.value for kv in status.values}

    def spin(self, seconds: float, until=lambda: False) -> bool:
        """Spin until `until()` or `seconds` pass."""
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline and not until():
            self.executor.spin_once(timeout_sec=0.005)
        return until()

    def nodes_up(self, count: int) -> bool:
        """Whether `count` classifier nodes subscribe to the sensor and publish estimates."""
        from tactex_classify.data.bags import TOPIC_ROLES
        return (self.node.count_subscribers(TOPIC_ROLES['imu'][0]) >= count
                and self.node.count_publishers('texture/estimate')
                + self.node.count_publishers('texture/estimate_check') >= count)

    def play(self, messages: list[tuple[int, str, bytes]]) -> None:
        """Publish one bag's messages at their log times / speed, with /clock before each.

        sweep/active (a Bool, no stamp) is stamped by each node with its clock on arrival,
        so a node that has not yet taken the latest /clock puts the contact's start, and
        every window after it, a few samples off the other node's. Around each flag the
        feeder pauses (`FLAG_SETTLE_S`, the pacing shifted by as much) so both nodes take
        it at the same simulated instant, as the recorder logged it.
        """
        import rclpy
        start_ns, start = messages[0][0], time.monotonic()
        clock_ns = None
        for log_ns, role, raw in messages:
            delay = start + (log_ns - start_ns) * 1e-9 / self.speed - time.monotonic()
            if delay > 0:
                self.spin(delay)
            if role == 'active':
                self.spin(FLAG_SETTLE_S)
            if log_ns != clock_ns:
                clock_ns = log_ns
                self.clock.publish(self.clock_type(
                    clock=rclpy.time.Time(nanoseconds=log_ns).to_msg()))
            if role == 'active':
                self.spin(FLAG_SETTLE_S)
            self.publishers[role].publish(raw)
            if role == 'active':
                self.spin(FLAG_SETTLE_S)
                start += 3 * FLAG_SETTLE_S


def stamp(time_msg) -> int:
    return time_msg.sec * 1_000_000_000 + time_msg.nanosec


def sweeps_of(estimates: list, spans: list[tuple[str, int, int]], classes: list[str]) -> list:
    """Per held-out bag: its label and its estimates (stamp order)."""
    result = []
    for label, first_ns, last_ns in spans:
        mine = sorted((e for e in estimates if first_ns <= stamp(e.header.stamp) <= last_ns),
                      key=lambda e: stamp(e.header.stamp))
        result.append((classes.index(label), mine))
    return result


def evaluate(sweeps: list, rate_hz: float) -> dict:
    """The decision measures per threshold, for the first window and for the whole sweep."""
    from tactex_classify.evaluation.cross_validation import decision_measures
    window_s = WINDOW / rate_hz
    period_ns = int(round(1e9 / rate_hz))

    def total_s(estimates) -> float:
        from tactex_classify.online.evidence import union_seconds
        return union_seconds([(stamp(e.window_starts[-1]), stamp(e.window_ends[-1]) + period_ns)
                              for e in estimates])

    used = [(label, estimates) for label, estimates in sweeps if estimates]
    rows = {}
    for threshold in THRESHOLDS:
        decisions = []
        for label, estimates in used:
            chosen = next((e for e in estimates if e.confidence > threshold), estimates[-1])
            decisions.append((chosen.class_id == label, chosen.contact_seconds,
                              min(1.0, chosen.contact_seconds / total_s(estimates))))
        rows[f'{threshold:.10g}'] = decision_measures(decisions)
    first = [(e[0].class_id == label, window_s, window_s / total_s(e)) for label, e in used]
    whole = [(e[-1].class_id == label, total_s(e), 1.0) for label, e in used]
    return {'thresholds': rows, 'first_window': decision_measures(first),
            'whole_sweep': decision_measures(whole),
            'sweeps_without_estimate': len(sweeps) - len(used),
            'restarts': sum(sum(b.windows_used <= a.windows_used for a, b in zip(
                e, e[1:], strict=False)) for _, e in used)}


def check_live_threshold(sweeps: list, checked: list, threshold: float) -> dict:
    """Sweeps where the live node at `threshold` decided as derived from the threshold-1 run.

    For each disagreement, what differed: the windows the two nodes cut (their first
    windows' start, ms apart; a sample lost or the contact flag arriving beside another
    sample shifts every window) or, on the same windows, the confidence.
    """
    agree = total = 0
    disagreements = []
    for number, ((_, estimates), (_, live)) in enumerate(zip(sweeps, checked, strict=True)):
        derived = next((e for e in estimates if e.confidence > threshold), None)
        decided = next((e for e in live if e.decided), None)
        if derived is None and decided is None:
            continue
        total += 1
        same = (derived is not None and decided is not None
                and derived.class_id == decided.class_id
                and derived.windows_used == decided.windows_used)
        agree += same
        if not same:
            disagreements.append({'sweep': number, 'derived': decision_of(derived),
                                  'decided': decision_of(decided),
                                  **windows_compared(estimates, live)})
    return {'threshold': threshold, 'agree': agree, 'sweeps': total,
            'disagreements': disagreements}


def decision_of(estimate) -> dict | None:
    """The class, windows and confidence of a decision (None: none was made)."""
    return None if estimate is None else {
        'class_id': estimate.class_id, 'windows_used': estimate.windows_used,
        'confidence': float(estimate.confidence)}


def windows_compared(estimates: list, live: list) -> dict:
    """How far apart the two nodes' windows are, and their confidence on shared windows."""
    first = [stamp(e[0].window_starts[0]) for e in (estimates, live) if e and e[0].window_starts]
    ends = {stamp(e.window_ends[-1]): float(e.confidence) for e in estimates}
    shared = [(ends[stamp(e.window_ends[-1])], float(e.confidence)) for e in live
              if not e.decided and stamp(e.window_ends[-1]) in ends]
    return {'first_window_offset_ms': (first[1] - first[0]) * 1e-6 if len(first) == 2
            else None,
            'windows': [len(estimates), len(live)], 'shared_windows': len(shared),
            'largest_confidence_difference': max(
                (abs(a - b) for a, b in shared), default=None)}


def plot(path: Path, results: dict) -> None:
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    figure, (by_threshold, by_time) = plt.subplots(1, 2, figsize=(11, 4.2))
    for model, result in results.items():
        rows = result['live']['thresholds']
        thresholds = [float(t) for t in rows]
        accuracy = [100 * rows[t]['accuracy'] for t in rows]
        contact = [rows[t]['median_contact_s'] for t in rows]
        by_threshold.semilogx([1 - t for t in thresholds], accuracy, 'o-', label=model)
        line, = by_time.plot(contact, accuracy, 'o-', label=f'{model}: threshold sweep')
        for name, marker in (('first_window', 's'), ('whole_sweep', 'D')):
            point = result['live'][name]
            by_time.plot(point['median_contact_s'], 100 * point['accuracy'], marker,
                         color=line.get_color(), label=f'{model}: {name.replace("_", " ")}')
    by_threshold.invert_xaxis()
    by_threshold.set(xlabel='1 - threshold', ylabel='accuracy of the decision (%)',
                     title='decision accuracy against the threshold')
    by_time.set(xlabel='median contact time to decision (s)', ylabel='accuracy (%)',
                title='accuracy against contact time (held-out sweeps, live)')
    for axis in (by_threshold, by_time):
        axis.grid(alpha=0.3)
        axis.legend(fontsize=7)
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)


def run_model(checkpoint: Path, test: list, speed: float, env: dict) -> dict:
    """Feed every held-out bag through two live nodes; the measures and the live check."""
    import rclpy
    from rclpy.context import Context

    from tactex_classify.models.checkpoint import read_checkpoint
    info = read_checkpoint(checkpoint)
    common = ['-p', f'checkpoint:={checkpoint}', '-p', 'contact:=sweep_active',
              '-p', 'use_sim_time:=true', '-p', 'diagnostics_period_s:=0.5']
    nodes = [subprocess.Popen([BIN / 'classifier_node', '--ros-args', *common,
                               '-p', 'threshold:=1.0'], env=env, stderr=subprocess.DEVNULL),
             subprocess.Popen([BIN / 'classifier_node', '--ros-args', '-r',
                               '__node:=classifier_check', '-r',
                               'texture/estimate:=texture/estimate_check', *common,
                               '-p', f'threshold:={DEFAULT_THRESHOLD}'], env=env,
                              stderr=subprocess.DEVNULL)]
    context = Context()
    rclpy.init(context=context)
    feeder = Feeder(context, speed)
    try:
        # The nodes run on simulated time (their diagnostics tick only once /clock runs):
        # they are up when both subscribe to the sensor and publish estimates.
        if not feeder.spin(60.0, lambda: feeder.nodes_up(2)):
            raise RuntimeError('classifier_node did not come up in 60 s')
        feeder.spin(2.0)
        spans = []
        for number, (label, messages) in enumerate(test, 1):
            feeder.play(messages)
            feeder.spin(0.5)
            spans.append((label, messages[0][0], messages[-1][0]))
            print(f'  fed {number}/{len(test)} ({label}): '
                  f'{len(feeder.estimates["texture/estimate"])} estimates so far', flush=True)
        feeder.spin(3.0)
        diagnostics = dict(feeder.diagnostics)
        estimates = dict(feeder.estimates)
    finally:
        feeder.node.destroy_node()
        rclpy.shutdown(context=context)
        for node in nodes:
            node.terminate()
            node.wait(timeout=15)
    classes = list(info.classes)
    sweeps = sweeps_of(estimates['texture/estimate'], spans, classes)
    checked = sweeps_of(estimates['texture/estimate_check'], spans, classes)
    live = evaluate(sweeps, info.stream.sampling_rate_hz)
    counters = {key: {name: value for name, value in values.items()
                      if name in COUNTERS or name.startswith('faults_')}
                for key, values in diagnostics.items()}
    return {'model_id': info.model_id, 'live': live,
            'live_check': check_live_threshold(sweeps, checked, DEFAULT_THRESHOLD),
            'counters': counters}


def main(argv: list[str] | None = None) -> int:
    """Collect, train, feed live, measure; keep results/online_accuracy.{json,md,png}."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--train-sweeps', type=int, default=12, help='per texture')
    parser.add_argument('--test-sweeps', type=int, default=4, help='held out, per texture')
    parser.add_argument('--models', default='minirocket,cnn_3')
    parser.add_argument('--epochs', type=int, default=80, help='deep models, at most')
    parser.add_argument('--profile', choices=('original', 'modern'), default='modern',
                        help="deep models' training profile (as bench_textures.py)")
    parser.add_argument('--scaling', choices=('minmax', 'standard', 'window'),
                        default='window', help="deep models' input scaling")
    parser.add_argument('--speed', type=float, default=3.0, help='times real time')
    args = parser.parse_args(argv)
    env = ros_environment()
    # A ROS domain of this run's own: no other run on this machine can cross-talk with it.
    env['ROS_DOMAIN_ID'] = str(random.SystemRandom().randint(200, 232))
    os.environ.update(env)
    results = {}
    with tempfile.TemporaryDirectory() as scratch:
        scratch = Path(scratch)
        train_bags, test_bags = collect_sets(scratch, args.train_sweeps, args.test_sweeps)
        test = sorted((bag_messages(path) for path in test_bags.iterdir()),
                      key=lambda bag: bag[1][0][0])  # in time order, as recorded
        for model in args.models.split(','):
            checkpoint = train(model, train_bags, scratch, args.epochs, args.profile,
                               args.scaling)
            result = run_model(checkpoint, test, args.speed, env)
            result['offline'] = offline_reference(checkpoint, test_bags)
            results[model] = result
            print(json.dumps(result['live']['thresholds'][f'{DEFAULT_THRESHOLD:.10g}']),
                  flush=True)
    summary = {'scene': 'uneven_texture', 'window': WINDOW, 'hop': HOP,
               'train_sweeps_per_texture': args.train_sweeps,
               'test_sweeps_per_texture': args.test_sweeps, 'speed': args.speed,
               'deep_training': {'epochs': args.epochs, 'profile': args.profile,
                                 'scaling': args.scaling},
               'models': results}
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / 'online_accuracy.json').write_text(json.dumps(summary, indent=2),
                                                  encoding='utf-8')
    plot(RESULTS / 'online_accuracy.png', results)
    table = render(summary)
    (RESULTS / 'online_accuracy.md').write_text(table, encoding='utf-8')
    print(table)
    dropped = {m: {node: counts.get('windows_dropped') for node, counts in r['counters'].items()}
               for m, r in results.items()}
    problems = [f'{m}: the node dropped windows {nodes}' for m, nodes in dropped.items()
                if any(v not in ('0', None) for v in nodes.values())]
    problems += [f'{m}: the live node at {r["live_check"]["threshold"]} disagreed with the '
                 f'derived decision in {r["live_check"]["sweeps"] - r["live_check"]["agree"]} '
                 'sweeps' for m, r in results.items()
                 if r['live_check']['agree'] != r['live_check']['sweeps']]
    for problem in problems:
        print(f'FAILED: {problem}', file=sys.stderr)
    return 1 if problems else 0


def render(summary: dict) -> str:
    """The tables of the kept markdown output."""
    lines = []
    for model, result in summary['models'].items():
        live, offline = result['live'], result['offline']
        lines += [f'## {model} ({result["model_id"]})', '',
                  '| decision | accuracy | median contact s | earliness | HM(acc, 1 - earl.) |',
                  '|---|---|---|---|---|']

        def row(name: str, m: dict) -> str:
            return (f'| {name} | {100 * m["accuracy"]:.1f} % | {m["median_contact_s"]:.2f} | '
                    f'{m["earliness"]:.3f} | {m["harmonic_mean"]:.3f} |')
        lines.append(row('first window', live['first_window']))
        for threshold, measures in live['thresholds'].items():
            lines.append(row(f'posterior > {threshold}', measures))
        lines.append(row('whole sweep', live['whole_sweep']))
        check = result['live_check']
        lines += ['', f'Live node at threshold {check["threshold"]}: same decision (class and '
                  f'window) as derived in {check["agree"]} of {check["sweeps"]} sweeps. '
                  f'Held-out sweeps without a single window in contact (left out above): '
                  f'{live["sweeps_without_estimate"]}. '
                  f'Evidence restarts (texture change) seen: {live["restarts"]}. Offline '
                  f'reference (converter windows, same model): window accuracy '
                  f'{100 * offline["window_accuracy"]:.1f} %, whole-sweep '
                  f'{100 * offline["whole_sweep_accuracy"]:.1f} %.', '']
        lines += [disagreement_line(d) for d in check.get('disagreements', [])]
    return '\n'.join(lines)


def disagreement_line(disagreement: dict) -> str:
    """One disagreement of the live check, with what differed between the two nodes."""
    def said(decision: dict | None) -> str:
        return 'no decision' if decision is None else (
            f'class {decision["class_id"]} after {decision["windows_used"]} windows '
            f'({decision["confidence"]:.6f})')
    offset = disagreement['first_window_offset_ms']
    difference = disagreement['largest_confidence_difference']
    return (f'- held-out sweep {disagreement["sweep"]}: derived {said(disagreement["derived"])}, '
            f'live {said(disagreement["decided"])}; first windows '
            + ('not both cut' if offset is None else f'{offset:+.1f} ms apart')
            + f', {disagreement["shared_windows"]} windows shared'
            + ('' if difference is None else
               f' (confidence differs by up to {difference:.2e} on them)') + '\n')


if __name__ == '__main__':
    sys.exit(main())
