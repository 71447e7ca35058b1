# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Identification with per-movement models fine-tuned from one pretrained on long sweeps.

Each movement's model learns from that movement's sweeps alone, a few per texture; a deep
model starting from weights pretrained on plentiful sweeps of another set may need far
fewer. This bench measures it on the same folds and held-out sweeps:
- source: `tactex sim collect --scene uneven_texture --sweeps 85` (the scene's own seed,
  10 s sweeps at its drawn speeds), converted at 128 samples (`--source` reuses one): the
  learning curves' set;
- pretrained: cnn_3, `modern` profile, per-window scaling, at most 100 epochs, stopping
  early on held-out source recordings, on every source recording (`--pretrained` reuses
  a checkpoint);
- movement sweeps: bench_identification_report's set (`tactex sim collect --movements
  config/movements.yaml --sweeps 20 --seed 2035`, converted at the file's window;
  `--data` reuses it);
- `tactex report identification` three times (2 folds, 3 inner folds, 10 seeds):
  minirocket per movement, cnn_3 per movement from scratch (`modern`, window scaling, 250
  epochs), and cnn_3 fine-tuned per movement from the pretrained checkpoint (`--init`,
  `modern`, `--epochs`).

Keeps bench/results/identification_init.json (each report's identification.json and the
commands with their seconds) and identification_init.png (accuracy against contact
seconds, per model: active solid, random dashed); `--plot` redraws the PNG from the JSON.
"""

import argparse
import hashlib
import json
from pathlib import Path
import sys
import tempfile
import time

from bench_textures import build_dataset, TACTEX, timed  # the benches' shared steps

RESULTS = Path(__file__).parent / 'results' / 'identification_init.json'
PLOT = RESULTS.with_suffix('.png')
MOVEMENTS = Path(__file__).parents[1] / 'config' / 'movements.yaml'
REPORT = ['--folds', '2', '--inner-folds', '3', '--seeds', '10', '--movements', str(MOVEMENTS)]
SETTINGS = {  # name: the report's per-movement model options
    'minirocket': ['--model', 'minirocket'],
    'cnn_3 from scratch': ['--model', 'cnn_3', '--profile', 'modern', '--scaling', 'window',
                           '--epochs', '250'],
}


def pretrain(source: Path, out: Path) -> float:
    """Train the cnn_3 every movement's model starts from; its seconds."""
    from tactex_classify.data.dataset import Dataset
    from tactex_classify.training.deep_classifier import DeepClassifier, TrainingConfig
    began = time.monotonic()
    data = Dataset.load(source)
    config = TrainingConfig.for_profile('modern', model='cnn_3', scaling='window', epochs=100,
                                        seed=0, threads=2)
    model = DeepClassifier(config).fit(data.X, data.y, data.classes, groups=data.trial,
                                       channels=data.channels)
    model.save(out, hop=data.info['hop'], sampling_rate_hz=data.info['sampling_rate_hz'],
               trained_on=data.digest())
    print(f'pretrained cnn_3: {len(model.history_)} epochs, '
          f'{model.unconverged_reason() or "converged"}', flush=True)
    return time.monotonic() - began


def described(source: Path, pretrained: Path, data: Path) -> dict:
    """What the source set, the pretraining and the movement sweeps were (for the text)."""
    from tactex_classify.data.dataset import Dataset
    checkpoint = json.loads((pretrained / 'checkpoint.json').read_text())
    sets = {}
    for name, path in (('source', source), ('movement_sweeps', data)):
        dataset = Dataset.load(path)
        sets[name] = {'digest': dataset.digest(), 'recordings': len(set(dataset.trial.tolist())),
                      'windows': int(dataset.y.size), 'classes': len(dataset.classes),
                      # the key bench_learning_curves.py keeps its set under
                      'windows_sha256': hashlib.sha256(dataset.X.tobytes()).hexdigest()[:16]}
    if checkpoint.get('trained_on') != sets['source']['digest']:
        raise SystemExit(f'error: --pretrained {pretrained} was not trained on --source {source}')
    sets['pretraining'] = {key: checkpoint['config'][key] for key in (
        'model', 'profile', 'scaling', 'epochs', 'early_stopping', 'seed')}
    return sets


def plot(kept: dict, path: Path) -> None:
    """Accuracy after each movement's contact seconds: active solid, random dashed."""
    import matplotlib
    matplotlib.use('Agg')
    from bench_profiles import finish_plot
    import matplotlib.pyplot as plt
    figure, axes = plt.subplots(figsize=(8, 4.5))
    for index, (name, report) in enumerate(kept['reports'].items()):
        seconds = report['contact_s'][0]  # every movement of the file lasts as long
        for policy, style in (('active', '-'), ('random', '--')):
            curve = report['policies'][policy]['accuracy_after_k'][:24]
            axes.plot([seconds * k for k in range(1, len(curve) + 1)],
                      [100 * right for right in curve], style, color=f'C{index}',
                      marker='o' if policy == 'active' else None, markersize=3,
                      label=f'{name}, {policy}')
    axes.set_xlabel('contact seconds (movements x 2.5 s)')
    axes.set_ylabel('identified right (%)')
    finish_plot(figure, axes, 1 / len(next(iter(kept['reports'].values()))['classes']),
                'identification: per-movement models, pretrained or not', path)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('--source', type=Path, help='the pretraining set (.npz), made if absent')
    parser.add_argument('--pretrained', type=Path, help='a cnn_3 checkpoint of the source set')
    parser.add_argument('--data', type=Path, help='the movement sweeps (.npz), made if absent')
    parser.add_argument('--epochs', type=int, default=60, help='fine-tuning epochs (60)')
    parser.add_argument('--plot', action='store_true', help='redraw the PNG from the JSON kept')
    args = parser.parse_args()
    if args.plot:
        plot(json.loads(RESULTS.read_text()), PLOT)
        print(f'wrote {PLOT}')
        return 0
    steps: list[dict] = []
    with tempfile.TemporaryDirectory() as scratch_name:
        scratch = Path(scratch_name)
        source, data = args.source, args.data
        if source is None:
            source = build_dataset(scratch / 'source', 85, steps)
        for option, given in (('--source', args.source), ('--pretrained', args.pretrained),
                              ('--data', args.data)):
            if given is not None:
                steps.append({'command': f'{option} {given}', 'seconds': None,
                              'note': 'made earlier by the same step'})
        pretrained = args.pretrained  # trained on --source (checked when the result is kept)
        if pretrained is None:
            pretrained = scratch / 'pretrained'
            steps.append({'command': f'pretrain cnn_3 on {source.name} (bench pretrain())',
                          'seconds': pretrain(source, pretrained)})
        if data is None:
            data = scratch / 'identification.npz'
            timed([TACTEX, 'sim', 'collect', '--movements', str(MOVEMENTS), '--sweeps', '20',
                   '--seed', '2035', '--workers', '2', '--out', str(scratch / 'bags')], steps)
            timed([TACTEX, 'convert', str(scratch / 'bags'), '--out', str(data), '--window',
                   '128'], steps)
        settings = {**SETTINGS, 'cnn_3 fine-tuned': [
            '--init', str(pretrained), '--profile', 'modern', '--epochs', str(args.epochs)]}
        reports = {}
        for name, options in settings.items():
            out = scratch / name.replace(' ', '_')
            timed([TACTEX, 'report', 'identification', str(data), *REPORT, *options, '--out',
                   str(out)], steps)
            reports[name] = json.loads((out / 'identification.json').read_text())
        description = described(source, pretrained, data)  # before the scratch folder goes
    kept = {'settings': settings, 'fine_tuning_epochs': args.epochs, **description,
            'reports': reports, 'steps': steps}
    RESULTS.write_text(json.dumps(kept, indent=1) + '\n', encoding='utf-8')
    plot(kept, PLOT)
    print(f'wrote {RESULTS} and {PLOT}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
