# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Active identification live in simulation, beside the offline replay of the same data.

Training sweeps (`--training`):
- `collect`: `tactex sim collect --movements config/movements.yaml` on a scene seed no
  test uses (12 textures x 8 movements x `--sweeps`), the sensor driven along the plate;
- `sweeps`: the system launched in simulation, a pathway probed along `--span`, and every
  texture (the bridge's patch_texture) swept `--sweeps` times under each movement the
  pathway holds, through the sweep action on the movement's part of the pathway, recorded
  with the movement's name: the way identify_node sweeps. The movement file is cut to
  those movements (work/movements.yaml).
Then `tactex convert` at the movements' window, `tactex train --movements` (the bundle,
one `--model` per movement, calibrated), the offline `tactex report identification` on the
same dataset, model and policy, and live: the system launched with `bundle:=...`, then for
every texture `--episodes` Identify goals (`--policy`, threshold 0.99) on the probed pathway.

With `--init CHECKPOINT` (and `--profile`, `--epochs`, `--scaling`) every movement's deep
model, in the bundle and in the offline report alike, is fine-tuned from the checkpoint.

Keeps bench/results/identify_live.json (or identify_live_sweeps.json; with `--init`, the
same names ending in _init; `--keep` names another of LIVE_RUNS, and `--pretraining` says
how the --init checkpoint was made), and draws every live run kept in identify_live.png (`--plot`
redraws it alone): every live episode
(truth, answer, movements, contact and wall seconds), the live summary beside the offline
report's active row, and the commands with their seconds. `--work DIR` keeps (and
reuses) the bags, dataset, bundle, offline report, live episodes (live/episodes.json) and
the commands that made them with their seconds (steps.json); another `--policy` has its
own offline report and live goals (offline_POLICY/, live_POLICY/).
"""

import argparse
from dataclasses import replace
import json
from pathlib import Path
import sys
import time

from bench_textures import TACTEX, timed  # one way to run and time a tactex step
import numpy as np
import yaml

from tactex.demo.identification import identification_figures
from tactex_classify.identification.selection import POLICIES

RESULTS = Path(__file__).parent / 'results' / 'identify_live.json'
MOVEMENTS = Path(__file__).parents[1] / 'config' / 'movements.yaml'
# The live runs kept (beside RESULTS), drawn side by side in PLOT.
LIVE_RUNS = ('identify_live.json', 'identify_live_sweeps.json', 'identify_live_init.json',
             'identify_live_sweeps_init.json', 'identify_live_sweeps_init_sweeps.json',
             'identify_live_sweeps_init_sweeps_realized.json',
             'identify_live_sweeps_rounds.json')
PLOT = RESULTS.with_name('identify_live.png')


def recorded_through_sweeps(work: Path, args) -> tuple[Path, Path]:
    """(bags, movement file): every texture swept under each movement the pathway holds."""
    from tactex.demo.identification import fitting_movements, record_movement_sweeps
    from tactex.demo.pipeline import ATTEMPTS, DEFAULT, Demo, demo_environment, SWEEP_TIMEOUT_S
    from tactex_description.movements import load_movements, movements_yaml
    from tactex_sim.textures import TEXTURES
    folder, movements_file = work / 'sweeps', work / 'movements.yaml'
    folder.mkdir(parents=True, exist_ok=True)
    with demo_environment(folder):
        demo = Demo(folder, folder, replace(DEFAULT, probe_span_m=args.span), time.monotonic())
        with demo.system('record') as (client, alive):
            pathway = demo.probe(client, alive)['pathway']
            movements = fitting_movements(pathway, load_movements(MOVEMENTS))
            movements_file.write_text(movements_yaml(movements), encoding='utf-8')
            record_movement_sweeps(demo, client, alive, pathway, movements,
                                   list(TEXTURES)[:args.textures], args.sweeps,
                                   attempts=ATTEMPTS, timeout_s=SWEEP_TIMEOUT_S)
    return folder / 'bags', movements_file


def prepared(work: Path, args, steps: list[dict]) -> tuple[Path, Path, Path, Path]:
    """(dataset, bundle, offline report folder, movement file), made unless `work` holds them."""
    data, movements = work / 'data.npz', MOVEMENTS
    if args.training == 'sweeps':
        movements = work / 'movements.yaml'
        bags = work / 'sweeps' / 'bags'
        if not data.is_file() and not bags.is_dir():
            began = time.monotonic()
            bags, movements = recorded_through_sweeps(work, args)
            steps.append({'command': 'sweeps through the sweep action (recorded_through_sweeps)',
                          'seconds': time.monotonic() - began})
    else:
        bags = work / 'bags'
        if not data.is_file() and not bags.is_dir():
            timed([TACTEX, 'sim', 'collect', '--movements', str(MOVEMENTS), '--sweeps',
                   str(args.sweeps), '--seed', str(args.seed), '--workers', '2', '--out',
                   str(bags)], steps)
    if not data.is_file():
        timed([TACTEX, 'convert', str(bags), '--out', str(data), '--window', '128'], steps)
    bundle = work / 'run' / 'bundle'
    if not (bundle / 'bundle.json').is_file():
        # Through the sweep action there are fewer sweeps per cell: fewer folds.
        folds = ['--folds', str(max(2, min(3, args.sweeps)))] if args.training == 'sweeps' \
            else []
        timed([TACTEX, 'train', str(data), '--movements', str(movements), '--model',
               args.model, *folds, *training_options(args), *repeats(args), '--out',
               str(work / 'run')], steps)
    offline = work / policy_folder('offline', args.policy)
    if not (offline / 'identification.json').is_file():
        # Nested folds need two training sweeps per cell inside each outer fold: with
        # three sweeps per cell (through the sweep action), three outer folds.
        outer = '3' if args.training == 'sweeps' and args.sweeps < 4 else '2'
        timed([TACTEX, 'report', 'identification', str(data), '--out', str(offline),
               '--movements', str(movements), '--policies', args.policy, '--folds', outer,
               '--inner-folds', '2',
               '--seeds', str(args.offline_seeds), '--model', args.model,
               *training_options(args), *repeats(args)], steps)
    return data, bundle, offline, movements


def policy_folder(name: str, policy: str) -> str:
    """A work folder's offline report or live goals of `policy` (active's keep their names)."""
    return name if policy == 'active' else f'{name}_{policy}'


def default_kept_file(training: str, fine_tuned: bool) -> str:
    """Where a live run is kept without --keep: fine-tuned bundles beside, never over, others."""
    return ('identify_live' + ('_sweeps' if training == 'sweeps' else '')
            + ('_init' if fine_tuned else '') + '.json')


def repeats(args) -> list[str]:
    """The bundle's and the offline report's option to fit a discount of repeated movements."""
    return ['--repeat-discount'] if args.repeat_discount else []


def training_options(args) -> list[str]:
    """How a deep per-movement model trains, the same for the bundle and the offline report."""
    options = ['--init', str(args.init)] if args.init else []
    for option, value in (('--profile', args.profile), ('--epochs', args.epochs),
                          ('--scaling', args.scaling)):
        if value is not None:
            options += [option, str(value)]
    return options


def checkpoint_alone(checkpoint: Path, data: Path) -> dict:
    """What the fine-tuning started from, and how right it is alone on each movement's sweeps.

    The checkpoint's model, the digest of the set it was trained on and its scaling; per
    movement, the share of sweeps it names right, not fine-tuned: a sweep's answer is the
    largest of its windows' normalised geometric mean, as a movement's model answers before
    calibration (how far the pretraining carries to these sweeps on its own).
    """
    from tactex_classify.data.dataset import Dataset
    from tactex_classify.identification.movement_evidence import sweep_vectors, trial_movements
    from tactex_classify.models.checkpoint import load_checkpoint
    dataset = Dataset.load(data)
    info, model = load_checkpoint(checkpoint)
    if list(info.classes) != list(dataset.classes):
        raise SystemExit(f'error: --init {checkpoint} holds other textures than {data}')
    trials, labels, vectors = sweep_vectors(dataset, model.predict_proba(dataset.X))
    movement_of = trial_movements(dataset)
    right: dict[str, list[bool]] = {}
    for trial, label, vector in zip(trials, labels, vectors, strict=True):
        right.setdefault(movement_of[int(trial)], []).append(bool(vector.argmax() == label))
    return {'model': info.model, 'trained_on': info.trained_on, 'scaling': info.scaling,
            'alone_sweep_accuracy': {name: float(np.mean(answers))
                                     for name, answers in right.items()}}


def live_episodes(work: Path, bundle: Path, movements: Path, args) -> tuple[list[dict], dict]:
    """Every texture identified `--episodes` times through identify_node; (episodes, probe)."""
    from tactex.demo.identification import identify_each
    from tactex.demo.pipeline import DEFAULT, Demo, demo_environment
    from tactex_sim.textures import TEXTURES
    folder = work / policy_folder('live', args.policy)
    folder.mkdir(parents=True, exist_ok=True)
    with demo_environment(folder):
        demo = Demo(folder, folder, replace(DEFAULT, probe_span_m=args.span), time.monotonic())
        with demo.system('identify', identify=(bundle, movements)) as (client, alive):
            probe = demo.probe(client, alive)
            episodes = identify_each(demo, client, alive, list(TEXTURES)[:args.textures],
                                     budget_movements=args.budget_movements,
                                     episodes=args.episodes, policy=args.policy)
    return episodes, {'points': probe['points'], 'contacts': len(probe['pathway'].contacts),
                      'normal_error_deg': float(np.mean(probe['normal_deg'])),
                      'position_error_mm': float(np.mean(probe['position_mm']))}


def plot(path: Path) -> None:
    """The true texture's belief over each live goal's contact seconds, one panel per run.

    Every run kept with its goals' beliefs is drawn. A goal's line is green when it decided
    right, red when it decided wrong, grey when it ran out of movements; the dashed line is
    the decision threshold.
    """
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    runs = [(name, json.loads((path.parent / name).read_text())) for name in LIVE_RUNS
            if (path.parent / name).is_file()]
    runs = [(name, kept) for name, kept in runs  # kept before the goals kept their beliefs
            if all('belief' in episode for episode in kept['episodes'])]
    figure, panels = plt.subplots(1, len(runs), figsize=(max(6.0, 4.2 * len(runs)), 3.8),
                                  sharey=True, squeeze=False)
    for axes, (name, kept) in zip(panels[0], runs, strict=True):
        textures = len({episode['truth'] for episode in kept['episodes']})
        for episode in kept['episodes']:
            color = ('grey' if not episode['answer'] else
                     'tab:green' if episode['answer'] == episode['truth'] else 'tab:red')
            seconds, belief = zip(*([(0.0, 1 / textures)] + episode['belief']), strict=True)
            axes.plot(seconds, belief, color=color, alpha=0.7, linewidth=1, marker='.')
        axes.axhline(0.99, color='k', linestyle='--', linewidth=0.8)
        right = sum(episode['answer'] == episode['truth'] for episode in kept['episodes'])
        tuned = ' fine-tuned' if kept.get('pretrained') else ''
        policy = '' if kept.get('policy', 'active') == 'active' else f', {kept["policy"]}'
        axes.set_title(f'{kept["model"]}{tuned}, trained on {kept.get("training", "collect")}'
                       f'{policy}\n{right} of {len(kept["episodes"])} decided right ({name})',
                       fontsize=8)
        axes.set_xlabel('contact seconds')
    panels[0][0].set_ylabel("true texture's belief")
    figure.suptitle('live Identify goals: green right, red wrong, grey undecided',
                    fontsize=10)
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('--sweeps', type=int, default=5, help='per texture and movement')
    parser.add_argument('--seed', type=int, default=2029, help='scene seed (no test uses it)')
    parser.add_argument('--model', default='minirocket')
    parser.add_argument('--init', type=Path, metavar='CHECKPOINT',
                        help="start every movement's deep model from this checkpoint")
    parser.add_argument('--profile', help="deep models: original or modern (train's default)")
    parser.add_argument('--epochs', type=int, help="deep models' epochs (train's default)")
    parser.add_argument('--scaling', help="deep models' scaling (train's default)")
    parser.add_argument('--span', type=float, default=0.16,
                        help='probed pathway, m (the fastest movement needs 150 mm)')
    parser.add_argument('--episodes', type=int, default=1, help='Identify goals per texture')
    parser.add_argument('--budget-movements', type=int, default=8)
    parser.add_argument('--policy', choices=POLICIES, default='active',
                        help='how the live goals and the offline replay choose (active)')
    parser.add_argument('--offline-seeds', type=int, default=10)
    parser.add_argument('--training', choices=('collect', 'sweeps'), default='collect',
                        help='training sweeps from sim collect, or through the sweep action')
    parser.add_argument('--textures', type=int, default=12, help='the first N textures')
    parser.add_argument('--work', type=Path, help='bags, data, bundle, logs (required)')
    parser.add_argument('--repeat-discount', action='store_true',
                        help="fit a discount of a movement's repeats (train and report)")
    parser.add_argument('--pretraining', metavar='TEXT',
                        help='with --init: how the checkpoint was made, kept with the run')
    parser.add_argument('--keep', choices=LIVE_RUNS,
                        help='the kept file in bench/results (default: identify_live, '
                             '_sweeps with --training sweeps, then _init with --init)')
    parser.add_argument('--plot', action='store_true',
                        help=f'only redraw {PLOT.name} from the runs kept')
    args = parser.parse_args()
    if args.plot:
        plot(PLOT)
        return 0
    if args.work is None:
        parser.error('--work DIR is required (or --plot)')
    if args.pretraining and not args.init:
        parser.error('--pretraining describes the --init checkpoint: give --init too')
    # The steps that made the work folder's contents, kept with it: a later call that
    # reuses them keeps their commands and seconds.
    made = args.work / 'steps.json'
    steps: list[dict] = json.loads(made.read_text()) if made.is_file() else []
    try:
        data, bundle, offline, movements = prepared(args.work, args, steps)
    finally:
        args.work.mkdir(parents=True, exist_ok=True)
        made.write_text(json.dumps(steps, indent=1) + '\n', encoding='utf-8')
    live = args.work / policy_folder('live', args.policy) / 'episodes.json'
    if not live.is_file():
        began = time.monotonic()
        episodes, probe = live_episodes(args.work, bundle, movements, args)
        live.write_text(json.dumps({'episodes': episodes, 'probe': probe,
                                    'seconds': time.monotonic() - began}))
    kept_live = json.loads(live.read_text())
    episodes, probe = kept_live['episodes'], kept_live['probe']
    offline_report = json.loads((offline / 'identification.json').read_text())
    active = offline_report['policies'][args.policy]  # kept as offline
    kept = {'scene_seed': args.seed, 'sweeps_per_texture_and_movement': args.sweeps,
            'model': args.model, 'training_options': training_options(args),
            'span_m': args.span, 'probe': probe,
            'budget_movements': args.budget_movements,
            'live': identification_figures(episodes), 'live_seconds': kept_live['seconds'],
            'offline': {key: active[key] for key in (
                'accuracy', 'median_contact_s', 'p90_contact_s', 'median_movements')},
            'offline_accuracy_after_budget': active['accuracy_after_k'][
                min(args.budget_movements, len(active['accuracy_after_k'])) - 1],
            'offline_first_three': {name: count for name, count in
                                    active['first_three_movements'].items() if count},
            'offline_sweep_accuracy': {name: row['sweep_accuracy'] for name, row in
                                       offline_report['movements'].items()},
            'offline_episodes': offline_report['episodes'],
            'offline_folds': offline_report['settings']['folds'],
            'bundle': {key: json.loads((bundle / 'bundle.json').read_text()).get(key, 0.0)
                       for key in ('tempering', 'repeat_discount')},
            'episodes': episodes, 'steps': steps}
    if args.init:  # what the fine-tuning started from, told by the set it was trained on
        kept['pretrained'] = checkpoint_alone(args.init, data)
        if args.pretraining:
            kept['pretrained']['recipe'] = args.pretraining
    kept['training'] = args.training
    kept['policy'] = args.policy
    kept['repeat_discount_fitted'] = args.repeat_discount
    kept['movements'] = [row['name'] for row in
                         yaml.safe_load(Path(movements).read_text())['movements']]
    results = RESULTS.with_name(args.keep or default_kept_file(args.training, bool(args.init)))
    results.write_text(json.dumps(kept, indent=1) + '\n', encoding='utf-8')
    plot(PLOT)
    print(json.dumps({k: kept[k] for k in ('live', 'offline', 'probe')}, indent=1))
    return 0


if __name__ == '__main__':
    sys.exit(main())
