# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Result sections of learning: the synthetic set, training, model grids, transfer."""

import itertools
import json
from pathlib import Path

import numpy as np
import results_common
from results_common import (
    device_mark,
    DEVICE_NOTE,
    FIGURES,
    kept_json,
    RESULTS,
    TEXTURE_MODELS,
)


def _texture_run() -> dict:
    return kept_json('textures/run.json')


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
        metrics = kept_json(f'textures/{model}/metrics.json')
        grouped, stratified = (metrics['schemes'][s] for s in ('grouped', 'stratified'))
        eight = next(row for row in grouped['sequence'] if row['windows'] == 8)
        settings = metrics['settings']
        label = TEXTURE_MODELS[model] if model in TEXTURE_MODELS else (
            f'{model}, modern profile, {settings["scaling"]} scaling, at most '
            f'{settings["epochs"]} epochs' if settings.get('profile') == 'modern' else
            f'{model}, {settings["epochs"]} epochs, {settings["init"]} initialisation')
        lines.append(f'| {label} | {100 * grouped["accuracy"]:.1f} % | '
                     f'{100 * stratified["accuracy"]:.1f} % | {100 * eight["accuracy"]:.1f} % '
                     f'({eight["touch_s"]:.1f} s of touch) |')
    leak = [100 * (kept_json(f'textures/{m}/metrics.json')['schemes']['stratified']['accuracy']
                   - kept_json(f'textures/{m}/metrics.json')['schemes']['grouped']['accuracy'])
            for m in run['models']]
    confused = []
    for model in run['models']:
        grouped = kept_json(f'textures/{model}/metrics.json')['schemes']['grouped']
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
    data = kept_json('init.json')
    cap = data['cap']
    lines = ['| model | PyTorch init | Keras init |', '|---|---|---|']
    for model in dict.fromkeys(row['model'] for row in data['results']):
        cells = [', '.join(str(row['epochs']) if row['epochs'] else
                           f'>{cap} ({100 * row["final_train_accuracy"]:.0f} %)'
                           for row in data['results']
                           if row['model'] == model and row['init'] == init_name)
                 for init_name in ('pytorch', 'keras')]
        lines.append(f'| {model} | {cells[0]} | {cells[1]} |')
    command = (f'python bench/bench_init.py --models {" ".join(data["models"])} --seeds '
               f'{" ".join(map(str, data["seeds"]))} --recordings-per-class '
               f'{data["recordings_per_class"]} --cap {cap}')
    source = (f'the set {Path(data["data"]).name}' if data['data'] else
              'the synthetic set it collects (default scene, 25 sweeps per texture)')
    return (f'Epochs to {100 * data["target"]:.0f} % training accuracy from each '
            f'initialisation (`{command}`: {data["windows"]} windows of '
            f'{data["recordings_per_class"]} recordings per class of {source}, at most '
            f'{cap} epochs):\n\n'
            + '\n'.join(lines) + '\n')


def sensor_stats() -> str:
    run, table = kept_json('sensor_stats/run.json'), kept_json('sensor_stats/stats.json')
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
    data = kept_json('channels/ablation.json')
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
    data = kept_json('profiles/profiles.json')
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
    data = kept_json('architectures/architectures.json')
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
    data = kept_json('window_voting/window_voting.json')
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
    data = kept_json('sim_to_real/sim_to_real.json')
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
    data = kept_json('learning_curves/learning_curves.json')
    sizes = data['sizes']
    table = ['| model | ' + ' | '.join(f'n = {n}' for n in sizes) + ' |',
             '|---|' + '---|' * len(sizes)]
    for model in data['models']:
        cells = []
        for n in sizes:
            point = data['points'].get(f'{model}@{n}')
            stalled = point and 'stalled at chance' in point.get('unconverged', [])
            cells.append('-' if point is None else f'{100 * np.mean(point["accuracy"]):.1f} % '
                         f'({np.mean(point["seconds"]):.0f} s)' + device_mark(point)
                         + ' (stalled)' * bool(stalled))
        table.append(f'| {TEXTURE_MODELS.get(model, model)} | ' + ' | '.join(cells) + ' |')
    calls = data.get('calls', [data['command']])
    how = (f', joining {len(calls)} calls run side by side on the two cores, one thread each, '
           'listed in `learning_curves.md` (the seconds include that sharing)'
           if len(calls) > 1 else '')
    missing = ('; `-`: not run' if any(f'{m}@{n}' not in data['points'] for m in data['models']
                                       for n in sizes) else '')
    return (f'Learning curves (`{data["command"].strip()}`{how}): accuracy on '
            f'{data["test_windows"]} windows of {data["test"]} held-out recordings per texture '
            'against the recordings per texture the model trained on, with the training '
            f'seconds of each point; {data["draws"]} draw(s); deep models with the `modern` '
            f'profile and per-window scaling, at most {data["epochs"]} epochs; chance '
            f'{100 * data["chance"]:.1f} %{missing}'
            + ('; (stalled): a training whose loss never left chance in all its epochs'
               if any('stalled at chance' in point.get('unconverged', [])
                      for point in data['points'].values()) else '')
            + (f'; {DEVICE_NOTE}' if any(
                device_mark(point) for point in data['points'].values()) else '')
            + '; `bench/results/learning_curves/`:\n\n'
            + '\n'.join(table) + '\n\n![learning curves]'
            f'({FIGURES}/learning_curves/learning_curves.png)\n')


def training() -> str:
    data = kept_json('training.json')
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
    summary, run = kept_json(f'{name}/summary.json'), kept_json(f'{name}/run.json')
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
        complete = sum(s['cells'] for s in row['schemes'].values()) == expected
        leader = best.get(row['window'])
        if complete and (leader is None or _mean_grouped(row) > _mean_grouped(leader)):
            best[row['window']] = row
    headline = '; '.join(
        f'at {window} samples, {row["model"]} with {100 * _mean_grouped(row):.1f} % '
        f'({100 * row["schemes"]["stratified"]["accuracy"]["mean"]:.1f} % leaky)'
        for window, row in sorted(best.items()))
    headline = headline or 'no row is complete'
    trained = [row['schemes']['grouped']['train_accuracy']['mean'] for row in summary['rows']
               if row['schemes']['grouped'].get('train_accuracy')]
    fitted = f'{100 * min(trained):.0f}-{100 * max(trained):.0f}'
    held_out = [_mean_grouped(row) for row in summary['rows']
                if row['schemes']['grouped'].get('train_accuracy')]
    chance = 100 / len(data[0][1]['classes'])
    status = ('**Incomplete**: ' + '; '.join(gaps) + '; the table holds only the cells that '
              'finished (last column).' if gaps else
              'Complete: every model at every window.')
    return (f'The kept comparison (`python bench/bench_compare.py --recordings {per_texture} '
            f'--folds {settings["folds"]} --epochs {settings["epochs"]} --seeds {seeds} '
            f'--windows {",".join(window for window, _ in data)}`, in {len(run["calls"])} '
            f'call(s); outputs in '
            f'`bench/results/compare/`): the first {per_texture} sweeps of each texture of '
            f'the synthetic set, whole recordings ({windows}), {settings["folds"]}-fold '
            f'cross-validation per scheme, {seeds} seed(s), every deep model trained for '
            f'**{settings["epochs"]} epochs** where the original trained 250, one thread per '
            "cell and two cells at a time on this machine's two shared cores: "
            f'{cells} cells in {minutes:.0f} min of wall time (the 1-minute load average '
            f'{min(loads):.1f}-{max(loads):.1f} as each call began and ended). {status} '
            'With so few epochs the deep models are far from converged: they reach '
            f'{fitted} % training accuracy (measured with '
            'batch statistics while training) but, evaluated with the BatchNorm running '
            "averages that Keras's momentum of 0.99 has barely moved in so few batches, they "
            f'score {100 * min(held_out):.0f}-{100 * max(held_out):.0f} % on held-out '
            f'recordings, where chance is {chance:.1f} %. Their rows measure what '
            f'{settings["epochs"]} epochs buy, not what the architectures can do; the '
            'baselines are the figures to trust here. Training time and latency were '
            'measured with another cell running on the same cores. Best honest '
            f'accuracy per window (complete rows), beside the same row with windows of one '
            f'recording on both sides of the split: {headline}.\n\n'
            + table(summary['rows'], expected) + '\n'
            f'![accuracy]({FIGURES}/compare/accuracy.png)\n')


def compare_long() -> str:
    from tactex_classify.evaluation.grid_report import table
    from tactex_classify.models.registry import BASELINES
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
    best = max(rows, key=_mean_grouped)
    kept = kept_json('compare/summary.json')  # the 5-epoch grid of the docs' table
    short = next(r for r in kept['rows']
                 if r['model'] == best['model'] and r['window'] == best['window'])
    unfinished = [row['model'] for row in rows
                  if sum(v['cells'] for v in row['schemes'].values()) < expected]
    status = f' **Unfinished**: {", ".join(unfinished)}.' if unfinished else ''
    baselines = [r for r in kept['rows']
                 if r['window'] == best['window'] and r['model'] in BASELINES]
    baseline = max(baselines, key=_mean_grouped)
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
            f'{best["model"]} reaches {100 * _mean_grouped(best):.1f} '
            f'% on held-out recordings at {best["window"]} samples (chance '
            f'{100 / len(summary["data"][str(best["window"])]["classes"]):.1f} %), against '
            f'{100 * _mean_grouped(short):.1f} % after '
            f'{kept["settings"]["epochs"]} epochs above: the deep '
            f'models reach {100 * min(fitted):.0f}-{100 * max(fitted):.0f} % on their '
            f'training windows and, with about '
            f'{round(per_texture * (settings["folds"] - 1) / settings["folds"])} training '
            f'recordings per texture, {_against(best, baseline)} on the same folds.\n\n'
            + table(rows, expected) + '\n')


def _against(deep: dict, baseline: dict) -> str:
    """How the best deep row generalises to new recordings beside the best baseline."""
    ours, theirs = _mean_grouped(deep), _mean_grouped(baseline)
    verdict = 'at least as well as' if ours >= theirs else 'less well than'
    return (f'{deep["model"]} generalises to new recordings {verdict} {baseline["model"]} '
            f'({100 * theirs:.1f} %) does')


def _mean_grouped(row: dict) -> float:
    return row['schemes']['grouped']['accuracy']['mean']


def _first_gpu_grid() -> dict:
    """The kept GPU grid's pace, and what it made of the rest and of the issue's full grid.

    pace: median epochs per second of its deep cells; epochs: their mean epochs; left_min:
    the minutes its missing deep cells need at that pace with its cells per GPU; full_h:
    the hours of the full grid (three windows, both schemes: twice its one window and
    scheme).
    """
    from tactex_classify.models.registry import BASELINES
    _, _, grid = _kept_grid('compare_gpu')
    first = grid[0]['command']
    deep_models = [m for m in _option(first, '--models').split(',') if m not in BASELINES]
    deep = [cell for cell in _cells('compare_gpu').values()
            if cell['cell']['model'] not in BASELINES]
    pace = float(np.median([cell['epochs_per_s'] for cell in deep]))
    epochs = float(np.mean([cell['epochs_run'] for cell in deep]))
    left = len(deep_models) * int(_option(first, '--seeds')) * \
        int(_option(first, '--folds')) - len(deep)
    left_min = left * epochs / (pace * int(_option(first, '--cells-per-gpu'))) / 60
    elapsed_min = sum(step['seconds'] for step in grid) / 60
    return {'pace': pace, 'left_cells': left, 'left_min': left_min,
            'full_h': 2 * (elapsed_min + left_min) / 60}


def compare_gpu() -> str:
    """The comparison on the physical sensor run on a lent GPU: what finished, and its pace."""
    import csv

    from tactex_classify.evaluation.grid_report import table
    from tactex_classify.models.registry import BASELINES
    summary, run, grid = _kept_grid('compare_gpu')
    settings, first = summary['settings'], grid[0]['command']
    seeds, folds = int(_option(first, '--seeds')), settings['folds']
    machine = _gpu_machine(run, 'GPU grid')
    gpu = machine['gpu']
    models = _option(first, '--models').split(',')
    deep_models = [model for model in models if model not in BASELINES]
    sharing = [int(_option(step['command'], '--cells-per-gpu')) for step in grid]
    calls = ', '.join(
        f'{step["seconds"] / 60:.1f} min with '
        f'{_option(step["command"], "--models").count(",") + 1} models, {shared} cells per GPU'
        for step, shared in zip(grid, sharing, strict=True))
    stopped = all(step['returncode'] not in (0, None) for step in grid)
    kept_cells = _cells('compare_gpu')
    cells = list(kept_cells.values())
    (data,) = summary['data'].values()
    classes = len(data['classes'])
    deep = [cell for cell in cells if cell['cell']['model'] not in BASELINES]
    estimate = _first_gpu_grid()
    with open(RESULTS / 'compare_gpu' / 'gpu_utilisation.csv', encoding='utf-8') as handle:
        busy = [int(row['utilization_gpu_percent']) for row in csv.DictReader(handle)]
    busy = np.percentile([value for value in busy if value > 0], [10, 50])
    rows = {row['model']: row for row in summary['rows']}
    unconverged = [row for row in summary['rows'] if row['not_converged']]
    ranked = sorted(rows, key=lambda name: -_mean_grouped(rows[name]))

    def grouped(model: str) -> str:
        return f'{model} {100 * _mean_grouped(rows[model]):.1f} % over ' \
               f'{rows[model]["schemes"]["grouped"]["cells"]} fold(s)'
    best_baseline = next(name for name in ranked if name in BASELINES)
    deep_rows = [name for name in ranked if name not in BASELINES]
    above = sum(_mean_grouped(rows[name]) > _mean_grouped(rows[best_baseline])
                for name in deep_rows)
    unfinished = [model for model in deep_models if model not in rows]
    total = len(models) * seeds * folds
    levels = kept_json('hydra_levels.json')
    (ours, per_fold), (theirs, before) = levels['accuracy'].items()
    change = levels['difference']
    with_it, without = (100 * np.mean(list(values.values())) for values in (per_fold, before))
    hydra = ("The hydra and multirocket_hydra rows predate HYDRA's kernel normalisation per "
             f"channel: on the first seed's {len(per_fold)} folds, `python "
             f'bench/bench_hydra_levels.py` gives HYDRA {with_it:.1f} % with it ({ours}) '
             f'against {without:.1f} % ({theirs}, these rows), {100 * change["mean"]:+.1f} '
             f'points [{100 * change["low"]:+.1f}, {100 * change["high"]:+.1f}] paired: still '
             'far below MiniRocket.')
    return (f'The comparison on the physical sensor, run on a GPU (`python '
            f'bench/bench_compare.py --grid compare_gpu --recordings 20 --windows 128 --cv '
            f'grouped --folds {folds} --seeds {seeds} --epochs {settings["epochs"]} '
            f'--early-stopping {settings["early_stopping"]} --profile {settings["profile"]} '
            f'--scaling {settings["scaling"]} --device cuda --cpus {machine["cpu_count"]} '
            f'--cells-per-gpu {sharing[0]} --models {",".join(models)}`, outputs in '
            f'`bench/results/compare_gpu/`). **Device: one {gpu["name"]}** '
            f'({gpu["memory_gib"]:.0f} GiB, torch {gpu["torch"]}) with {machine["cpu_count"]} '
            'cores, lent for 15 minutes a session, like the two sections on many cells on one '
            'GPU and the full grid below; every other figure on this page came from the two '
            f'CPU cores. Calls: {calls}' + (', each stopped at its time limit'
                                                   if stopped else '') +
            f'. **Incomplete**: {len(cells)} of {total} cells ({len(deep)} of them deep '
            'models), so most rows hold one or two folds of the first seed: read them as a '
            f'first look, not a ranking. Best so far: {grouped(deep_rows[0])}, against the '
            f'best baseline {grouped(best_baseline)}; {above} of the {len(deep_rows)} deep '
            'models with a finished cell score above it'
            + (f' ({", ".join(unfinished)}: none finished)' if unfinished else '') + '.'
            + (' Not converged: ' + '; '.join(
                f'{row["model"]} ({_unconverged_cells(row["model"], kept_cells, classes)})'
                for row in unconverged) + '.' if unconverged else '') + '\n\n'
            f'Pace: {sharing[0]} deep-model cells shared the GPU, each training at a median '
            f'{estimate["pace"]:.2f} epochs per second (batch 32, augmentation on the cores), '
            f'while the GPU reported {busy[1]:.0f} % busy (10th percentile {busy[0]:.0f} %): '
            'the processes took turns on it, so per-step overhead, not arithmetic, set the '
            'pace. At the pace of the cells that finished, the '
            f'{estimate["left_cells"]} deep cells left need about {estimate["left_min"]:.0f} '
            'min more (the baselines run beside them on the cores), and the full grid of the '
            f'issue (three windows, both schemes, one seed: {2 * total} cells) about '
            f'{estimate["full_h"]:.1f} h: the goal of one hour on a GPU is not met with this '
            'setup ([Many cells on one GPU](#many-cells-on-one-gpu) says what changes it).\n\n'
            + table(summary['rows'], seeds * folds) + '\n' + hydra + '\n\n'
            f'![accuracy]({FIGURES}/compare_gpu/accuracy.png)\n')


def _gpu_machine(run: dict, grid: str) -> dict:
    """The one machine, with a GPU, that ran every call of a kept grid."""
    machines = {json.dumps(call['machine'], sort_keys=True) for call in run['calls']}
    if len(machines) != 1 or not run['calls'][0]['machine']['gpu']:
        raise ValueError(f'the kept {grid} mixes machines or ran without a GPU: {machines}')
    return run['calls'][0]['machine']


def _grid_projection(name: str, models: list[str], windows: list[int], per_scheme: int) -> dict:
    """How far a kept grid of both schemes is and, at the pace it measured, what is left.

    Deep models (on the GPU) and baselines (on the cores) are paced apart. For each,
    together: the cells that trained at once on average (their training seconds over the
    grid's wall seconds); left_min: the minutes its missing cells need at that pace, each
    costing the mean training seconds of its model, window and scheme's finished cells
    (else its model and window's, else its model's, else the kind's). The grid's minutes
    left are the longer of the two; whole_min adds the minutes it ran.
    """
    from tactex_classify.models.registry import BASELINES, SCHEMES
    _, _, grid = _kept_grid(name)
    cells = _cells(name)
    wall_s = sum(step['seconds'] for step in grid)
    if not cells or not wall_s:
        raise ValueError(f'the kept grid {name} has no finished cells or no timed call')
    seconds: dict[tuple, list[float]] = {}
    for (model, window, _, _, scheme), cell in cells.items():
        kind = model in BASELINES
        for key in ((model, window, scheme), (model, window), (model,), (kind,)):
            seconds.setdefault(key, []).append(cell['train_s'])
    pace = {}
    for kind, label in ((False, 'deep'), (True, 'baselines')):
        left_s = 0.0
        for model, window, scheme in itertools.product(
                [m for m in models if (m in BASELINES) == kind], windows, SCHEMES):
            spent = seconds.get((model, window, scheme), [])
            like = spent or next(seconds[key] for key in ((model, window), (model,), (kind,))
                                 if key in seconds)
            left_s += (per_scheme - len(spent)) * float(np.mean(like))
        together = sum(seconds[kind,]) / wall_s
        pace[label] = {'together': together, 'left_min': left_s / together / 60}
    left_min = max(kind['left_min'] for kind in pace.values())
    return {'done': len(cells), 'wall_min': wall_s / 60, **pace, 'left_min': left_min,
            'whole_min': wall_s / 60 + left_min}


def _full_grid() -> dict:
    """The kept full GPU grid: its summary, calls, steps, models, windows and projection."""
    from tactex_classify.models.registry import ALL_MODELS
    summary, run, grid = _kept_grid('compare_gpu_full')
    command = grid[-1]['command']
    if _option(command, '--cv') != 'both':
        raise ValueError('the kept full GPU grid runs both schemes')
    models = (_option(command, '--models').split(',') if '--models' in command.split()
              else list(ALL_MODELS))
    windows = sorted(int(window) for window in summary['data'])
    seeds, folds = int(_option(command, '--seeds')), summary['settings']['folds']
    return {'summary': summary, 'run': run, 'grid': grid, 'command': command,
            'models': models, 'windows': windows, 'seeds': seeds, 'folds': folds,
            'total': len(models) * len(windows) * 2 * seeds * folds,
            'projection': _grid_projection('compare_gpu_full', models, windows, seeds * folds)}


def compare_gpu_full() -> str:
    """The issue's full grid on a lent GPU: how far it is, its measured pace, what it shows."""
    from tactex_classify.evaluation.grid_report import table
    from tactex_classify.models.registry import BASELINES
    full = _full_grid()
    summary, run, grid, command = full['summary'], full['run'], full['grid'], full['command']
    windows, seeds, folds = full['windows'], full['seeds'], full['folds']
    total, projection = full['total'], full['projection']
    machine = _gpu_machine(run, 'full GPU grid')
    gpu = machine['gpu']
    deep, baselines = projection['deep'], projection['baselines']
    calls = ', '.join(f'{step["seconds"] / 60:.1f} min' for step in grid)
    stopped = all(step['returncode'] not in (0, None) for step in grid)
    rebuilt = [number for number, call in enumerate(run['calls'], 1) if 'note' in call]
    recordings = {call['recordings_per_texture'] for call in run['calls']}.pop()
    rows = summary['rows']

    def best(window: int, scheme: str, baseline: bool) -> str:
        ranked = [row for row in rows if row['window'] == window and scheme in
                  row['schemes'] and (row['model'] in BASELINES) == baseline and
                  not row['not_converged']]
        row = max(ranked, key=lambda row: row['schemes'][scheme]['accuracy']['mean'])
        values = row['schemes'][scheme]
        return f'{row["model"]} {100 * values["accuracy"]["mean"]:.1f} % ({values["cells"]})'

    def leaky_gain(baseline: bool) -> list[float]:
        return [100 * (row['schemes']['stratified']['accuracy']['mean'] - _mean_grouped(row))
                for row in rows if (row['model'] in BASELINES) == baseline and
                not row['not_converged'] and {'grouped', 'stratified'} <= set(row['schemes'])]
    honest = '; '.join(f'{window}: {best(window, "grouped", False)} against '
                       f'{best(window, "grouped", True)}' for window in windows)
    leaky = '; '.join(f'{window}: {best(window, "stratified", True)}' for window in windows)
    gains = {kind: leaky_gain(kind == 'baselines') for kind in ('baselines', 'deep models')}
    gains_text = ', '.join(f'the {kind} {np.median(values):+.0f} points (median of '
                           f'{len(values)} rows, {min(values):+.0f} to {max(values):+.0f})'
                           for kind, values in gains.items())
    projected = projection['whole_min']
    return (f"The issue's full grid on a GPU (`{_bench_command(command, recordings, windows)}`, "
            'outputs in `bench/results/compare_gpu_full/`): every model at every window, both '
            f'schemes, {folds} folds, {seeds} seed{"s" if seeds > 1 else ""}, {total} cells, '
            f"on the first {recordings} sweeps per texture of the learning curves' set "
            "(grid.json keeps the datasets' digests; a resumed call needs the same data"
            + _data_recipe('compare_gpu_full', run.get('data_recipe')) + '). '
            f'**Device: one {gpu["name"]}** (torch {gpu["torch"]}) with '
            f'{machine["cpu_count"]} cores. Calls: {calls}'
            + (', each stopped at its time limit' if stopped else '')
            + (f' (call {", ".join(map(str, rebuilt))}: its entry in run.json was rebuilt '
               'from its log, as the entry says)' if rebuilt else '') +
            f'. **Incomplete: {projection["done"]} of {total} cells**, in the order the grid '
            'runs them (fold by fold), so each row holds its first folds.\n\n'
            f'**Pace, measured on this grid.** In {projection["wall_min"]:.1f} min of the '
            f"grid's wall time (each call's start included), the deep models' finished cells "
            f'trained {deep["together"]:.1f} at once on average (on the GPU) and the '
            f"baselines' {baselines['together']:.1f} (on the cores). At those paces the "
            f'{total - projection["done"]} cells left (each as long as the finished cells of '
            f'its model, window and scheme) need about {deep["left_min"]:.0f} min on the GPU '
            f'and {baselines["left_min"]:.0f} min on the cores, side by side: the whole grid '
            f'about {projected:.0f} min, '
            + ('within' if projected <= 60 else 'beyond') + ' the hour of the goal. It is a '
            'projection until a lent GPU finishes the grid: its last cells may train with '
            'fewer beside them, and each further call spends about 20 s starting.\n\n'
            f'**What it shows so far.** Grouped by recording, the best deep model against the '
            f'best baseline (cells in brackets): {honest}. Leaky, the best baseline: {leaky}. '
            f'Leaky splits add to grouped accuracy {gains_text}: windows of one recording on '
            'both sides of the split flatter the baselines most (a leaky figure here is '
            'mostly one fold).\n\n'
            + table(rows, seeds * folds * 2) + '\n'
            f'![accuracy]({FIGURES}/compare_gpu_full/accuracy.png)\n')


def _data_recipe(grid: str, recipe: dict | None) -> str:
    """How a kept grid's data are built again, from run.json's data_recipe, if it has one."""
    if not recipe or not recipe['code'] or recipe['code'].endswith('-dirty') or recipe['bags']:
        return ''  # built from bags or from changed code: no command builds them again
    minutes = sum(step['seconds'] for step in recipe['steps']) / 60
    workers = _option(recipe['steps'][0]['command'], '--workers')  # the collect step's
    return (f', which `python bench/bench_compare.py --grid {grid} --recordings '
            f'{recipe["recordings_per_texture"]} --windows '
            f'{",".join(map(str, recipe["windows"]))} --sweeps {recipe["sweeps"]} --code '
            f'{recipe["code"][:12]} --data-only` builds again with the code of that commit and '
            f'checks against them: {minutes:.0f} min with {workers} workers')


def _bench_command(command: str, recordings: int, windows: list[int]) -> str:
    """The bench_compare call that runs a kept grid's `tactex compare` step."""
    words = command.split()
    options = ' '.join(f'{name} {_option(command, name)}' for name in (
        '--cv', '--folds', '--seeds', '--epochs', '--early-stopping', '--profile', '--scaling',
        '--device', '--cells-per-gpu', '--cpus') if name in words)
    grid = Path(_option(command, '--out')).name
    return (f'python bench/bench_compare.py --grid {grid} --recordings {recordings} '
            f'--windows {",".join(map(str, windows))} {options}'
            + (' --mps' if '--mps' in words else ''))


def gpu_pace() -> str:
    """How fast cells train together on the lent GPU, and what that makes of the full grid."""
    from tactex_classify.models.modern_architectures import ENSEMBLE_MEMBERS
    from tactex_classify.models.registry import BASELINES, DEEP_MODELS
    calls = kept_json('gpu_pace.json')['calls']
    machine = calls[-1]['machine']
    runs = [(number, run) for number, call in enumerate(calls, 1) for run in call['runs']
            if run['cell_epochs_per_s']]

    def best(model: str, **options) -> dict:
        return max((run for _, run in runs if run['model'] == model and
                    all(run.get(k, False) == v for k, v in options.items())),
                   key=lambda run: run['cell_epochs_per_s'])

    def pace(run: dict) -> str:
        return f'{run["cell_epochs_per_s"]:.1f} cell-epochs/s'
    rows = ['| call | model | cells at once | MPS | cuDNN autotune | epochs/s a cell | '
            'cell-epochs/s (GPU) | vs one cell | GPU busy % | host / GPU ms a step |',
            '|---|---|---|---|---|---|---|---|---|---|']
    for number, run in runs:
        profile, busy = run.get('profile'), run['gpu_busy_percent']
        rows.append('| ' + ' | '.join([
            str(number), run['model'], str(run['cells']), 'yes' if run['mps'] else '-',
            'yes' if run.get('autotune') else '-', f'{run["median_epochs_per_s"]:.2f}',
            f'{run["cell_epochs_per_s"]:.2f}',
            f'{run["vs_one_cell"]:.2f}' if 'vs_one_cell' in run else '-',
            '-' if busy is None or profile else f'{busy:.0f}',
            f'{profile["host_ms_per_step"]:.1f} / {profile["gpu_busy_ms_per_step"]:.1f} '
            f'({profile["gpu_operations_per_step"]:.0f} GPU operations)' if profile else '-',
        ]) + ' |')
    small, inception = 'cnn_3', 'inception_time'
    alone_small = best(small, cells=1)['profile']
    plain = {cells: best(small, mps=False, cells=cells) for cells in (6, 12, 16)}
    shared = {cells: best(small, mps=True, cells=cells) for cells in (6, 12, 16)}
    gain = shared[12]['cell_epochs_per_s'] / plain[12]['cell_epochs_per_s']
    alone_it, tuned_it = best(inception, cells=1, autotune=False), \
        best(inception, cells=1, autotune=True)
    together_it = best(inception, cells=12, mps=True, autotune=True)
    repeats = [run['cell_epochs_per_s'] for _, run in runs if run['model'] == inception and
               run['cells'] == 1 and not run.get('autotune')]
    # The issue's full grid at tactex's GPU setting (MPS, autotune), from the kept grids'
    # epochs per cell; a model not measured here is scaled by its seconds per epoch against
    # cnn_3's in the first GPU grid, where both shared the GPU alike.
    now_small = best(small, mps=True, autotune=True)
    first, converged = _cells('compare_gpu'), _cells('compare_converged')
    kept = {**first, **converged}

    def mean_of(model: str, cells: dict, value) -> float:
        return float(np.mean([value(cell) for key, cell in cells.items() if key[0] == model]))
    epochs = {m: mean_of(m, kept, lambda cell: cell['epochs_run']) for m in DEEP_MODELS
              if any(key[0] == m for key in kept)}
    epochs['inception_time_ensemble'] = epochs[inception]
    per_epoch = {m: mean_of(m, first, lambda cell: cell['train_s'] / cell['epochs_run'])
                 for m in DEEP_MODELS if any(key[0] == m for key in first)}
    throughput = {m: now_small['cell_epochs_per_s'] * per_epoch[small] / per_epoch[m]
                  for m in per_epoch}
    throughput[inception] = together_it['cell_epochs_per_s']
    throughput['inception_time_ensemble'] = throughput[inception] / ENSEMBLE_MEMBERS
    per_model = 3 * 2 * 5  # windows 128/256/512, both schemes, 5 folds
    deep_min = sum(per_model * epochs[m] / throughput[m] for m in DEEP_MODELS) / 60
    single_thread_s = sum(mean_of(m, converged, lambda cell: cell['train_s'])
                          for m in BASELINES)
    baseline_min = per_model * single_thread_s / machine['cpu_count'] / 60
    it_cpu_s = mean_of(inception, converged, lambda cell: cell['train_s'])
    it_cpu_cells = sum(key[0] == inception for key in converged)
    cpu_cores = _kept_grid('compare_converged')[1]['calls'][0]['machine']['cpu_count']
    ensemble_cpu_h = per_model * ENSEMBLE_MEMBERS * it_cpu_s / cpu_cores / 3600
    scaled = sorted(m for m in DEEP_MODELS if m not in (small, inception,
                                                         'inception_time_ensemble'))
    summed = [number for number, call in enumerate(calls, 1) if any(
        run.get('throughput_over') == 'sum of cell medians' for run in call['runs'])]
    calls_text = '; '.join(
        f'call {number}: `{call["command"]}`, '
        f'{sum(run["wall_s"] for run in call["runs"]) / 60:.1f} min'
        for number, call in enumerate(calls, 1))
    return (
        f'Measured with `python bench/bench_gpu_pace.py` on one {machine["gpu"]["name"]} with '
        f'{machine["cpu_count"]} cores (torch {machine["gpu"]["torch"]}), kept in '
        f'`bench/results/gpu_pace.json` ({calls_text}): N trainings of a grid cell started at '
        "once (fold 1 of the GPU grid's data, modern profile, per-window scaling, batch 32), "
        'each timed over its epochs after the first. '
        + (f'In call(s) {", ".join(map(str, summed))} the throughput adds up each cell\'s '
           'median epoch pace and the GPU busy column averages the whole run (later calls '
           'count both over the span in which every cell trained only).' if summed else
           'Throughput and GPU busy count the span in which every cell trained only.')
        + '\n\n'
        f"**The host, not the GPU, set cnn_3's pace.** Alone, a step took "
        f'{alone_small["host_ms_per_step"]:.1f} ms of wall time but '
        f'{alone_small["gpu_busy_ms_per_step"]:.1f} ms of GPU time '
        f'({alone_small["gpu_operations_per_step"]:.0f} GPU operations a step, each launched '
        'from Python). Without MPS the throughput stopped growing at 6 cells '
        f'({pace(plain[6])}; 12 cells {pace(plain[12])}, 16 cells {pace(plain[16])}): the '
        "processes' kernels take turns on the GPU. Under NVIDIA's Multi-Process Service they "
        f'run side by side and it kept growing: 6 cells {pace(shared[6])}, 12 cells '
        f'{pace(shared[12])} ({gain:.1f} times the same cells without it), 16 cells '
        f'{pace(shared[16])}.\n\n'
        "**cuDNN's default algorithms set InceptionTime's pace.** Alone, its step took "
        f'{alone_it["profile"]["gpu_busy_ms_per_step"]:.1f} ms of GPU time for '
        f'{alone_it["profile"]["host_ms_per_step"]:.1f} ms of wall time (its 39-, 19- and '
        '9-tap convolutions), so more cells at once gained little (12 cells: '
        f'{best(inception, cells=12, mps=False)["vs_one_cell"]:.2f} times one cell). With '
        'cuDNN timing its algorithms once per shape (`torch.backends.cudnn.benchmark`, what '
        "tactex's training now does on a GPU), a step took "
        f'{tuned_it["profile"]["gpu_busy_ms_per_step"]:.1f} ms of GPU time and a cell trained '
        f'{tuned_it["vs_one_cell"]:.2f} times as fast as an untuned one in the same call; 12 '
        f'tuned cells under MPS reached {pace(together_it)}, '
        f'{together_it["cell_epochs_per_s"] / tuned_it["cell_epochs_per_s"]:.1f} times one '
        f'tuned cell and {together_it["vs_one_cell"]:.0f} times one untuned cell. The untuned '
        f'single cells of {inception} in the two calls differ by '
        f'{100 * (max(repeats) / min(repeats) - 1):.0f} % (call to call).\n\n'
        '**The full grid, estimated before it ran.** Every model at windows 128, 256 and 512, '
        f"both schemes, 5 folds ({per_model * len(DEEP_MODELS)} deep cells) at tactex's GPU "
        f'setting (MPS and autotune: {small} {pace(now_small)} with '
        f'{now_small["cells"]} cells, {inception} {pace(together_it)} with '
        f'{together_it["cells"]}), with each model\'s mean epochs in the kept grids, needs '
        f'about {deep_min:.0f} min of GPU time for the deep models and {baseline_min:.0f} '
        f'min of the {machine["cpu_count"]} cores for the baselines: about '
        f'{deep_min + baseline_min:.0f} min, against about {_first_gpu_grid()["full_h"]:.1f} '
        'h for the setup of the GPU grid above. Its assumptions: the models not measured '
        f'here ({", ".join(scaled)}) keep the ratio of their seconds per epoch to '
        f"{small}'s in the first GPU grid, the ensemble trains at a fifth of "
        f"{inception}'s pace, windows of 256 and 512 take no longer an epoch than 128 "
        '(they hold half and a quarter of the windows), and the baselines (their '
        'single-thread training seconds in the main comparison) have the cores to '
        'themselves. `tactex compare --device cuda --mps --cells-per-gpu 16` runs a grid this '
        'way: [the full grid on a GPU](#the-full-grid-on-a-gpu) measures its pace on the '
        f'grid itself (about {_full_grid()["projection"]["whole_min"]:.0f} min projected).\n\n'
        f'**{cpu_cores} CPU cores: the 8-hour goal is out of reach.** In the main comparison one '
        f'{inception} cell took {it_cpu_s / 60:.0f} min of one core at window 128 '
        f'(mean of {it_cpu_cells} cells, early stopping included); the ensemble trains '
        f'{ENSEMBLE_MEMBERS} such networks, so its {per_model} cells of the full grid alone '
        f'need about {ensemble_cpu_h:.0f} h of the {cpu_cores} cores, and {inception} itself '
        f'{ensemble_cpu_h / ENSEMBLE_MEMBERS:.0f} h more.\n\n'
        + '\n'.join(rows) + '\n\n'
        f'![GPU pace]({FIGURES}/gpu_pace.png)\n')


def convergence_check() -> str:
    """The main comparison's unconverged cells trained again for longer: does the mark matter?"""
    kept = kept_json('convergence_check.json')
    rows = ['| cell | before | after | after: converged? |', '|---|---|---|---|']
    for row in kept['cells']:
        cell, before, after = row['cell'], row['before'], row['after']
        rows.append(f'| {cell["model"]} seed {cell["seed"]} fold {cell["fold"]} | '
                    f'{100 * before["accuracy"]:.1f} % after {before["epochs"]} epochs '
                    f'({row["why_before"]}) | {100 * after["accuracy"]:.1f} % after '
                    f'{after["epochs"]} epochs ({after["train_s"]:.0f} s) | '
                    f'{after["unconverged"] or "yes"} |')
    change = {row['cell']['model']: [] for row in kept['cells']}
    for row in kept['cells']:
        change[row['cell']['model']].append(100 * (row['after']['accuracy'] -
                                                   row['before']['accuracy']))
    grid = _cells(kept['grid'])
    summary = kept_json(f'{kept["grid"]}/summary.json')
    ranked = {row['model']: _mean_grouped(row) for row in summary['rows']
              if not row['not_converged']}
    means = {row['model']: _mean_grouped(row) for row in summary['rows']}

    def moved(model: str, values: list[float]) -> str:
        new_mean = 100 * means[model] + sum(values) / sum(key[0] == model for key in grid)
        above = min((name for name in ranked if 100 * ranked[name] > new_mean),
                    key=lambda name: ranked[name], default=None)
        return (f'{model}: {", ".join(f"{value:+.1f}" for value in values)} points, so its '
                f'mean over {sum(key[0] == model for key in grid)} cells would be about '
                f'{new_mean:.1f} % (was {100 * means[model]:.1f} %)'
                + (f', still below {above} ({100 * ranked[above]:.1f} %)' if above else ''))
    moves = '; '.join(moved(model, values) for model, values in change.items())
    return (f'The cells of the main comparison marked not converged, trained again with at '
            f'most {kept["epochs"]} epochs instead of {kept["grid_epochs"]} and nothing else '
            f'changed (`{kept["command"]}`; the warm-up and cosine schedule stretch over the '
            f'longer run). Their accuracy changed by {moves}.\n\n'
            + '\n'.join(rows) + '\n')


def _cells(name: str) -> dict[tuple, dict]:
    """A kept grid's finished cells, by (model, window, seed, fold, scheme)."""
    cells = {}
    for path in sorted((results_common.RESULTS / name / 'cells').rglob('*.json')):
        cell = kept_json(str(path.relative_to(results_common.RESULTS)))
        key = cell['cell']
        cells[key['model'], key['window'], key['seed'], key['fold'], key['scheme']] = cell
    return cells


def _unconverged_cells(model: str, cells: dict, classes: int) -> str:
    """How many of a model's kept cells did not converge, and why.

    For example '2 of 15 cells still falling' or '3 of 3 cells stalled at chance'.
    """
    from tactex_classify.evaluation.grid_report import cell_unconverged_because
    mine = [cell for key, cell in cells.items() if key[0] == model]
    reasons = [cell_unconverged_because(cell, classes) for cell in mine]
    return ', '.join(f'{reasons.count(reason)} of {len(mine)} cells {reason}'
                     for reason in sorted({reason for reason in reasons if reason}))


def compare_converged() -> str:
    """The main comparison: deep models trained to convergence beside every baseline, paired."""
    from tactex_classify.evaluation.grid_report import cost_front, cost_point, table
    from tactex_classify.models.registry import BASELINES
    summary, run, grid = _kept_grid('compare_converged')
    settings, command = summary['settings'], grid[-1]['command']
    seeds, folds = int(_option(command, '--seeds')), settings['folds']
    expected = seeds * folds
    rows = summary['rows']
    (window, data), = summary['data'].items()
    classes = len(data['classes'])
    per_texture = {call['recordings_per_texture'] for call in run['calls']}
    machines = {json.dumps(call['machine'], sort_keys=True) for call in run['calls']}
    if len(per_texture) != 1 or len(machines) != 1:
        raise ValueError(f'the main comparison mixes recordings per texture {per_texture} '
                         f'or machines {machines}')
    cores = run['calls'][0]['machine']['cpu_count']
    cells = sum(row['schemes']['grouped']['cells'] for row in rows)
    minutes = sum(step['seconds'] for step in grid) / 60
    loads = [load for step in grid for load in step['load_average']]
    deep = [row for row in rows if row['model'] not in BASELINES]
    baselines = [row for row in rows if row['model'] in BASELINES]
    incomplete = [f'{row["model"]} ({row["schemes"]["grouped"]["cells"]} of {expected})'
                  for row in rows if row['schemes']['grouped']['cells'] < expected]
    unconverged = [row for row in deep if row['not_converged']]
    ranked = {row['model'] for row in rows if not row['not_converged']}

    def figure(row: dict) -> str:
        accuracy = row['schemes']['grouped']['accuracy']
        return f'{row["model"]} {100 * accuracy["mean"]:.1f} ± {100 * accuracy["sd"]:.1f} %'
    best_baseline = max(baselines, key=_mean_grouped)
    ours, gpu = _cells('compare_converged'), _cells('compare_gpu')

    def versus(row: dict) -> str:
        difference = row.get('vs_best_baseline')
        if not difference or difference['low'] is None:
            return figure(row)
        return (f'{figure(row)}, {100 * difference["mean"]:+.1f} points '
                f'[{100 * difference["low"]:+.1f}, {100 * difference["high"]:+.1f}] '
                f'over {difference["n"]} paired cells')
    ranked_versus = '; '.join(versus(row) for row in sorted(
        (row for row in deep if row['model'] in ranked), key=lambda row: -_mean_grouped(row)))
    unranked = ''
    if unconverged:
        unranked = (' Not ranked, because some cells did not converge (the training loss '
                    'still falling at the last epoch, or never below chance): ' + '; '.join(
                        f'{versus(row)} ({_unconverged_cells(row["model"], ours, classes)})'
                        for row in unconverged) + '.')
    ladder = ', then '.join(f'{row["model"]} ({accuracy:.1f} % for {seconds:.0f} s)'
                            for row in cost_front(rows, 'train_s')
                            for seconds, accuracy in [cost_point(row, 'train_s')])
    splits = {}
    for model, _, seed, fold, _ in ours:
        if model in ranked:
            splits.setdefault(model, set()).add((seed, fold))
    common = set.intersection(*splits.values()) if splits else set()
    alike_splits = ''
    if common and len(common) < expected:
        seeds_common = sorted({seed for seed, _ in common})
        means = sorted(((np.mean([cell['accuracy'] for key, cell in ours.items()
                                  if key[0] == model and (key[2], key[3]) in common]), model)
                        for model in splits), reverse=True)
        alike_splits = (f' On the {len(common)} splits every row has (seed(s) '
                        f'{", ".join(map(str, seeds_common))}), so that the short rows are '
                        'ranked on the same recordings: ' + ', '.join(
                            f'{model} {100 * mean:.1f} %' for mean, model in means) + '.')
    shared = [key for key in sorted(set(ours) & set(gpu)) if 'hydra' not in key[0]]
    baseline_cells = [key for key in shared if key[0] in BASELINES]
    windows = sum(len(ours[key]['y_pred']) for key in baseline_cells)
    alike = sum(int(np.sum(np.equal(ours[key]['y_pred'], gpu[key]['y_pred'])))
                for key in baseline_cells)
    on_both = [key for key in shared if key[0] not in BASELINES]
    devices = '; '.join(f'{key[0]} seed {key[2]} fold {key[3]}: '
                        f'{100 * gpu[key]["accuracy"]:.1f} % on the GPU, '
                        f'{100 * ours[key]["accuracy"]:.1f} % here' for key in on_both)
    status = ('Complete: every cell of every row.' if not incomplete else
              '**Incomplete**: ' + ', '.join(incomplete) + ' cells.')
    converged = ('every deep row converged (none marked `not converged`)' if not unconverged
                 else 'not converged: ' + ', '.join(row['model'] for row in unconverged))
    return (f'The main comparison (`python bench/bench_compare.py --grid compare_converged '
            f'--recordings {per_texture.pop()} --windows {window} --cv grouped --folds {folds} '
            f'--seeds {seeds} '
            f'--epochs {settings["epochs"]} --early-stopping {settings["early_stopping"]} '
            f'--profile {settings["profile"]} --scaling {settings["scaling"]} --device '
            f'{_option(command, "--device")} --cpus {_option(command, "--cpus")} --models '
            f'{",".join(row["model"] for row in rows)}`, in {len(grid)} call(s), outputs in '
            "`bench/results/compare_converged/`): the GPU grid's recordings (the same "
            f'{data["windows"]} windows of {window} samples from {data["recordings"]} '
            'recordings, '
            'the same SHA-256), grouped by recording, every model trained and scored on the '
            f'same {expected} splits ({seeds} seeds x {folds} folds), the deep models for at '
            f'most {settings["epochs"]} epochs with early stopping after '
            f'{settings["early_stopping"]} epochs without improvement on held-out training '
            f'recordings: {converged}. On {cores} CPU cores and no GPU, one thread per cell, '
            f'{_option(command, "--cpus")} cells at a time: {cells} cells in {minutes:.0f} '
            'min (load average '
            f'{min(loads):.1f}-{max(loads):.1f}). {status}\n\n'
            f'Against the best baseline, {figure(best_baseline)}, paired by seed and fold '
            "(95 % interval, Student's t; the folds of one seed share training recordings, "
            f'so the interval is if anything too narrow): {ranked_versus}.{unranked} Accuracy '
            f'against training time per fold, the Pareto front of the ranked rows: '
            f'{ladder}.{alike_splits}\n\n'
            f'The same cells on two machines: the {len(baseline_cells)} baseline cells the GPU '
            f"grid also ran on its cores (HYDRA's aside: those predate its kernel "
            f'normalisation) predicted {alike} of their {windows} windows alike; the deep '
            'cells both ran, trained on the GPU there and on a core here: ' + devices + '.\n\n'
            + table(rows, expected) + '\n'
            f'![accuracy against cost]({FIGURES}/compare_converged/cost.png)\n')
