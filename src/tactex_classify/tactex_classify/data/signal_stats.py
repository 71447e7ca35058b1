# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Channel statistics of recordings, per texture: what a module (real or simulated) reports.

For each texture and channel over the samples that slid in contact: mean, RMS about the
mean, p99 and maximum of the magnitude, the share of samples at the chip's rails, the
samples beyond its full scale, and the dominant frequency (Welch's peak above 3 Hz).
Welch spectra per channel group, textures overlaid, go to PNG files. Where a recording
carries the simulator's ground truth, the Madgwick filter (as madgwick_node runs it) is
run over its raw IMU stream and its tilt against the true attitude of sensor_link while
sliding is reported: the error a contact normal taken from that attitude inherits.
Works on any recordings `tactex convert` reads, so a module's owner can hold the
simulation against their own.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
import math
from pathlib import Path

import numpy as np

from tactex_classify.data.bags import read_recording, Recording
from tactex_classify.data.dataset import FilterRule, keep_mask, recording_paths
from tactex_classify.data.stream_alignment import nearest
from tactex_common import chips, plotting
from tactex_common.channels import ACCEL, BARO, GYRO, MAG

GROUPS = {'accel': ACCEL, 'gyro': GYRO, 'mag': MAG, 'baro': BARO}
UNITS = {'accel': 'm/s^2', 'gyro': 'rad/s', 'mag': 'T', 'baro': 'Pa'}
# Welch segments (samples): about 2 s at 120 Hz, shorter for a shorter recording.
SEGMENT = 256
# The dominant frequency is looked for above this: below it lie the sweep's own motion
# over the uneven surface and the leakage of Welch's 0.5 Hz bins around it.
MIN_PEAK_HZ = 3.0


@dataclass(frozen=True)
class Limits:
    """The configured full scale, the rails and one count of each channel group (SI)."""

    full_scale: dict[str, float]
    rails: dict[str, tuple[float, float]]
    count: dict[str, float]

    @classmethod
    def configured(cls) -> Limits:
        """The ranges of tactex_common.chips (the firmware's)."""
        ranges = {'accel': chips.accel_range(), 'gyro': chips.gyro_range(),
                  'mag': chips.mag_range()}
        full = {g: r.full_scale_si for g, r in ranges.items()}
        rails = {g: r.rails_si for g, r in ranges.items()}
        count = {g: r.lsb_si for g, r in ranges.items()}
        full['baro'] = chips.PRESSURE_MAX_PA
        rails['baro'] = (chips.PRESSURE_MIN_PA, chips.PRESSURE_MAX_PA)
        count['baro'] = chips.PRESSURE_LSB_PA
        return cls(full, rails, count)


@dataclass
class TextureSignals:
    """The sliding samples of one texture's recordings, per channel, with their rate."""

    rate_hz: float
    samples: dict[str, list[np.ndarray]] = field(default_factory=dict)
    tilt_errors_deg: list[np.ndarray] = field(default_factory=list)
    recordings: int = 0


def collect(paths: Sequence[Path], *, rule: FilterRule | None = None,
            progress: Callable[[str], None] = lambda line: None) -> dict[str, TextureSignals]:
    """Read each recording; the sliding samples of each texture (label, else 'unlabelled').

    Args:
        paths: recordings, or folders holding recordings.
        rule: what counts as sliding in contact (as `tactex convert` decides it).
        progress: receives a line per recording.
    """
    textures: dict[str, TextureSignals] = {}
    paths = recording_paths(paths, progress)
    for index, path in enumerate(paths, 1):
        recording = read_recording(path)
        label = str(recording.metadata.get('label', 'unlabelled'))
        keep = keep_mask(recording, rule or FilterRule(), False, label)
        if not keep.any() and recording.truth is None and recording.active_ns is None:
            keep = np.ones_like(keep)
        entry = textures.setdefault(label, TextureSignals(recording.rate_hz))
        entry.recordings += 1
        for channel in recording.channels:
            entry.samples.setdefault(channel, []).append(recording.channel(channel)[keep])
        errors = madgwick_tilt_errors_deg(recording)
        if errors is not None:
            entry.tilt_errors_deg.append(errors[keep])
        progress(f'[{index}/{len(paths)}] {path.name}: {label}, {int(keep.sum())} of '
                 f'{keep.size} samples sliding in contact')
    return textures


def madgwick_tilt_errors_deg(recording: Recording) -> np.ndarray | None:
    """Tilt (deg) of the Madgwick attitude from the true one at each sample; None: no truth.

    NaN where the true attitude is no attitude (a zero or non-finite quaternion).
    """
    from tactex_sensor.madgwick import filter_batch, MadgwickConfig
    from tactex_sensor.orientation import tilt_between

    truth = recording.truth
    needed = (*ACCEL, *GYRO)
    if truth is None or truth.sensor_q.shape[0] < 2 or not set(needed) <= set(
            recording.channels) or recording.stamps_ns.size < 2:
        return None
    stamps = recording.stamps_ns
    dt = np.diff(stamps, prepend=stamps[0]) * 1e-9
    estimate = filter_batch(np.stack([recording.channel(c) for c in GYRO], axis=1),
                            np.stack([recording.channel(c) for c in ACCEL], axis=1), dt,
                            config=MadgwickConfig())
    truth_index = nearest(stamps, truth.edge_ns, math.inf)
    return np.degrees([tilt_between(q, truth.sensor_q[i])
                       for q, i in zip(estimate, truth_index, strict=True)])


def channel_row(values: np.ndarray, rate_hz: float, group: str, limits: Limits) -> dict:
    """The statistics of one channel's sliding samples (NaN dropped)."""
    values = values[np.isfinite(values)]
    if values.size == 0:
        return {'samples': 0}
    magnitude = np.abs(values)
    low, high = limits.rails[group]
    tolerance = 0.5 * limits.count[group]  # a reading within half a count sits on the rail
    at_rails = (values <= low + tolerance) | (values >= high - tolerance)
    beyond = magnitude > limits.full_scale[group] if group != 'baro' else (
        (values < chips.PRESSURE_MIN_PA) | (values > chips.PRESSURE_MAX_PA))
    return {'samples': int(values.size), 'mean': float(values.mean()),
            'rms': float(np.sqrt(np.mean((values - values.mean()) ** 2))),
            'p99': float(np.percentile(magnitude, 99)), 'max': float(magnitude.max()),
            'at_rails': float(at_rails.mean()), 'beyond_full_scale': int(beyond.sum()),
            'peak_hz': dominant_frequency(values, rate_hz)}


def spectrum(values: np.ndarray, rate_hz: float) -> tuple[np.ndarray, np.ndarray]:
    """Welch power spectral density (frequency Hz, power unit^2/Hz); empty when too short."""
    from scipy.signal import welch
    values = values[np.isfinite(values)]
    if values.size < 16 or not math.isfinite(rate_hz) or rate_hz <= 0:
        return np.zeros(0), np.zeros(0)
    return welch(values - values.mean(), fs=rate_hz, nperseg=min(SEGMENT, values.size))


def dominant_frequency(values: np.ndarray, rate_hz: float) -> float:
    """The frequency (Hz) of the largest spectral peak above MIN_PEAK_HZ; NaN if none."""
    frequency, power = spectrum(values, rate_hz)
    above = frequency > MIN_PEAK_HZ
    if not above.any() or not np.any(power[above] > 0):
        return math.nan
    return float(frequency[above][np.argmax(power[above])])


def statistics(textures: dict[str, TextureSignals], limits: Limits) -> dict:
    """Per texture and channel the statistics, per texture the Madgwick tilt error."""
    table = {}
    for texture, entry in sorted(textures.items()):
        rows = {}
        for group, channels in GROUPS.items():
            for channel in channels:
                if channel in entry.samples:
                    rows[channel] = channel_row(np.concatenate(entry.samples[channel]),
                                                entry.rate_hz, group, limits)
        errors = np.concatenate(entry.tilt_errors_deg) if entry.tilt_errors_deg else None
        errors = None if errors is None else errors[np.isfinite(errors)]  # truth without one
        table[texture] = {'recordings': entry.recordings, 'rate_hz': entry.rate_hz,
                          'channels': rows,
                          'madgwick_tilt_deg_median': None if errors is None or not errors.size
                          else float(np.median(errors))}
    return table


def warnings(table: dict) -> list[str]:
    """One line per texture and channel with samples beyond the configured full scale."""
    return [f'{texture}: {channel} has {row["beyond_full_scale"]} sample(s) beyond the '
            'configured full scale'
            for texture, entry in table.items() for channel, row in entry['channels'].items()
            if row.get('beyond_full_scale')]


def markdown(table: dict, limits: Limits) -> str:
    """The table as Markdown: one section per channel group, a row per texture and axis."""
    lines = ['# Channel statistics while sliding in contact', '',
             'Full scale (configured): ' + ', '.join(
                 f'{g} +-{limits.full_scale[g]:.4g} {UNITS[g]}' for g in ('accel', 'gyro',
                                                                           'mag')) +
             f'; barometer {chips.PRESSURE_MIN_PA / 1e3:g}-{chips.PRESSURE_MAX_PA / 1e3:g} kPa.',
             '']
    for group, channels in GROUPS.items():
        lines += [f'## {group} ({UNITS[group]})', '',
                  '| texture | channel | mean | RMS | p99 | max | at rails | beyond FS | '
                  'peak Hz |', '|---|---|---|---|---|---|---|---|---|']
        for texture, entry in table.items():
            for channel in channels:
                row = entry['channels'].get(channel)
                if not row or not row.get('samples'):
                    continue
                lines.append(f'| {texture} | {channel} | {row["mean"]:.4g} | {row["rms"]:.3g} | '
                             f'{row["p99"]:.4g} | {row["max"]:.4g} | '
                             f'{100 * row["at_rails"]:.2f} % | {row["beyond_full_scale"]} | '
                             f'{row["peak_hz"]:.1f} |')
        lines.append('')
    tilts = {t: e['madgwick_tilt_deg_median'] for t, e in table.items()
             if e['madgwick_tilt_deg_median'] is not None}
    if tilts:
        lines += ['## Madgwick tilt against the true attitude while sliding (median, deg)', '',
                  '| texture | median tilt error |', '|---|---|']
        lines += [f'| {t} | {v:.2f} |' for t, v in tilts.items()]
        lines.append('')
    return '\n'.join(lines)


def plot_spectra(textures: dict[str, TextureSignals], folder: Path) -> list[Path]:
    """One PNG per channel group: the Welch spectrum (axes summed) of each texture."""
    written = []
    for group, channels in GROUPS.items():
        plt, figure, axes = plotting.figure()
        drawn = False
        for texture, entry in sorted(textures.items()):
            total = None
            for channel in channels:
                if channel not in entry.samples:
                    continue
                parts = [spectrum(v, entry.rate_hz) for v in entry.samples[channel]]
                parts = [p for p in parts if p[0].size]
                if not parts:
                    continue
                size = min(p[0].size for p in parts)
                power = np.mean([p[1][:size] for p in parts], axis=0)
                frequency = parts[0][0][:size]
                total = power if total is None else total[:size] + power[:total.size]
            if total is not None and np.any(total > 0):
                axes.semilogy(frequency[:total.size], total, label=texture, linewidth=1)
                drawn = True
        if not drawn:
            plt.close(figure)
            continue
        axes.set_xlabel('frequency (Hz)')
        axes.set_ylabel(f'power ({UNITS[group]}^2/Hz, axes summed)')
        axes.set_title(f'{group} while sliding in contact')
        plotting.legend_outside(axes)
        axes.grid(True, which='both', alpha=0.3)
        path = folder / f'spectrum_{group}.png'
        plotting.save(plt, figure, path)
        written.append(path)
    return written
