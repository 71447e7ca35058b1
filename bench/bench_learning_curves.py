# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Learning curves: grouped accuracy against training recordings per texture, with the cost.

From the simulated uneven-texture set (`--data`, or `--sweeps` per texture simulated),
`--test` recordings per texture are held out once; from the rest, n recordings per
texture (`--sizes`; a size beyond what the set holds is skipped and named) train each
model of `--models`, `--draws` times with different draws, and every training is scored
on the same held-out recordings. Deep models train with the `modern` profile and
per-window scaling (its early stopping holds out some of the training recordings);
baselines as they are. Each
point keeps its accuracy and training seconds, so the curve shows where, if anywhere, a
deep model overtakes the baselines and what each point costs, and for each draw of a deep
model why it did not converge (`unconverged_because`: stalled at chance, or still falling
at its last epoch; None when it converged), marked in the table (points kept before
this check existed carry no mark).

Points are kept in RESULTS/learning_curves.json as they finish and a run with the same
data and settings resumes; a deep model's training in progress is kept too (in
`--out`/training_state, at an epoch's end, at most once a minute, and at its end until
the point is kept), so a long point stopped part way goes on from its last kept epoch,
its seconds counting the training before the stop. `--merge DIR ...` trains nothing: it
joins the points kept by calls run side by side (each with its own `--out`, the same set
and settings) into `--out`; a point two folders hold is the later folder's, the earlier
kept aside as `replaced`, and a merged folder's calls are listed one by one (so new
calls can be merged into the kept results). Writes learning_curves.{json,md,png}.
"""

import hashlib
import json
import os
from pathlib import Path
import sys
import time

os.environ.setdefault('OMP_WAIT_POLICY', 'PASSIVE')

from bench_architectures import configuration, fit_timed  # noqa: E402  (one row's model)
from bench_profiles import common_parser, finish_plot, keep, load_or_simulate  # noqa: E402
from bench_sim_to_real import accuracy, draw, hold_out  # noqa: E402
import numpy as np  # noqa: E402
from results_common import device_mark, DEVICE_NOTE  # noqa: E402  (the rendered table's)

from tactex_classify.training.training_state import forget  # noqa: E402

RESULTS = Path(__file__).parent / 'results' / 'learning_curves'
# What makes two calls' points comparable: the set (its hash) and the settings. The device
# is each point's own (`device`): it changes the seconds (on a GPU, the last bits too),
# not the protocol.
KEY = ('dataset', 'test', 'draws', 'epochs', 'seed')


def markdown(summary: dict) -> str:
    """Accuracy (mean ± sd over draws) and training seconds per model and size."""
    from tactex_classify.models.registry import BASELINES
    sizes = summary['sizes']
    lines = [f'Accuracy on {summary["test_windows"]} windows of {summary["test"]} held-out '
             f'recordings per texture (chance {100 * summary["chance"]:.1f} %), trained on '
             f'n recordings per texture, {summary["draws"]} draw(s) each; deep models: '
             f'`modern` profile, per-window scaling, at most {summary["epochs"]} epochs; '
             f'`{summary["command"].strip()}`.', '',
             '| model | ' + ' | '.join(f'n = {n}' for n in sizes) + ' |',
             '|---|' + '---|' * len(sizes)]
    for model in summary['models']:
        cells = []
        for n in sizes:
            point = summary['points'].get(f'{model}@{n}')
            reasons = sorted({r for r in (point or {}).get('unconverged', []) if r})
            cells.append('-' if point is None else
                         f'{100 * np.mean(point["accuracy"]):.1f} % '
                         f'({np.mean(point["seconds"]):.0f} s)' + device_mark(point)
                         + (f' (not converged: {", ".join(reasons)})' if reasons else ''))
        lines.append(f'| {model} | ' + ' | '.join(cells) + ' |')
    if any('unconverged' not in summary['points'].get(f'{model}@{n}', {'unconverged': 0})
           for model in summary['models'] if model not in BASELINES for n in sizes):
        lines += ['', 'Deep-model points kept before the convergence check existed carry '
                  'no mark either way.']
    if any(device_mark(point) for point in summary['points'].values()):
        lines += ['', DEVICE_NOTE[0].upper() + DEVICE_NOTE[1:] + '.']
    if summary['skipped']:
        lines += ['', 'Not in this set: ' + ', '.join(summary['skipped']) + '.']
    if summary.get('replaced'):
        lines += ['', 'Points a later call replaced (what the earlier call measured):', '']
        lines += [f'- {name.replace("@", " at n = ")}: {100 * np.mean(old["accuracy"]):.1f} % '
                  f'({np.mean(old["seconds"]):.0f} s), replaced by `{old["by"].strip()}`'
                  for name, old in summary['replaced'].items()]
    if len(summary.get('calls', [])) > 1:  # merged from calls run side by side
        lines += ['', f'Run as {len(summary["calls"])} calls side by side (`-`: not run):', '']
        lines += [f'- `{call.strip()}`' for call in summary['calls']]
    return '\n'.join(lines) + '\n'


def plot(summary: dict, path: Path) -> None:
    """Accuracy against recordings per texture, one line per model (log x; baselines dashed)."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt

    from tactex_classify.models.registry import BASELINES

    figure, axes = plt.subplots(figsize=(8, 4.5))
    for model in summary['models']:
        baseline = model in BASELINES  # dashed squares: the deep models are solid circles
        points = [(n, summary['points'][f'{model}@{n}']) for n in summary['sizes']
                  if f'{model}@{n}' in summary['points']]
        if points:
            axes.errorbar([n for n, _ in points],
                          [100 * np.mean(p['accuracy']) for _, p in points],
                          yerr=[100 * np.std(p['accuracy']) for _, p in points],
                          marker='s' if baseline else 'o',
                          capsize=3, linestyle='--' if baseline else '-',
                          label=f'{model} (baseline)' if baseline else model)
    axes.set_xscale('log')
    axes.minorticks_off()  # the sizes alone label the axis
    axes.set_xticks(summary['sizes'], [str(n) for n in summary['sizes']])
    axes.set_xlabel('training recordings per texture')
    axes.set_ylabel('accuracy on held-out recordings (%)')
    finish_plot(figure, axes, summary['chance'], 'learning curves', path)


def epoch_lines(name: str, epochs: int, started: float):
    """Epoch lines of a deep model's fit: its first in this call (a resumed one's), every tenth."""
    shown = False

    def progress(record: dict) -> None:
        nonlocal shown
        if not shown or record['epoch'] % 10 == 0:
            shown = True
            print(f'[{time.monotonic() - started:7.0f} s] {name} epoch {record["epoch"]}/'
                  f'{epochs}: training loss {record["train_loss"]:.3f}', flush=True)
    return progress


def main() -> int:
    parser = common_parser(__doc__, RESULTS)
    parser.add_argument('--sizes', default='5,10,20,40,80')
    parser.add_argument('--test', type=int, default=5, help='held-out recordings per texture')
    parser.add_argument('--draws', type=int, default=1)
    parser.add_argument('--models', default='minirocket,multirocket,extratrees,cnn_3,'
                        'cnn_attention,resnet,inception_time')
    parser.add_argument('--device', default='cpu')
    parser.add_argument('--merge', nargs='+', type=Path, metavar='DIR',
                        help='join the points kept in these --out folders; train nothing')
    args = parser.parse_args()
    if args.merge:
        return merge(args.merge, args.out, [int(n) for n in args.sizes.split(',')],
                     [m.strip() for m in args.models.split(',') if m.strip()])

    started = time.monotonic()
    dataset = load_or_simulate(args.data, args.sweeps)
    test, pool = hold_out(dataset, args.test, np.random.default_rng(args.seed))
    available = min(np.unique(dataset.trial[np.isin(dataset.trial, pool) & (dataset.y == c)]
                              ).size for c in range(len(dataset.classes)))
    wanted = [int(n) for n in args.sizes.split(',')]
    sizes = [n for n in wanted if n <= available]
    models = [m.strip() for m in args.models.split(',') if m.strip()]
    key = dict(zip(KEY, (hashlib.sha256(dataset.X.tobytes()).hexdigest()[:16], args.test,
                         args.draws, args.epochs, args.seed), strict=True))
    json_path = args.out / 'learning_curves.json'
    kept = json.loads(json_path.read_text(encoding='utf-8')) if json_path.is_file() else {}
    points = {name: {'device': kept.get('device', 'cpu'), **point}  # kept before points had it
              for name, point in kept.get('points', {}).items()} if all(
        kept.get(k) == v for k, v in key.items()) else {}
    summary = {**key, 'device': args.device, 'sizes': sizes, 'models': models,
               'test_windows': int(test.y.size),
               'chance': 1 / len(dataset.classes), 'points': points,
               'skipped': [f'n = {n} (the set holds {available} training recordings per '
                           'texture)' for n in wanted if n > available],
               'command': 'python bench/bench_learning_curves.py ' + ' '.join(sys.argv[1:])}
    args.out.mkdir(parents=True, exist_ok=True)
    states = args.out / 'training_state'
    for n in sizes:
        for model in models:
            if f'{model}@{n}' in points:
                continue
            point = {'accuracy': [], 'seconds': [], 'unconverged': [], 'device': args.device}
            for index in range(args.draws):
                train = dataset.select(draw(dataset, pool, n, np.random.default_rng(
                    [args.seed, n, index])))
                config = configuration(model, args.epochs, args.seed + index, 1)
                estimator, seconds = fit_timed(
                    config, train, args.device, states / f'{model}@{n}#{index}.pt',
                    epoch_lines(f'n={n:3d} {model}', args.epochs, started))
                point['accuracy'].append(accuracy(estimator, test))
                point['seconds'].append(round(seconds, 1))
                point['unconverged'].append(estimator.unconverged_reason() if hasattr(
                    estimator, 'unconverged_reason') else None)
            points[f'{model}@{n}'] = point
            print(f'[{time.monotonic() - started:7.0f} s] n={n:3d} {model:16s} '
                  f'{100 * np.mean(point["accuracy"]):5.1f} %, '
                  f'{np.mean(point["seconds"]):.0f} s', flush=True)
            json_path.write_text(json.dumps(summary, indent=1) + '\n', encoding='utf-8')
            for index in range(args.draws):  # kept in the JSON: their states are done with
                forget(states / f'{model}@{n}#{index}.pt')
    keep(args.out, 'learning_curves', summary, markdown, plot)
    return 0


def merge(folders: list[Path], out: Path, sizes: list[int], models: list[str]) -> int:
    """Join the points of calls run side by side into `out` (`models` in this order)."""
    missing = [str(folder) for folder in folders
               if not (folder / 'learning_curves.json').is_file()]
    if missing:
        print(f'error: --merge: no learning_curves.json in {", ".join(missing)}',
              file=sys.stderr)
        return 1
    parts = [json.loads((folder / 'learning_curves.json').read_text(encoding='utf-8'))
             for folder in folders]
    for folder, part in zip(folders, parts, strict=True):
        differ = [k for k in (*KEY, 'test_windows', 'chance') if part[k] != parts[0][k]]
        if differ:
            print(f'error: --merge {folder}: another set or settings than {folders[0]} '
                  f'({", ".join(differ)})', file=sys.stderr)
            return 1
    points, replaced = {}, dict(parts[0].get('replaced', {}))
    for part in parts:  # a later call's point replaces an earlier one's, which is kept aside
        for name, point in part['points'].items():
            point = {**point, 'device': point.get('device', part.get('device', 'cpu'))}
            if name in points and points[name] != point:
                replaced[name] = {**points[name], 'by': part['command']}
            points[name] = point
    summary = {k: parts[0][k] for k in (*KEY, 'test_windows', 'chance')}
    summary.update(sizes=sizes, points=points, skipped=[], replaced=replaced,
                   models=[m for m in models if any(f'{m}@{n}' in points for n in sizes)],
                   command='python bench/bench_learning_curves.py ' + ' '.join(sys.argv[1:]),
                   calls=[call for part in parts for call in part.get('calls',
                                                                      [part['command']])])
    keep(out, 'learning_curves', summary, markdown, plot)
    return 0


if __name__ == '__main__':
    sys.exit(main())
