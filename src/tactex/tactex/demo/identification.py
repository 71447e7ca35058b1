# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The demo's identification: textures swept under named movements, then Identify goals.

Identification learns from sweeps made the way identify_node makes them: each movement of
config/movements.yaml that the probed pathway holds is sent to the sweep action on the
movement's part of the pathway, recorded with the movement's name (models trained on
sweeps of the sensor driven directly do not transfer to sweeps through the planner and the
arm's servo loop; docs/topics/identification-measured.md). The demo and
bench/bench_identify_live.py both record and identify through these functions, over a
launched system's client (`tactex.demo.session`).
"""

from __future__ import annotations

from dataclasses import replace
import math
from pathlib import Path
import shutil
import time

import numpy as np
import yaml

from tactex.errors import CommandError
from tactex_classify.identification.selection import Budget, LIVE_DEFAULT

THRESHOLD = Budget().threshold  # classifier_node's decision threshold too: both decide alike
IDENTIFY_TIMEOUT_S = 1800.0


def ramp_acceleration() -> float:
    """sweep_node's ramp acceleration as launched (config/sweep.yaml); parts allow for it."""
    from tactex.launching.spec import config_path
    config = yaml.safe_load(Path(config_path('sweep.yaml')).read_text(encoding='utf-8'))
    return float(config['/**/sweep_node']['ros__parameters']['ramp_acceleration'])


def fitting_movements(pathway, movements, limit: int | None = None):
    """The first `limit` (None: all) movements whose part with its ramps the pathway holds.

    Raises:
        CommandError: the pathway holds none of them.
    """
    from tactex_classify.identification.movement_goals import probed_arrays
    from tactex_classify.identification.pathway_part import holds, pathway_length
    points, _ = probed_arrays(pathway)
    ramps = ramp_acceleration()
    fitting = [m for m in movements.movements if holds(points, m, ramps)][:limit]
    if not fitting:
        raise CommandError(f'the probed pathway ({1e3 * pathway_length(points):.0f} mm) holds '
                           'none of the movements with their speed ramps: probe a longer span')
    return replace(movements, movements=tuple(fitting))


def record_movement_sweeps(demo, client, alive, pathway, movements, textures: list[str],
                           per_movement: int, *, attempts: int, timeout_s: float,
                           first_trial: int = 0, keep: Path | None = None) -> list[str]:
    """Sweep each texture `per_movement` times under every movement, recording; the paths.

    Each goal is the movement's part of `pathway` (`movement_goal`), labelled, numbered
    from `first_trial` and named with the movement. An aborted sweep is tried once more
    (its recording discarded) up to `attempts` goals in all, each waited on `timeout_s`;
    `keep` moves each recording there (apart from others).
    """
    from action_msgs.msg import GoalStatus

    from tactex_classify.identification.movement_goals import movement_goal
    ramps = ramp_acceleration()
    paths: list[str] = []
    total, began = len(textures) * len(movements.movements) * per_movement, time.monotonic()
    for texture in textures:
        client.set_texture(texture, alive)
        for movement in movements.movements:
            for _ in range(per_movement):
                trial = first_trial + len(paths)
                what = f'sweep {trial} ({texture}, {movement.name})'
                for _attempt in range(attempts):
                    status, result = client.send_sweep(
                        movement_goal(pathway, movement, ramps, label=texture, trial=trial,
                                      record=True), timeout_s, what, alive)
                    if status == GoalStatus.STATUS_SUCCEEDED:
                        break
                    demo.discard(result.recording_path)
                    demo.say(f'  {what}: {result.message}; its recording is discarded')
                else:
                    raise CommandError(f'{what} failed {attempts} times: {result.message}')
                path = Path(result.recording_path)
                if keep is not None:
                    keep.mkdir(parents=True, exist_ok=True)
                    path = Path(shutil.move(str(path), str(keep / path.name)))
                paths.append(str(path))
        done = len(paths)
        left = (time.monotonic() - began) / done * (total - done)
        demo.say(f'  [{done}/{total}] {texture}: {len(movements.movements)} movements x '
                 f'{per_movement} sweeps  (about {left:.0f} s left)')
    return paths


def identify_each(demo, client, alive, textures: list[str], *, budget_movements: int,
                  episodes: int = 1, pathway=None, policy: str = LIVE_DEFAULT) -> list[dict]:
    """`episodes` Identify goals (`policy`, THRESHOLD) per texture; one row per goal.

    Without `pathway` the goals leave it empty: identify_node takes the broadcast one.

    A row: truth, status, answer ('' undecided), leader (the top of the final belief),
    movements, windows, contact_s, wall_s, stop_reason, message and belief: the
    (contact seconds, probability of the truth) after each movement.
    """
    from tactex_msgs.action import Identify
    rows = []
    for texture in textures:
        client.set_texture(texture, alive)
        for episode in range(episodes):
            belief: list[tuple[float, float]] = []

            def on_feedback(message, truth=texture, belief=belief) -> None:
                f = message.feedback
                if truth in f.class_names:
                    belief.append((float(f.contact_seconds),
                                   float(f.probabilities[list(f.class_names).index(truth)])))
            goal = Identify.Goal(policy=policy, threshold=THRESHOLD,
                                 budget_movements=budget_movements, seed=episode)
            if pathway is not None:
                goal.pathway = pathway
            began = time.monotonic()
            status, result = client.identify(goal, IDENTIFY_TIMEOUT_S, f'identify {texture}',
                                             alive, on_feedback)
            names, probabilities = list(result.class_names), list(result.probabilities)
            row = {'truth': texture, 'status': int(status), 'answer': result.texture,
                   'leader': names[int(np.argmax(probabilities))] if probabilities else '',
                   'movements': list(result.movements),
                   'windows': [int(w) for w in result.windows],
                   'contact_s': float(result.contact_seconds),
                   'wall_s': time.monotonic() - began, 'stop_reason': result.stop_reason,
                   'message': result.message, 'belief': belief}
            rows.append(row)
            demo.say(f'  {texture}: {row["answer"] or "undecided"} (leader {row["leader"]}) '
                     f'after {len(row["movements"])} movements {", ".join(row["movements"])}; '
                     f'{row["contact_s"]:.1f} s in contact, {row["wall_s"]:.0f} s'
                     + (f'; {row["message"]}' if row['message'] else ''))
    return rows


def identification_figures(rows: list[dict]) -> dict:
    """Accuracy (decided and right), the leader's, the share decided, movements and seconds."""
    from action_msgs.msg import GoalStatus
    if not rows:
        return {'episodes': 0}
    contact = np.array([row['contact_s'] for row in rows])
    movements = np.array([len(row['movements']) for row in rows])
    return {'episodes': len(rows),
            'accuracy': float(np.mean([row['answer'] == row['truth'] for row in rows])),
            'leader_accuracy': float(np.mean([row['leader'] == row['truth'] for row in rows])),
            'decided': float(np.mean([bool(row['answer']) for row in rows])),
            'median_movements': float(np.median(movements)),
            'median_contact_s': float(np.median(contact)),
            'p90_contact_s': float(np.percentile(contact, 90)),
            'median_wall_s': float(np.median([row['wall_s'] for row in rows])),
            'failed': sum(row['status'] != GoalStatus.STATUS_SUCCEEDED for row in rows)}


def identification_summary(path: Path, rows: list[dict], fixed_decision_s: float) -> dict:
    """The figures and goals of summary.json; the plot to `path` (`plot_identification`)."""
    plot_identification(path, rows, fixed_decision_s)
    return identification_figures(rows) | {'goals': rows}


def plot_identification(path: Path, rows: list[dict], fixed_decision_s: float) -> None:
    """The belief in the true texture against contact seconds, per goal, beside the fixed run."""
    from tactex_common import plotting
    plt, figure, axes = plotting.figure()
    for row in rows:
        seconds = [s for s, _ in row['belief']]
        belief = [p for _, p in row['belief']]
        right = row['answer'] == row['truth']
        axes.plot(seconds, belief, marker='o', linestyle='-' if right else '--',
                  label=f'{row["truth"]} ({row["answer"] or "undecided"})')
    axes.axhline(THRESHOLD, color='grey', linewidth=0.8, label=f'threshold {THRESHOLD:g}')
    if math.isfinite(fixed_decision_s):
        axes.axvline(fixed_decision_s, color='black', linestyle=':', linewidth=1.0,
                     label=f'fixed sweep: median decision {fixed_decision_s:.1f} s')
    axes.set(xlabel='contact seconds', ylabel='belief in the true texture', xlim=(0.0, None),
             ylim=(0.0, 1.02), title='Identify goals, one line each')
    plotting.legend_outside(axes)
    plotting.save(plt, figure, path, 'a point after each movement; dashed: the goal did not '
                  'end on the truth (legend: truth (answer))')
