# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""How much each section of the accuracy-time report measures: `QUICK` (a test) or `DEFAULT`."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Size:
    """The amount of work of every section.

    Attributes:
        name: 'quick' or 'default'.
        textures: how many of the 12 textures the classification data holds.
        sweeps: sweeps per texture of the classification data (sections 1, 2).
        folds: grouped cross-validation folds.
        windows: window lengths (samples; hop half the window).
        models: the models compared (deep ones train `epochs` epochs).
        epochs: epochs of the deep models.
        speeds_mm_s: sliding speeds of section 4.
        speed_sweeps: sweeps per texture and speed (section 4).
        speed_contact_s: seconds of sliding contact of each section-4 sweep (at 60 mm/s
            more than 2 s runs out of the arm's reach on the plate).
        speed_window: window of section 4 (samples).
        probe_span_m: length of the probed line (section 3).
        probe_settings: (step m, descent speed m/s) pairs of section 3.
        sim_seconds: seconds of sliding of each section-5 sweep (at most 7: the plate's
            reachable stretch at 15 mm/s).
        filter_seconds: length of each section-6 motion (s).
        filter_rates_hz: Madgwick rates of section 6.
        filter_gains: Madgwick gains of section 6.
        job_sweeps: sweeps per texture recorded in section 7.
        latency_calls: single-window calls timed per model and runtime.
        identify_movements: the first movements of config/movements.yaml (section 8).
        identify_sweeps: sweeps per texture and movement (section 8).
        identify_seeds: episodes per held-out texture and fold (section 8).
    """

    name: str
    textures: int
    sweeps: int
    folds: int
    windows: tuple[int, ...]
    models: tuple[str, ...]
    epochs: int
    speeds_mm_s: tuple[float, ...]
    speed_sweeps: int
    speed_contact_s: float
    speed_window: int
    probe_span_m: float
    probe_settings: tuple[tuple[float, float], ...]
    sim_seconds: float
    filter_seconds: float
    filter_rates_hz: tuple[float, ...]
    filter_gains: tuple[float, ...]
    job_sweeps: int
    latency_calls: int
    identify_movements: int
    identify_sweeps: int
    identify_seeds: int


QUICK = Size(name='quick', textures=4, sweeps=4, folds=4, windows=(64, 128),
             models=('extratrees', 'minirocket', 'cnn_3'), epochs=3,
             speeds_mm_s=(5.0, 15.0, 30.0, 60.0), speed_sweeps=3, speed_contact_s=2.0,
             speed_window=64, probe_span_m=0.02,
             probe_settings=((0.01, 0.005), (0.01, 0.02), (0.02, 0.005)),
             sim_seconds=4.0, filter_seconds=8.0, filter_rates_hz=(50.0, 120.0, 350.0),
             filter_gains=(0.01, 0.03, 0.1, 0.3), job_sweeps=2, latency_calls=50,
             identify_movements=3, identify_sweeps=4, identify_seeds=5)

DEFAULT = Size(name='default', textures=8, sweeps=4, folds=4, windows=(64, 128, 256),
               models=('extratrees', 'minirocket', 'cnn_3'), epochs=15,
               speeds_mm_s=(5.0, 15.0, 30.0, 60.0), speed_sweeps=2, speed_contact_s=2.0,
               speed_window=64, probe_span_m=0.03,
               probe_settings=((0.01, 0.005), (0.01, 0.02), (0.005, 0.005), (0.02, 0.005)),
               sim_seconds=7.0, filter_seconds=30.0,
               filter_rates_hz=(50.0, 100.0, 120.0, 200.0, 350.0),
               filter_gains=(0.01, 0.02, 0.03, 0.06, 0.1, 0.2, 0.3), job_sweeps=2,
               latency_calls=200, identify_movements=8, identify_sweeps=5, identify_seeds=10)
