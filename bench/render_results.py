# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Write the docs site's benchmark figures from the outputs kept in bench/results/.

Every benchmark figure of the docs (docs/*/*.md) sits in a generated section between
`<!-- results:NAME -->` and `<!-- /results -->`, each section on exactly one page; this
script renders each from the files the benchmarks left in bench/results/ and rewrites only
what lies between the markers, so prose and figures cannot disagree with the kept outputs.
`make results` runs it; `--check` exits 1 (listing the stale sections) instead of writing,
which the test suite uses. Figures are linked through docs/results, a link to bench/results.
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
DOCS = Path(__file__).parents[1] / 'docs'
# bench/results/ as a page one folder below docs/ sees it (docs/results links there).
FIGURES = '../results'
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


def observers() -> str:
    text = _read('bench_observers.txt')
    ref, view, watch = (_numbers(_line(text, key)) for key in
                        ('nothing beside', 'tactex view', 'tactex status'))
    verdict = 'under' if view[5] < 1.0 else 'over'
    return (f'What watching costs `teensy_node` at 350 Hz (frame written -> Imu received; '
            f'median p99 of 3 interleaved rounds, `python bench/bench_observers.py`): '
            f'{ref[1]:.2f} ms with nothing beside it (rounds {ref[2]:.2f}-{ref[3]:.2f}); '
            f'{watch[1]:.2f} ms with `tactex status` and `tactex watch` running '
            f'({watch[5]:+.2f} ms); {view[1]:.2f} ms with the live view forwarding at its '
            f'default `max_rate_hz` (60) to a subscribed WebSocket client ({view[5]:+.2f} ms, '
            f'rounds {view[2]:.2f}-{view[3]:.2f}: {verdict} the 1 ms target on 2 shared cores, '
            f'where the node, the view, the client and the emulator compete).\n')


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


def sensor_stats() -> str:
    run, table = _json('sensor_stats/run.json'), _json('sensor_stats/stats.json')
    rows = [row for entry in table.values() for row in entry['channels'].values()]
    rails = max(row['at_rails'] for row in rows)
    beyond = sum(row['beyond_full_scale'] for row in rows)
    rocking = [entry['channels']['gy'] for entry in table.values()]
    accel = max(entry['channels'][axis]['max'] for entry in table.values()
                for axis in ('ax', 'ay', 'az'))
    tilts = [entry['madgwick_tilt_deg_median'] for entry in table.values()]
    strongest = max(table, key=lambda texture: table[texture]['channels']['gy']['rms'])
    return (f'- Measured by `python bench/bench_sensor_stats.py` ({run["started"]}: '
            f'`{run["steps"][0]["command"]}` of the shipped `{run["scene"]}` scene, '
            f'{len(table)} textures, then `tactex sim stats`; `bench/results/sensor_stats/`: '
            f'the table and the four spectra): {beyond or "no"} samples beyond the full '
            f'scale, {f"at most {100 * rails:.2f} %" if rails else "none"} of a channel\'s '
            f'samples at a rail; the rocking axis (gy) at '
            f'{min(r["rms"] for r in rocking):.2f}-{max(r["rms"] for r in rocking):.2f} rad/s '
            f'RMS and at most {max(r["max"] for r in rocking):.2f} rad/s (the old model: 456 '
            f'to 877 of about 900 sliding samples beyond 4.3 rad/s), the most on '
            f'{strongest}; |accel| at most {accel:.1f} m/s^2 of the +-39 m/s^2 range; Madgwick '
            f'tilt {min(tilts):.2f}-{max(tilts):.2f} deg median while sliding.\n')


def channels() -> str:
    data = _json('channels/ablation.json')
    models = sorted({row['model'] for row in data['rows']})
    groups = list(dict.fromkeys(row['group'] for row in data['rows']))
    accuracy = {(row['group'], row['model']): row['grouped_accuracy'] for row in data['rows']}
    table = ['| channels | ' + ' | '.join(TEXTURE_MODELS.get(m, m) for m in models) + ' |',
             '|---|' + '---|' * len(models)]
    table += [f'| {group} | ' + ' | '.join(f'{100 * accuracy[group, m]:.1f} %' for m in models)
              + ' |' for group in groups]
    return (f'Channel ablation (`{data["command"].strip()}`, {data["seconds"] / 60:.0f} min: 12 '
            f'textures x {data["sweeps_per_texture"]} simulated sweeps, each channel group '
            f'alone and all together, grouped {data["folds"]}-fold accuracy by recording, '
            f'chance {100 * data["chance"]:.1f} %; `bench/results/channels/`, with '
            f'`ablation.png`):\n\n' + '\n'.join(table) + '\n')


def profiles() -> str:
    data = _json('profiles/profiles.json')
    rows = data['rows']
    best = max((row for row in rows if row['kind'] == 'baseline'), key=lambda r: r['accuracy'])
    table = ['| training | grouped accuracy | epochs trained | s per fold |', '|---|---|---|---|']
    for row in rows:
        epochs = [fold['epochs'] for fold in row['folds'] if 'epochs' in fold]
        trained = f'{sum(epochs) / len(epochs):.0f}' if epochs else '-'
        seconds = sum(fold['seconds'] for fold in row['folds']) / len(row['folds'])
        name = TEXTURE_MODELS.get(row['name'], row['name'])
        mark = ' (not converged)' if row['not_converged'] else ''
        table.append(f'| {name}{mark} | {100 * row["accuracy"]:.1f} ± {100 * row["sd"]:.1f} % '
                     f'| {trained} | {seconds:.0f} |')
    return (f'Training profiles of {data["model"]}, each element of `modern` taken out once '
            f'(`{data["command"].strip()}`, {data["seconds"] / 60:.0f} min: '
            f'{data["windows"]} windows of {data["recordings"]} simulated recordings, grouped '
            f'{data["folds"]}-fold by recording, the same folds for every row, at most '
            f'{data["epochs"]} epochs; chance {100 * data["chance"]:.1f} %, best baseline '
            f'{100 * best["accuracy"]:.1f} %; `bench/results/profiles/`, with '
            f'`profiles.png`):\n\n' + '\n'.join(table) + '\n')


def _percent(values) -> str:
    """Mean ± sd of shares, in percent."""
    return f'{100 * np.mean(values):.1f} ± {100 * np.std(values):.1f} %'


def architectures() -> str:
    data = _json('architectures/architectures.json')
    table = ['| model | grouped accuracy | epochs trained | training s per fold | inference ms '
             'per window |', '|---|---|---|---|---|']
    for row in data['rows']:
        epochs = [fold['epochs'] for fold in row['folds'] if 'epochs' in fold]
        mark = ' (not converged)' if row['not_converged'] else ''
        table.append(f'| {TEXTURE_MODELS.get(row["name"], row["name"])}{mark} | '
                     f'{100 * row["accuracy"]:.1f} ± {100 * row["sd"]:.1f} % | '
                     f'{f"{np.mean(epochs):.0f}" if epochs else "-"} | '
                     f'{np.mean([fold["seconds"] for fold in row["folds"]]):.0f} | '
                     f'{row["inference_ms"]:.2f} |')
    missing = f' Not run yet on this set: {", ".join(data["not_run"])}.' \
        if data.get('not_run') else ''
    return (f'Architectures on the set of the profile ablation (`{data["command"].strip()}`: '
            f'{data["windows"]} windows of {data["recordings"]} simulated recordings, grouped '
            f'{data["folds"]}-fold by recording, the same folds for every row; deep models '
            f'with the `modern` profile and per-window scaling, at most {data["epochs"]} '
            f'epochs, on {data["device"]}; chance {100 * data["chance"]:.1f} %; '
            '`bench/results/architectures/`, with `architectures.png`, accuracy against '
            f'training cost).{missing}\n\n' + '\n'.join(table) + '\n')


def window_voting() -> str:
    data = _json('window_voting/window_voting.json')
    table = ['| model | 128 alone | 256 alone | 512 alone | soft vote of the three | '
             'training s per fold (vote: the sum) |', '|---|---|---|---|---|---|']
    for row in data['rows']:
        cells = [_percent(row['accuracy'][key]) for key in ('128', '256', '512', 'vote')]
        table.append(f'| {row["name"]} | ' + ' | '.join(cells) +
                     f' | {sum(row["seconds"].values()):.0f} |')
    windows = ', '.join(f'{count} of {size}' for size, count in data['windows'].items())
    return (f'Soft voting across window sizes (`{data["command"].strip()}`: {windows} '
            f'samples from the same {data["recordings"]} recordings, grouped '
            f'{data["folds"]}-fold with the folds drawn once on the recordings; each length '
            'scored on its own test windows, the vote on the 512-sample ones; chance '
            f'{100 * data["chance"]:.1f} %; `bench/results/window_voting/`):\n\n'
            + '\n'.join(table) + '\n')


def sim_to_real() -> str:
    data = _json('sim_to_real/sim_to_real.json')
    ks = data['ks']
    table = ['| setting | ' + ' | '.join(f'k = {k}' for k in ks) + ' |',
             '|---|' + '---|' * len(ks)]
    for setting, by_k in data['accuracy'].items():
        table.append(f'| {setting} | ' + ' | '.join(_percent(by_k[str(k)]) for k in ks) + ' |')
    return (f'Sim-to-real fine-tuning (`{data["command"].strip()}`, {data["seconds"] / 60:.0f} '
            f'min): accuracy on {data["test_windows"]} windows of {data["test"]} held-out '
            'recordings per texture of the shifted scene, trained on k recordings per texture '
            f'of it (mean ± sd over {data["draws"]} draws); {data["model"]} with the `modern` '
            f'profile and per-window scaling, {data["epochs"]} epochs, pretrained on '
            f'{data["source_recordings"]} simulated recordings of the uneven-texture scene; '
            f'chance {100 * data["chance"]:.1f} %; `bench/results/sim_to_real/`, with '
            '`sim_to_real.png`:\n\n' + '\n'.join(table) + '\n')


def learning_curves() -> str:
    data = _json('learning_curves/learning_curves.json')
    sizes = data['sizes']
    table = ['| model | ' + ' | '.join(f'n = {n}' for n in sizes) + ' |',
             '|---|' + '---|' * len(sizes)]
    for model in data['models']:
        cells = []
        for n in sizes:
            point = data['points'].get(f'{model}@{n}')
            cells.append('-' if point is None else f'{100 * np.mean(point["accuracy"]):.1f} % '
                         f'({np.mean(point["seconds"]):.0f} s)')
        table.append(f'| {TEXTURE_MODELS.get(model, model)} | ' + ' | '.join(cells) + ' |')
    return (f'Learning curves (`{data["command"].strip()}`): accuracy on '
            f'{data["test_windows"]} windows of {data["test"]} held-out recordings per texture '
            'against the recordings per texture the model trained on, with the training '
            f'seconds of each point; {data["draws"]} draw(s); deep models with the `modern` '
            f'profile and per-window scaling, at most {data["epochs"]} epochs; chance '
            f'{100 * data["chance"]:.1f} %; `bench/results/learning_curves/`, with '
            '`learning_curves.png`:\n\n' + '\n'.join(table) + '\n')


def sim_collect() -> str:
    data = _json('sim_collect.json')
    one, two = data['runs']['1'], data['runs']['2']
    same = 'byte for byte the same bags' if data['same_bags'] else '**different bags**'
    return (f'- `python bench/bench_collect.py --sweeps {data["sweeps"] // 12}`: '
            f'`tactex sim collect` recorded the {data["sweeps"]} sweeps in {one / 60:.1f} min '
            f'with one worker and {two / 60:.1f} min with two (a local Ray instance, its start '
            f'included) in the same run: {data["speedup"]:.2f}x on the 2 cores of this '
            f'machine, {same} (load average {data["load_before"]:.1f} before, '
            f'{data["load_after"]:.1f} after; `bench/results/sim_collect.json`).\n')


def training() -> str:
    data = _json('training.json')
    rows = ['| model | epochs/s before | epochs/s after | after / before | same weights |',
            '|---|---|---|---|---|']
    rows += [f'| {r["model"]} | {r["before_epochs_per_s"]:.3f} | {r["after_epochs_per_s"]:.3f} '
             f'| {r["speedup"]:.2f}x | {"yes" if r["same_weights"] else "no"} |'
             for r in data['loop']]
    labels = ('1 cell x 1 thread', '1 cell x 2 threads', '2 cells x 1 thread')
    cells = ['| model | ' + ' | '.join(labels) + ' |', '|---|---|---|---|']
    cells += [f'| {r["model"]} | ' + ' | '.join(f'{r[label]:.3f}' for label in labels) + ' |'
              for r in data['parallel']]
    overhead = data['evaluation']
    return (f'Training cost on this CPU (`python bench/bench_training.py`: one epoch of each '
            f'model on {data["data"]}, one thread, the loop before this work (commit '
            f'{data["before_commit"]}) and after it in the same run; load average '
            f'{data["load_before"][0]:.1f} to {data["load_after"][0]:.1f}):\n\n'
            + '\n'.join(rows) + '\n\n'
            "The loop now gathers each epoch's shuffled windows once and slices batches from "
            'them, adds loss and hits up where the model runs (no host round trip per batch, '
            'which matters on a GPU) and predicts under `inference_mode`; it trains the same '
            'weights bit for bit. On the CPU the convolutions and LSTMs are nearly all of an '
            'epoch, so the loop itself had little to remove. What pays on two cores is how '
            'they are shared, in epochs/s summed over the cells running:\n\n'
            + '\n'.join(cells) + '\n\n'
            f'Evaluation is cheap: the test fold of {overhead["test_windows"]} windows is '
            f'classified in {overhead["predict_s"]:.2f} s against {overhead["epoch_s"]:.1f} s '
            f'for an epoch of {overhead["model"]}, and early stopping\'s check of the '
            f'held-out recordings adds about {100 * overhead["validation_share"]:.0f} % per '
            'epoch.\n')


def _option(command: str, name: str) -> str:
    """The value given to option `name` in a recorded command line."""
    words = command.split()
    return words[words.index(name) + 1]


def _grid_gaps(rows: list[dict], expected: int) -> list[str]:
    """What the kept comparison lacks of every model at 128, 256 and 512 samples."""
    from tactex_classify.models.registry import ALL_MODELS
    done = {(row['window'], row['model']): sum(scheme['cells'] for scheme
                                               in row['schemes'].values()) for row in rows}
    gaps = []
    for window in (128, 256, 512):
        missing = [model for model in ALL_MODELS if (window, model) not in done]
        partial = [f'{model} ({done[window, model]} of {expected} cells)' for model in ALL_MODELS
                   if done.get((window, model), expected) < expected]
        if len(missing) == len(ALL_MODELS):
            gaps.append(f'window {window} did not run')
        elif missing or partial:
            gaps.append(f'window {window} lacks ' + ', '.join(missing + partial))
    return gaps


def _kept_grid(name: str) -> tuple[dict, dict, list[dict]]:
    """A kept comparison's summary, its calls (run.json) and their `tactex compare` steps."""
    summary, run = _json(f'{name}/summary.json'), _json(f'{name}/run.json')
    grid = [step for call in run['calls'] for step in call['steps']
            if step['command'].startswith('tactex compare ')]
    return summary, run, grid


def compare() -> str:
    from tactex_classify.evaluation.grid_report import table
    summary, run, grid = _kept_grid('compare')
    settings = summary['settings']
    seeds = {int(_option(step['command'], '--seeds')) for step in grid}
    per_texture = {call['recordings_per_texture'] for call in run['calls']}
    if len(seeds) != 1 or len(per_texture) != 1:
        raise ValueError(f'the kept comparison mixes runs: seeds {seeds}, recordings per '
                         f'texture {per_texture}')
    seeds, per_texture = seeds.pop(), per_texture.pop()
    expected = seeds * settings['folds'] * 2
    cells = sum(scheme['cells'] for row in summary['rows'] for scheme in row['schemes'].values())
    minutes = sum(step['seconds'] for step in grid) / 60
    loads = [load for step in grid for load in step['load_average']]
    data = sorted(summary['data'].items(), key=lambda item: int(item[0]))
    windows = ', '.join(f'{d["windows"]} windows of {window} samples from {d["recordings"]} '
                        'recordings' for window, d in data)
    gaps = _grid_gaps(summary['rows'], expected)
    best = {}
    for row in summary['rows']:
        accuracy = row['schemes']['grouped']['accuracy']['mean']
        complete = sum(s['cells'] for s in row['schemes'].values()) == expected
        if complete and accuracy > best.get(row['window'], (0, ''))[0]:
            best[row['window']] = (accuracy, row['model'])
    headline = '; '.join(f'at {window} samples, {model} with {100 * accuracy:.1f} %'
                         for window, (accuracy, model) in sorted(best.items()))
    headline = headline or 'no row is complete'
    trained = [row['schemes']['grouped']['train_accuracy']['mean'] for row in summary['rows']
               if row['schemes']['grouped'].get('train_accuracy')]
    fitted = f'{100 * min(trained):.0f}-{100 * max(trained):.0f}'
    held_out = [row['schemes']['grouped']['accuracy']['mean'] for row in summary['rows']
                if row['schemes']['grouped'].get('train_accuracy')]
    chance = 100 / len(data[0][1]['classes'])
    status = ('**Incomplete**: ' + '; '.join(gaps) + '; the table holds only the cells that '
              'finished (last column).' if gaps else
              'Complete: every model at every window.')
    return (f'The kept comparison (`python bench/bench_compare.py --recordings {per_texture} '
            f'--folds {settings["folds"]} --epochs {settings["epochs"]} --seeds {seeds} '
            f'--windows W`, W = 128, 256, 512 one after the other; outputs in '
            f'`bench/results/compare/`): the first {per_texture} sweeps of each texture of '
            f'the synthetic set, whole recordings ({windows}), {settings["folds"]}-fold '
            f'cross-validation per scheme, {seeds} seed(s), every deep model trained for '
            f'**{settings["epochs"]} epochs** where the original trained 250, one thread per '
            "cell and two cells at a time on this machine's two shared cores: "
            f'{cells} cells in {minutes:.0f} min of wall time (the 1-minute load average '
            f'{min(loads):.1f}-{max(loads):.1f} as each window began and ended). {status} '
            'With so few epochs the deep models are far from converged: they reach '
            f'{fitted} % training accuracy (measured with '
            'batch statistics while training) but, evaluated with the BatchNorm running '
            "averages that Keras's momentum of 0.99 has barely moved in so few batches, they "
            f'score {100 * min(held_out):.0f}-{100 * max(held_out):.0f} % on held-out '
            f'recordings, where chance is {chance:.1f} %. Their rows measure what '
            f'{settings["epochs"]} epochs buy, not what the architectures can do; the '
            'baselines are the figures to trust here. Training time and latency were '
            'measured with another cell and other jobs on the same cores. Best honest '
            f'accuracy per window (complete rows): {headline}.\n\n'
            + table(summary['rows'], expected) + '\n'
            f'![accuracy]({FIGURES}/compare/accuracy.png)\n')


def online_latency() -> str:
    data = _json('online_latency.json')
    rows = data['rows']
    groups: dict[tuple[str, str], list[dict]] = {}
    for row in rows:
        groups.setdefault((row['model'], row['runtime_used']), []).append(row)

    def span(values: list[float]) -> str:
        return f'{min(values):.1f}-{max(values):.1f}'
    lines = ['| model | runtime | configurations | p50 ms | p99 ms | node p99 ms | bare model '
             'p50 ms | dropped |', '|---|---|---|---|---|---|---|---|']
    for (model, runtime), found in groups.items():
        lines.append(f'| {model} | {runtime} | {len(found)} | '
                     f'{span([r["p50_ms"] for r in found])} | '
                     f'{span([r["p99_ms"] for r in found])} | '
                     f'{span([r["node_p99_ms"] for r in found])} | '
                     f'{span([r["bare_p50_ms"] for r in found])} | '
                     f'{sum(r["dropped"] for r in found)} |')
    cnn = [r for r in rows if r['family'] == 'cnn']
    fast = [r for r in rows if r['family'] in ('cnn', 'minirocket')]
    dropped_350 = sum(r['dropped'] for r in rows if r['rate_hz'] == 350.0)
    estimates = [r['windows'] for r in rows]
    windows = sorted({r['window'] for r in rows})
    rates = sorted({r['rate_hz'] for r in rows})
    return ("End-to-end latency, a window's last sample arriving to its estimate (`python "
            f'bench/bench_online.py`, kept in `bench/results/online_latency.{{md,json}}`: '
            f'{len(rows)} configurations: {", ".join(dict.fromkeys(r["model"] for r in rows))} '
            'at windows '
            f'{", ".join(map(str, windows))} and {" and ".join(f"{r:g}" for r in rates)} Hz '
            f'with hop = window / 2, torch and onnxruntime side by side; {min(estimates)}-'
            f'{max(estimates)} estimates each, so a p99 is close to the largest of them; '
            'teensy_node and classifier_node SCHED_FIFO on one core; load average '
            f'{data["load_average_before"]:.1f} before, {data["load_average_after"]:.1f} after, '
            'other jobs on the same cores). Ranges are over windows, rates and runtimes '
            '(the per-configuration table is in the kept file):\n\n'
            + '\n'.join(lines) + '\n\n'
            f'Must: CNN p99 < 20 ms, met by {sum(r["p99_ms"] < 20.0 for r in cnn)} of '
            f'{len(cnn)} configurations; windows dropped at 350 Hz: {dropped_350}. Goal: p99 '
            f'< 5 ms for the CNN and MiniRocket, met by {sum(r["p99_ms"] < 5.0 for r in fast)} '
            f'of {len(fast)}. The bare model takes {span([r["bare_p50_ms"] for r in rows])} '
            'ms; the rest is the pipeline.\n')


def compare_long() -> str:
    from tactex_classify.evaluation.grid_report import table
    summary, run, grid = _kept_grid('compare_long')
    settings = summary['settings']
    command = grid[-1]['command']
    seeds = int(_option(command, '--seeds'))
    schemes = _option(command, '--cv')
    expected = seeds * settings['folds'] * (2 if schemes == 'both' else 1)
    per_texture = {call['recordings_per_texture'] for call in run['calls']}.pop()
    minutes = sum(step['seconds'] for step in grid) / 60
    loads = [load for step in grid for load in step['load_average']]
    rows = summary['rows']
    models = ','.join(sorted({row['model'] for row in rows}))
    windows = ','.join(str(w) for w in sorted({row['window'] for row in rows}))
    best = max(rows, key=lambda row: row['schemes']['grouped']['accuracy']['mean'])
    kept = _json('compare/summary.json')  # the 5-epoch grid of the docs' table
    short = next(r for r in kept['rows']
                 if r['model'] == best['model'] and r['window'] == best['window'])
    unfinished = [row['model'] for row in rows
                  if sum(v['cells'] for v in row['schemes'].values()) < expected]
    status = f' **Unfinished**: {", ".join(unfinished)}.' if unfinished else ''
    baselines = [r for r in kept['rows']
                 if r['window'] == best['window'] and r['model'] in ('minirocket', 'extratrees')]
    baseline = max(baselines, key=lambda r: r['schemes']['grouped']['accuracy']['mean'])
    fitted = [row['schemes']['grouped']['train_accuracy']['mean'] for row in rows]
    stopping = (f'stopped when the loss on {100 * settings["validation_fraction"]:.0f} % of the '
                'training recordings held out has not improved for '
                f'{settings["early_stopping"]} epochs (the epochs column is the one kept)'
                if settings['early_stopping'] else 'no early stopping')
    return (f'The deep models trained longer (`python bench/bench_compare.py --grid '
            f'compare_long --recordings {per_texture} --models {models} --windows {windows} '
            f'--cv {schemes} --folds {settings["folds"]} --epochs {settings["epochs"]} '
            f'--early-stopping {settings["early_stopping"]} --seeds {seeds}`, outputs in '
            '`bench/results/compare_long/`): the same recordings, grouped by recording, '
            f'{settings["epochs"]} epochs at most, {stopping}; '
            f'{sum(r["schemes"]["grouped"]["cells"] for r in rows)} cells in {minutes:.0f} min '
            f'on the two cores (load average {min(loads):.1f}-{max(loads):.1f}).{status} '
            f'{best["model"]} reaches {100 * best["schemes"]["grouped"]["accuracy"]["mean"]:.1f} '
            f'% on held-out recordings at {best["window"]} samples, against '
            f'{100 * short["schemes"]["grouped"]["accuracy"]["mean"]:.1f} % after '
            f'{kept["settings"]["epochs"]} epochs above: the deep '
            f'models now fit their training windows ({100 * min(fitted):.0f}-'
            f'{100 * max(fitted):.0f} %) but, with about '
            f'{round(per_texture * (settings["folds"] - 1) / settings["folds"])} training '
            'recordings per texture, generalise to new recordings less well than '
            f'{baseline["model"]} ({100 * baseline["schemes"]["grouped"]["accuracy"]["mean"]:.1f}'
            ' %) does on the same folds.\n\n'
            + table(rows, expected) + '\n')


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
    'observers': observers,
    'driver': driver, 'sim': sim, 'convert': convert, 'synthetic_set': synthetic_set,
    'textures': textures, 'init': init, 'kinematics': kinematics, 'sweep': sweep,
    'sim_collect': sim_collect, 'training': training, 'compare': compare,
    'compare_long': compare_long, 'online_latency': online_latency,
    'sensor_stats': sensor_stats, 'channels': channels, 'profiles': profiles,
    'architectures': architectures, 'window_voting': window_voting,
    'sim_to_real': sim_to_real, 'learning_curves': learning_curves}


def _wrapped(text: str) -> str:
    """Paragraphs wrapped at the docs' width (tables as they are, bullets indented)."""
    paragraphs = text.strip('\n').split('\n\n')
    return '\n\n'.join(part if part.startswith('|') else textwrap.fill(
        part, WIDTH, subsequent_indent='  ' if part.startswith('- ') else '',
        break_on_hyphens=False) for part in paragraphs) + '\n'


def render() -> dict[str, str]:
    """Every generated section, rendered from the kept outputs."""
    return {name: _wrapped(make()) for name, make in SECTIONS.items()}


def pages() -> dict[Path, str]:
    """The docs pages that may hold generated sections (docs/*/*.md), and their text."""
    return {path: path.read_text(encoding='utf-8') for path in sorted(DOCS.glob('*/*.md'))
            if path.parent.name not in ('results', 'reference')}


def placed(texts: dict[Path, str], sections: dict[str, str]) -> dict[str, Path]:
    """The page of each generated section.

    Raises:
        ValueError: a marker names no known section, a known one has no marker, or one
            has more than one.
    """
    found = [(match['name'], path) for path, text in texts.items()
             for match in SECTION.finditer(text)]
    names = [name for name, _ in found]
    unknown = sorted(set(names) - set(sections))
    missing = sorted(set(sections) - set(names))
    twice = sorted({name for name in names if names.count(name) > 1})
    if unknown or missing or twice:
        raise ValueError(f'docs markers: unknown {unknown}, missing {missing}, twice {twice}')
    return {name: path for name, path in found}


def rewrite(text: str, sections: dict[str, str]) -> str:
    """`text` with every generated section replaced by its rendering.

    Raises:
        ValueError: a marker names no known section.
    """
    unknown = sorted({match['name'] for match in SECTION.finditer(text)} - set(sections))
    if unknown:
        raise ValueError(f'docs markers: unknown {unknown}')
    return SECTION.sub(lambda m: m.group(1) + sections[m['name']] + m.group(4), text)


def stale(text: str, sections: dict[str, str]) -> list[str]:
    """Names of the sections whose text differs from their rendering."""
    return [m['name'] for m in SECTION.finditer(text) if m['body'] != sections[m['name']]]


def main(argv: list[str] | None = None) -> int:
    """Rewrite the docs pages' generated sections (or, with --check, only compare)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--check', action='store_true', help='compare only; exit 1 if stale')
    args = parser.parse_args(argv)
    texts = pages()
    sections = render()
    placed(texts, sections)
    if args.check:
        names = [name for text in texts.values() for name in stale(text, sections)]
        if names:
            print(f'error: docs sections out of date: {", ".join(names)}; run make results',
                  file=sys.stderr)
            return 1
        return 0
    for path, text in texts.items():
        if (new := rewrite(text, sections)) != text:
            path.write_text(new, encoding='utf-8')
    return 0


if __name__ == '__main__':
    sys.exit(main())
