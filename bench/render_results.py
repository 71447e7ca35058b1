# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Write the README's benchmark figures from the outputs kept in bench/results/.

Every figure of the README sits in a generated section between `<!-- results:NAME -->`
and `<!-- /results -->`; this script renders each section from the files the benchmarks
left in bench/results/ and rewrites only what lies between the markers, so prose and
figures cannot disagree with the kept outputs. `make results` runs it; `--check` exits 1
(listing the stale sections) instead of writing, which the test suite uses.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
import json
from pathlib import Path
import re
import sys
import textwrap

import numpy as np

RESULTS = Path(__file__).parent / 'results'
README = Path(__file__).parents[1] / 'README.md'
SECTION = re.compile(r'(<!-- results:(?P<name>[a-z_]+) -->\n)(?P<body>.*?)(<!-- /results -->)',
                     re.DOTALL)
WIDTH = 90
TEXTURE_MODELS = {'extratrees': 'statistics + ExtraTrees', 'minirocket': 'MiniRocket + ridge'}


def _read(name: str) -> str:
    return (RESULTS / name).read_text(encoding='utf-8')


def _json(name: str):
    return json.loads(_read(name))


def _numbers(line: str) -> list[float]:
    """The numbers of a line of a kept text output, in order."""
    return [float(v) for v in re.findall(r'(?<![\w.])-?\d+(?:\.\d+)?(?:e[-+]?\d+)?', line)]


def _line(text: str, start: str) -> str:
    """The first line of `text` that starts with `start`."""
    return next(line for line in text.splitlines() if line.startswith(start))


def sensor_decoder() -> str:
    text = _read('bench_sensor_decoder.txt')
    bare, clean, garbage = (_numbers(_line(text, key)) for key in
                            ('bare unpack', 'clean', '1 % garbage'))
    return (f'the decoder handles {clean[0]:,.0f} frames/s on a clean stream and '
            f'{garbage[1]:,.0f} with 1 % garbage ({clean[0] / 50_000:.0f}x the 50,000 '
            f'target; {clean[1]:.2f}x a bare struct unpack without search or CRC, '
            f'{bare[0]:,.0f} frames/s).\n')


def sensor_node() -> str:
    text = _read('bench_sensor_node.txt')
    node = _numbers(_line(text, 'teensy_node'))
    ratio = _numbers(_line(text, 'p99 node / reference'))[0]
    return (f'Through `teensy_node` at 350 Hz, a frame written to the pty arrives as an Imu '
            f'message with p50 {node[0]:.2f} ms and p99 {node[1]:.2f} ms (target p99 < 5 ms; '
            f'{ratio:.1f}x a bare pyserial read of the same stream).\n')


def madgwick() -> str:
    data = _json('madgwick.json')
    cost = {row.split('|')[1].strip(): _numbers(row.split('|')[2])
            for row in _read('madgwick.md').splitlines()
            if row.startswith('| tactex ') or row.startswith('| imufusion (C)')
            or row.startswith('| ahrs Madgwick')}
    rows = data['results']
    tuned = ('tactex', 'imufusion', 'ahrs')
    cases: dict[tuple, dict[str, float]] = {}
    for row in rows:
        if row['filter'] in tuned:
            error = row['rms_attitude_deg'] if row['mode'] == 'MARG' else row['rms_tilt_deg']
            cases.setdefault((row['bias'], row['rate_hz'], row['mode'], row['motion']),
                             {})[row['filter']] = error
    wins = sum(min(errors, key=errors.get) == 'tactex' for errors in cases.values())
    lost = [f'{motion}, {rate:g} Hz, {mode}, {bias} ({min(errors, key=errors.get)})'
            for (bias, rate, mode, motion), errors in cases.items()
            if min(errors, key=errors.get) != 'tactex']
    lines = ['| gyro bias | mode | tactex | imufusion 1.3.3 | ahrs 0.4.0 |',
             '|---|---|---|---|---|']
    for bias in dict.fromkeys(row['bias'] for row in rows):
        for mode in ('IMU', 'MARG'):
            means = [np.mean([errors[name] for (b, _, m, _), errors in cases.items()
                              if b == bias and m == mode]) for name in tuned]
            lines.append(f'| {bias} | {mode} | ' + ' | '.join(f'{v:.2f}' for v in means) + ' |')
    gains = {name: ' / '.join(f'{data["tuned"][name][mode]["gain"]:g}' for mode in ('IMU',
                                                                                  'MARG'))
             for name in tuned}
    grids = [data['tuned']['tactex'][mode]['grid'] for mode in ('IMU', 'MARG')]
    both = min(grids[0], key=lambda gain: grids[0][gain] + grids[1][gain])
    default = (f'Our default gain, {data["default_gain"]:g}, '
               + ('is' if float(both) == data['default_gain'] else 'is not')
               + f' the one of least mean error over both modes on the tuning seed ({both}). ')
    stream = cost['tactex streaming (Python)'][0]
    return (f'The filter costs {stream:.2f} us per sample streaming and '
            f'{cost["tactex batch (numba)"][0]:.3f} us in the batch path '
            f'({stream / cost["tactex batch (numba)"][0]:.0f}x less; imufusion\'s C code '
            f'{cost["imufusion (C)"][0]:.2f} us, ahrs {cost["ahrs Madgwick"][0]:.1f} us). '
            f'Accuracy on five seeded motions at 120 and 350 Hz, IMU and MARG, without and '
            f'with a 0.6 deg/s gyro bias, every filter with its gain grid-tuned on seed '
            f'{data["tuning_seed"]} and scored on seed {data["scored_seed"]} (IMU / MARG '
            f'gains: tactex {gains["tactex"]}, imufusion {gains["imufusion"]}, ahrs '
            f'{gains["ahrs"]}; what each was given is in `bench/results/madgwick.md`): mean '
            f'RMS error (deg; tilt for IMU, full attitude for MARG) after '
            f'{data["settle_s"]:g} s:\n\n' + '\n'.join(lines) + '\n\n'
            + default + f'Ours has the lowest error in {wins} of {len(cases)} cases; the '
            f'others: ' + ('; '.join(lost) if lost else 'none') + '.\n')


def driver() -> str:
    text = _read('bench_driver.txt')
    pings = _numbers(_line(text, '5 unicast pings'))
    cycle = _numbers(_line(text, 'sync read'))
    loop = _numbers(_line(text, 'arm_driver 100 Hz loop'))
    return (f'- `python bench/bench_driver.py`: a full cycle (sync read of 5 servos + sync '
            f'write) takes {cycle[-2]:.2f} ms median, p99 {cycle[-1]:.2f} ms (target <= 2 ms; '
            f'{cycle[-2] / pings[-2]:.2f}x the time of five unicast pings); the 100 Hz '
            f"loop's |period - 10 ms| is {loop[-2]:.3f} ms median, p99 {loop[-1]:.2f} ms "
            f'(target < 2 ms).\n')


def sim() -> str:
    data = _json('sim.json')
    parts = [f'{name} {row["real_time_factor"]:.1f}x real time ({row["sensor_rate_hz"]:g} Hz, '
             f'{row["step_ms"]:.2f} ms steps; physics and control alone '
             f'{row["physics_alone_factor"]:.1f}x)' for name, row in data.items()]
    return (f'- `python bench/bench_sim.py`: {"; ".join(parts)}. Targets: probe 20x, the '
            f'texture scene with every effect 5x.\n')


def convert() -> str:
    text = _read('bench_convert.txt')
    wrote = _numbers(_line(text, 'wrote'))
    reference = _numbers(_line(text, 'rosbags read'))
    ours = _numbers(_line(text, 'tactex read_recording'))
    return (f'- `python bench/bench_convert.py`: on a 1-hour 350 Hz recording '
            f'({wrote[0] / 1e6:.2f} million messages, {wrote[1]:.0f} MB) conversion runs at '
            f"{ours[-2] / reference[-2]:.2f}x the speed of rosbags' own read + deserialise "
            f'(target 0.5x) with a peak of {ours[-1]:.0f} MB resident.\n')


def _texture_run() -> dict:
    return _json('textures/run.json')


def synthetic_set() -> str:
    run = _texture_run()
    dataset = run['dataset']
    collect = next(step for step in run['steps'] if ' sim collect ' in step['command'])
    return (f'- On the synthetic set (`tactex sim collect`, 12 textures x '
            f'{dataset["sweeps_per_texture"]} sweeps, {collect["seconds"] / 60:.1f} min in '
            f'the last benchmark run), 128-sample windows with 50 % overlap give '
            f'{dataset["windows"]} windows from {dataset["recordings"]} recordings (the '
            f'original: 3962).\n')


def textures() -> str:
    run = _texture_run()
    dataset = run['dataset']
    lines = []
    for model in run['models']:
        metrics = _json(f'textures/{model}/metrics.json')
        grouped, stratified = (metrics['schemes'][s] for s in ('grouped', 'stratified'))
        eight = next(row for row in grouped['sequence'] if row['windows'] == 8)
        label = TEXTURE_MODELS[model] if model in TEXTURE_MODELS else (
            f'{model}, {metrics["settings"]["epochs"]} epochs, {metrics["settings"]["init"]} '
            f'initialisation')
        lines.append(f'| {label} | {100 * grouped["accuracy"]:.1f} % | '
                     f'{100 * stratified["accuracy"]:.1f} % | {100 * eight["accuracy"]:.1f} % '
                     f'({eight["touch_s"]:.1f} s of touch) |')
    leak = [100 * (_json(f'textures/{m}/metrics.json')['schemes']['stratified']['accuracy']
                   - _json(f'textures/{m}/metrics.json')['schemes']['grouped']['accuracy'])
            for m in run['models']]
    confused = []
    for model in run['models']:
        grouped = _json(f'textures/{model}/metrics.json')['schemes']['grouped']
        matrix, names = np.array(grouped['confusion']), list(grouped['per_class'])
        np.fill_diagonal(matrix, 0)
        pairs = np.dstack(np.unravel_index(np.argsort(-matrix, axis=None)[:2], matrix.shape))[0]
        confused.append(f'{TEXTURE_MODELS.get(model, model)}: ' + ', '.join(
            f'{names[i]} as {names[j]} ({matrix[i, j]})' for i, j in pairs))
    minutes = sum(step['seconds'] for step in run['steps']) / 60
    return (f'Results on one build of the synthetic set (12 textures x '
            f'{dataset["sweeps_per_texture"]} sweeps of the uneven-texture scene, '
            f'{dataset["windows"]} windows of 128 samples, SHA-256 '
            f'{dataset["sha256"][:12]}...; one `python bench/bench_textures.py` run, '
            f'{minutes:.0f} min, reports in `bench/results/textures/`):\n\n'
            '| classifier | grouped by recording (honest) | stratified windows (leaky) | '
            'honest, 8 windows |\n|---|---|---|---|\n' + '\n'.join(lines) + '\n\n'
            f'The leak of window-level cross-validation is {min(leak):.1f}-{max(leak):.1f} '
            f'points here. The windows most often confused (grouped, true as predicted): '
            + '; '.join(confused) + '.\n')


def init() -> str:
    data = _json('init.json')
    cap = data['cap']
    lines = ['| model | PyTorch init | Keras init |', '|---|---|---|']
    for model in dict.fromkeys(row['model'] for row in data['results']):
        cells = [', '.join(str(row['epochs']) if row['epochs'] else
                           f'>{cap} ({100 * row["final_train_accuracy"]:.0f} %)'
                           for row in data['results']
                           if row['model'] == model and row['init'] == init_name)
                 for init_name in ('pytorch', 'keras')]
        lines.append(f'| {model} | {cells[0]} | {cells[1]} |')
    return (f'Epochs to {100 * data["target"]:.0f} % training accuracy from each '
            f'initialisation (`python bench/bench_init.py`: {data["windows"]} windows of '
            f'{data["recordings_per_class"]} recordings per class of the synthetic set, seeds '
            f'{", ".join(map(str, data["seeds"]))}, at most {cap} epochs):\n\n'
            + '\n'.join(lines) + '\n')


def kinematics() -> str:
    data = _json('kinematics.json')
    sentences = []
    for use, (analytic, numeric) in data.items():
        sentences.append(f'{use}, {analytic["solves_per_s"]:,.0f} solves/s against '
                         f'{numeric["solves_per_s"]:,.0f} for {numeric["solver"]} '
                         f'({analytic["solves_per_s"] / numeric["solves_per_s"]:.0f}x; it '
                         f'missed {numeric["misses"]} of {numeric["targets"]} targets by more '
                         f'than 1 um, the analytic IK {analytic["misses"]})')
    return '- `python bench/bench_kinematics.py`: ' + '; '.join(sentences) + '.\n'


def sweep() -> str:
    data = _json('sweep.json')

    def row(label: str, numbers: dict) -> str:
        return (f'| {label} | {numbers["contact"]:.1f} | {numbers["speed"]:.1f} '
                f'({numbers["arm_speed"]:.1f}) | {numbers["depth"]:.2f} '
                f'({numbers["planned"]:.2f}) | {numbers["bias"]:+.2f} | '
                f'{numbers["plan_ms"]:.0f} |')

    reference, default = data['reference'], data['probed_closed_loop']
    lines = ["| sweep | contact % (worst pathway) | worst speed window % (arm's edge) | "
             "press depth error rms mm (the plan's share) | mean mm | planning ms |",
             '|---|---|---|---|---|---|',
             row('scripted, on the true surface (reference)', reference),
             row('**probed in closed loop (MuJoCo, tactex_probe) every 10 mm, a point every '
                 '2 mm**', default)]
    lines += [row(f'{count} trajectory points, model probe every 10 mm', numbers)
              for count, numbers in data['by_samples'].items()]
    lines += [row(f'model probe every {step} mm, a point every 2 mm', numbers)
              for step, numbers in data['by_step_mm'].items()]
    return ('\n'.join(lines) + '\n\n' +
            f'"Model probe": contacts on the true surface with a probe\'s noise (1 mm, 2 deg), '
            f'for the curves. Along pathways the explorer probed in closed loop (the default '
            f'sweep, {data["pathways"]} pathways): {default["contact"]:.1f} % of the contact '
            f'segment in contact at worst (threshold 95 %, goal 99 %); the worst 0.25 s window '
            f'{default["speed"]:.1f} % off {data["speed_m_s"] * 1e3:g} mm/s (threshold 10 %, '
            f'goal 5 %; the edge where the arm holds it {default["arm_speed"]:.1f} %); the '
            f'press depth {default["depth"]:.2f} mm rms off the asked '
            f'{data["press_depth_m"] * 1e3:g} mm ({default["depth"] / reference["depth"]:.2f}x '
            f'the scripted sweep that knows the surface), of which the plan '
            f'{default["planned"]:.2f} mm; planned in {default["plan_ms"]:.0f} ms.\n')


SECTIONS: dict[str, Callable[[], str]] = {
    'sensor_decoder': sensor_decoder, 'sensor_node': sensor_node, 'madgwick': madgwick,
    'driver': driver, 'sim': sim, 'convert': convert, 'synthetic_set': synthetic_set,
    'textures': textures, 'init': init, 'kinematics': kinematics, 'sweep': sweep}


def _wrapped(text: str) -> str:
    """Paragraphs wrapped at the README's width (tables as they are, bullets indented)."""
    paragraphs = text.strip('\n').split('\n\n')
    return '\n\n'.join(part if part.startswith('|') else textwrap.fill(
        part, WIDTH, subsequent_indent='  ' if part.startswith('- ') else '',
        break_on_hyphens=False) for part in paragraphs) + '\n'


def render() -> dict[str, str]:
    """Every generated section, rendered from the kept outputs."""
    return {name: _wrapped(make()) for name, make in SECTIONS.items()}


def rewrite(text: str, sections: dict[str, str]) -> str:
    """`text` with every generated section replaced by its rendering.

    Raises:
        ValueError: a marker names no known section, or a known one has no marker.
    """
    found = [match['name'] for match in SECTION.finditer(text)]
    unknown = sorted(set(found) - set(sections))
    missing = sorted(set(sections) - set(found))
    if unknown or missing:
        raise ValueError(f'README markers: unknown {unknown}, missing {missing}')
    return SECTION.sub(lambda m: m.group(1) + sections[m['name']] + m.group(4), text)


def stale(text: str, sections: dict[str, str]) -> list[str]:
    """Names of the sections whose text differs from their rendering."""
    return [m['name'] for m in SECTION.finditer(text) if m['body'] != sections[m['name']]]


def main(argv: list[str] | None = None) -> int:
    """Rewrite README.md's generated sections (or, with --check, only compare)."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('--check', action='store_true', help='compare only; exit 1 if stale')
    args = parser.parse_args(argv)
    text = README.read_text(encoding='utf-8')
    sections = render()
    if args.check:
        names = stale(text, sections)
        if names:
            print(f'error: README sections out of date: {", ".join(names)}; run make results',
                  file=sys.stderr)
            return 1
        return 0
    README.write_text(rewrite(text, sections), encoding='utf-8')
    return 0


if __name__ == '__main__':
    sys.exit(main())
