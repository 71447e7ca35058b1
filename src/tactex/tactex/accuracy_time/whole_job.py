# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Section 7: where the time goes in one simulated run of the whole job.

Probe a line of the plate (section 3's default run), plan a sweep along its contacts
and play it through the driver's controller (`tactex_trajectory`), record labelled
sweeps (`tactex_sim.collect`), convert them, train the model, and decide the texture of
held-out sweeps live (the checkpoint's predictor and the live node's `Evidence`). Each
stage's wall time in this run, and the arm's time (simulated seconds) of the physical
stages: what a real robot would spend.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
import time

import numpy as np

from tactex.accuracy_time.classification import make_estimator
from tactex.accuracy_time.sizes import Size

WINDOW = 128
HELD_OUT_SEED_OFFSET = 1000


def whole_job(probe_run, scratch: Path, size: Size, model: str, threshold: float,
              log: Callable[[str], None], *, seed: int, threads: int) -> dict:
    """Per stage: wall seconds of this run and simulated (arm) seconds."""
    from tactex_classify.data.dataset import convert
    from tactex_classify.evaluation.cross_validation import decide_recordings
    from tactex_classify.online.runtime import load_predictor
    from tactex_sim.collect import collect
    from tactex_sim.scene import load_scene, resolve_scene
    from tactex_sim.textures import TEXTURES
    from tactex_sim.world import World
    from tactex_trajectory.planner import plan_sweep
    from tactex_trajectory.simulated_sweeps import execute, measure
    stages = [{'stage': 'probe', 'wall_s': probe_run['wall_s'],
               'arm_s': probe_run['run'].sim_time_s}]
    scene = load_scene(resolve_scene('uneven_texture'))
    contacts = probe_run['run'].pathway.contacts
    start = np.append(probe_run['run'].final_joints, 0.0)
    began = time.perf_counter()
    plan = plan_sweep(np.array([c.position for c in contacts]),
                      np.array([c.normal for c in contacts]), None, start)
    record = execute(World(scene, seed=seed), plan, start_joints=start)
    contact = measure(record, plan, scene.surface).contact_fraction
    stages.append({'stage': 'sweep (plan + play)', 'wall_s': time.perf_counter() - began,
                   'arm_s': float(record.times_s[-1])})
    log(f'  sweep along {len(contacts)} probed contacts: {100 * contact:.0f} % in contact')
    textures = list(TEXTURES)[:size.textures]
    began = time.perf_counter()
    collect(scene, size.job_sweeps, scratch / 'job', textures=textures,
            progress=lambda line: None)
    record_s = time.perf_counter() - began
    began = time.perf_counter()
    data = convert([scratch / 'job'], window=WINDOW, hop=WINDOW // 2,
                   progress=lambda line: None)
    convert_s = time.perf_counter() - began
    rate = data.info['sampling_rate_hz']
    stages.append({'stage': 'record', 'wall_s': record_s, 'arm_s': sum(
        r['samples'] for r in data.info['recordings']) / rate})
    stages.append({'stage': 'convert', 'wall_s': convert_s, 'arm_s': 0.0})
    estimator = make_estimator(model, size, seed=seed, threads=threads)
    began = time.perf_counter()
    estimator.fit(data.X, data.y, data.classes, groups=data.trial, channels=data.channels)
    folder = estimator.save(scratch / 'job_model', hop=WINDOW // 2, sampling_rate_hz=rate)
    stages.append({'stage': f'train ({model})', 'wall_s': time.perf_counter() - began,
                   'arm_s': 0.0})
    held_out = scratch / 'job_held_out'
    collect(replace(scene, seed=scene.seed + HELD_OUT_SEED_OFFSET), 1, held_out,
            textures=textures, progress=lambda line: None)
    test = convert([held_out], window=WINDOW, hop=WINDOW // 2, progress=lambda line: None)
    predictor = load_predictor(folder, threads=1)
    columns = [list(predictor.info.classes).index(name) for name in test.classes]
    decisions = decide_recordings(
        test, lambda i: predictor.predict_proba(test.X[i][None])[0][columns], threshold, rate)
    stages.append({'stage': 'live decision', 'wall_s': float(np.mean(
        [d['wall_s'] for d in decisions])), 'arm_s': float(np.mean(
            [d['contact_s'] for d in decisions]))})
    accuracy = float(np.mean([d['correct'] for d in decisions]))
    log(f'  live: {100 * accuracy:.0f} % of {len(decisions)} held-out sweeps right')
    return {'stages': stages, 'model': model, 'threshold': threshold, 'window': WINDOW,
            'sweeps': size.job_sweeps, 'textures': size.textures, 'contact_fraction': contact,
            'live_accuracy': accuracy, 'held_out': len(decisions), 'probed': len(contacts)}
