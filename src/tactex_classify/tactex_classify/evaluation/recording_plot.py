# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""A recording at a glance: its ten channels against time, the windows' samples shaded."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from tactex_classify.data.bags import Recording  # noqa: E402

# Channel groups drawn on one axis each, with their SI unit.
PANELS = ((('ax', 'ay', 'az'), 'acceleration (m/s²)'),
          (('gx', 'gy', 'gz'), 'angular rate (rad/s)'),
          (('mx', 'my', 'mz'), 'magnetic field (T)'), (('baro',), 'pressure (Pa)'))


def plot_recording(path: Path, recording: Recording, kept: np.ndarray) -> None:
    """Write the recording's channels against seconds since its first sample to `path`.

    Args:
        path: the PNG to write.
        recording: the aligned samples (`tactex_classify.data.bags.read_recording`).
        kept: (n,) bool, the samples `tactex convert` would cut windows from (shaded).
    """
    panels = [(names, unit) for names, unit in PANELS
              if any(name in recording.channels for name in names)]
    figure, axes = plt.subplots(max(len(panels), 1), 1, figsize=(9, 2.0 * max(len(panels), 1)
                                                                  + 0.8), sharex=True,
                                squeeze=False)
    seconds = (recording.stamps_ns - recording.stamps_ns[0]) / 1e9 \
        if recording.stamps_ns.size else np.zeros(0)
    for axis, (names, unit) in zip(axes[:, 0], panels, strict=False):
        for name in names:
            if name in recording.channels:
                axis.plot(seconds, recording.values[:, recording.channels.index(name)],
                          linewidth=0.7, label=name)
        if kept.any():
            axis.fill_between(seconds, 0, 1, where=kept, transform=axis.get_xaxis_transform(),
                              color='tab:green', alpha=0.12, label='sliding in contact')
        axis.set_ylabel(unit, fontsize=8)
        axis.legend(loc='upper left', bbox_to_anchor=(1.01, 1.0), fontsize=7)
        axis.grid(alpha=0.3)
    label = recording.metadata.get('label', 'unlabelled')
    axes[0, 0].set_title(f'{recording.path.name}: {label}, {recording.stamps_ns.size} samples '
                         f'at {recording.rate_hz:.0f} Hz, {int(kept.sum())} sliding in contact',
                         fontsize=9)
    axes[-1, 0].set_xlabel('time since the first sample (s)')
    figure.tight_layout()
    figure.savefig(path, dpi=110, bbox_inches='tight')
    plt.close(figure)
