# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Recordings and datasets through the live classifier's core: what classifier_node says, when.

A recording's messages go to `live.OnlineClassifier` in the order they were logged, each
sensor sample with its header stamp and its log time as arrival, sweep/active with its
log time, the stated rate from recording/metadata: what classifier_node's worker does
with what its subscriptions receive. So alignment, gaps, resyncs, the contact rule, the
rate check, the evidence and the decision are the node's own, not a copy. The core is
polled every `STEP_HOPS` hops of IMU samples and every window is classified (a node whose
model keeps up). A long recording is decoded in a second process meanwhile
(`tactex_classify.data.decoder_process`).

A dataset has windows, not streams: each recording's windows go through `Evidence` in
start order, restarting where consecutive windows do not touch (contact was lost).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from tactex_classify.data.bags import (
    readable_parts,
    resolve_topics,
    ROLE_CHANNELS,
    TOPIC_ROLES,
)
from tactex_classify.data.dataset import Dataset
from tactex_classify.data.decoder_process import decoded_samples
from tactex_classify.errors import BagError
from tactex_classify.online.evidence import Estimate, Evidence, EvidenceSettings
from tactex_classify.online.live import LiveSettings, OnlineClassifier
from tactex_classify.online.runtime import Predictor
from tactex_classify.online.stream_health import stated_metadata

STEP_HOPS = 4  # hops of IMU samples between passes of the core


@dataclass
class Replayed:
    """What the classifier said on one recording.

    Attributes:
        name: the recording's path, or `DATASET#trial`.
        label: its recorded label (None when unlabelled).
        start_ns: stamp of its first sample (times below are from here).
        windows: (start_ns, end_ns, probabilities) of every classified window.
        decisions: (stamp_ns, class name) of each decision, in order.
        final: probabilities of the last estimate (None without any window).
        faults: windows not classified by cause, resets of the evidence by reason, and the
            stream's counts (late, dropped, invalid, resyncs).
        longest_contact: the longest run of samples in contact (a window needs its length).
    """

    name: str
    label: str | None
    start_ns: int
    windows: list[tuple[int, int, np.ndarray]] = field(default_factory=list)
    decisions: list[tuple[int, str]] = field(default_factory=list)
    final: np.ndarray | None = None
    faults: dict = field(default_factory=dict)
    standing_since: int | None = None  # first window of the evidence behind a decision
    longest_contact: int = 0

    @property
    def decision(self) -> str | None:
        """The first decision (None: the evidence never met the rule)."""
        return self.decisions[0][1] if self.decisions else None

    @property
    def decided_s(self) -> float | None:
        """Seconds from the first sample to the first decision."""
        return (self.decisions[0][0] - self.start_ns) / 1e9 if self.decisions else None


def replay_recording(predictor: Predictor, path: Path, *, live: LiveSettings | None = None,
                     evidence: EvidenceSettings | None = None,
                     remaps: Mapping[str, str] | None = None, rate_tolerance: float = 0.05,
                     progress: Callable[[int], None] | None = None) -> Replayed:
    """Run one recording through the live core.

    Raises:
        BagError: the recording cannot be read, lacks a topic the model needs, or its rate
            is not the model's (naming both).
    """
    info = predictor.info
    classifier = OnlineClassifier(predictor.predict_proba, info.stream, len(info.classes),
                                  live=live or LiveSettings(), evidence=evidence,
                                  newest_only=False,
                                  rate_tolerance=rate_tolerance)
    notes: list[str] = []
    inventory, parts = readable_parts(Path(path), notes)
    roles = resolve_topics(inventory.types, remaps)
    needed = classifier.windows.needed_roles
    missing = [role for role in needed if role not in roles]
    if missing:
        wanted = ', '.join(f'{TOPIC_ROLES[r][0]} ({", ".join(ROLE_CHANNELS[r])})'
                           for r in missing)
        contact = 'baro' not in info.stream.channels and 'pressure' in missing
        raise BagError(f'{path}: {info.model_id} reads channels {", ".join(info.stream.channels)}'
                       f'{" and the pressure for contact" if contact else ""}; the recording has '
                       f'no {wanted}; name it with --topic ROLE=NAME')
    by_topic = {roles[role]: role for role in (*needed, 'active', 'metadata') if role in roles}
    result = Replayed(str(path), None, 0)
    metadata: dict = {}
    imu_samples, step_every = 0, STEP_HOPS * classifier.windows.hop
    add = classifier.windows.add
    with decoded_samples(path, parts, by_topic,
                         sum(inventory.counts.get(topic, 0) for topic in by_topic)) as samples:
        for role, stamp, log_ns, data in samples:
            if role == 'active':
                classifier.windows.set_active(data, log_ns)
            elif role == 'metadata':
                stated = stated_metadata(data)
                if 'sensor_rate_hz' in stated:
                    classifier.rate.stated(stated['sensor_rate_hz'])
                metadata.update(stated)
            else:
                if not result.start_ns:
                    result.start_ns = stamp
                add(role, stamp, data, log_ns)
                if role == 'imu':
                    imu_samples += 1
                    if imu_samples % step_every == 0:
                        _take(classifier, result, info.classes)
                        if progress is not None:
                            progress(step_every)
    _take(classifier, result, info.classes)
    label = metadata.get('label')
    result.label = label if isinstance(label, str) and label.strip() else None
    result.faults = {**classifier.faults, 'resets': dict(classifier.resets), 'notes': notes,
                     **{k: v for k, v in classifier.windows.counts.items()
                        if k in ('late', 'dropped', 'invalid', 'off_timeline', 'resyncs')}}
    result.longest_contact = classifier.windows.longest_contact
    if not result.windows and classifier.faults['refused']:
        raise BagError(f'{path}: {classifier.last_fault}: classifier_node would refuse every '
                       'window; train a model on recordings at this rate')
    return result


def _take(classifier: OnlineClassifier, result: Replayed, classes) -> None:
    """One pass of the core; its estimates into the result."""
    for classified in classifier.step():
        window, estimate = classified.window, classified.estimate
        result.windows.append((window.start_ns, window.end_ns, classified.proba))
        _note(result, estimate, classes)


def _note(result: Replayed, estimate: Estimate, classes) -> None:
    """The estimate after a window; a decision is new when its evidence started anew."""
    result.final = estimate.probabilities
    since = estimate.spans_ns[0][0] if estimate.spans_ns else None
    if estimate.decided and since != result.standing_since:
        result.decisions.append((estimate.stamp_ns, classes[estimate.class_id]))
    result.standing_since = since if estimate.decided else None


def replay_dataset(predictor: Predictor, dataset: Dataset, name: str,
                   evidence: EvidenceSettings | None = None) -> list[Replayed]:
    """Each recording of a dataset: its windows' probabilities through the evidence.

    A dataset with more channels than the model reads gives it its own, in its order. A
    window holding NaN or inf is not classified (counted in the recording's faults as
    `non_finite`); the evidence restarts after it, as after lost contact.

    Raises:
        BagError: the dataset's channels, window or rate are not the model's (naming both).
    """
    stream = predictor.info.stream
    read = set(stream.channels) <= set(dataset.channels)
    mismatches = stream.mismatches(
        channels=stream.channels if read else dataset.channels, window=dataset.X.shape[1],
        sampling_rate_hz=dataset.info.get('sampling_rate_hz'))
    if mismatches:
        raise BagError(f'{name}: {predictor.info.model_id} does not fit it: '
                       + '; '.join(mismatches))
    X = dataset.X[:, :, [list(dataset.channels).index(c) for c in stream.channels]]
    finite = np.all(np.isfinite(X), axis=(1, 2))
    proba = np.zeros((len(X), len(predictor.info.classes)))
    if finite.any():
        proba[finite] = predictor.predict_proba(X[finite])
    period_ns = int(round(1e9 / stream.sampling_rate_hz))
    span_ns = stream.window * period_ns
    sources = recording_sources(dataset)
    results = []
    for trial in np.unique(dataset.trial):
        rows = np.flatnonzero(dataset.trial == trial)
        rows = rows[np.argsort(dataset.t0[rows], kind='stable')]
        starts = np.round(dataset.t0[rows] * 1e9).astype(np.int64)
        result = Replayed(f'{name}#{int(trial)}{sources.get(int(trial), "")}',
                          dataset.classes[dataset.y[rows[0]]], int(starts[0]))
        belief = Evidence(len(predictor.info.classes), period_ns, evidence or EvidenceSettings())
        result.faults = {'non_finite': int(np.sum(~finite[rows]))}
        previous_end = None
        for row, start in zip(rows[finite[rows]], starts[finite[rows]], strict=True):
            end = int(start) + span_ns - period_ns
            if previous_end is not None and start > previous_end + period_ns:
                belief.reset()  # windows that do not touch: contact was lost between them
            previous_end = end
            estimate = belief.add(proba[row], int(start), end)
            result.windows.append((int(start), end, proba[row]))
            _note(result, estimate, predictor.info.classes)
        results.append(result)
    return results


def recording_sources(dataset: Dataset) -> dict[int, str]:
    """Per trial, ' (FOLDER/NAME)' of the file it was converted from, as the sidecar says."""
    sources = {}
    for row in dataset.info.get('recordings', []):
        if isinstance(row, dict) and isinstance(row.get('trial'), int) \
                and isinstance(row.get('path'), str):
            source = Path(row['path'])
            sources[row['trial']] = f' ({source.parent.name}/{source.name})'
    return sources
