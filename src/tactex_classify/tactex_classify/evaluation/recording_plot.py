# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""A recording at a glance: its channels against the edge's travel (or time), windows shaded."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from tactex_classify.data.bags import Recording
from tactex_classify.data.edge_travel import edge_travel_m
from tactex_common import plotting

# Channel groups drawn on one axis each, with their SI unit.
PANELS = ((('ax', 'ay', 'az'), 'acceleration (m/s²)'),
          (('gx', 'gy', 'gz'), 'angular rate (rad/s)'),
          (('mx', 'my', 'mz'), 'magnetic field (T)'), (('baro',), 'pressure (Pa)'))


def plot_recording(path: Path, recording: Recording, kept: np.ndarray) -> str:
    """Write the recording's channels to `path`; returns what the horizontal axis shows.

    The axis is the sensor edge's travel along its path (mm) where the recording says
    where the edge was (ground truth, or the arm's joint states), so sweeps at other
    speeds line up by position; seconds since the first sample otherwise.

    Args:
        path: the PNG to write.
        recording: the aligned samples (`tactex_classify.data.bags.read_recording`).
        kept: (n,) bool, the samples `tactex convert` would cut windows from (shaded).
    """
    panels = [(names, unit) for names, unit in PANELS
              if any(name in recording.channels for name in names)]
    columns = 1 if len(panels) <= 2 else 2  # a grid of house panels, two across at most
    rows = max(math.ceil(len(panels) / columns), 1)
    plt, figure, axes = plotting.figure(rows, columns, squeeze=False)
    travel = edge_travel_m(recording)
    if travel is not None:
        along = 1e3 * travel[0]
        axis_label = f'edge travel along its path (mm, from {travel[1]})'
    else:
        along = (recording.stamps_ns - recording.stamps_ns[0]) / 1e9 \
            if recording.stamps_ns.size else np.zeros(0)
        axis_label = 'time since the first sample (s; no edge positions recorded)'

    for index, axis in enumerate(axes.flat):
        if index >= len(panels):
            axis.set_visible(False)
            continue
        names, unit = panels[index]
        for name in names:
            if name in recording.channels:
                axis.plot(along, recording.values[:, recording.channels.index(name)],
                          linewidth=0.7, label=name)
        if kept.any():
            axis.fill_between(along, 0, 1, where=kept, transform=axis.get_xaxis_transform(),
                              color='tab:green', alpha=0.12, label='sliding in contact')
        axis.set_ylabel(unit, fontsize=8)
        if index + columns >= len(panels):  # nothing drawn below it
            axis.set_xlabel(axis_label, fontsize=8)
        plotting.legend_outside(axis)
        axis.grid(alpha=0.3)
    label = recording.metadata.get('label', 'unlabelled')
    figure.suptitle(f'{recording.path.name}: {label}, {recording.stamps_ns.size} samples at '
                    f'{recording.rate_hz:.0f} Hz, {int(kept.sum())} sliding in contact',
                    fontsize=9)
    plotting.save(plt, figure, path)
    return axis_label
