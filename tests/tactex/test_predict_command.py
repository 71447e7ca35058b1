# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex predict`: a checkpoint on recordings or datasets says what classifier_node would.

It runs the live core (alignment, gaps, contact, rate check, evidence, decision) on each
recording's messages in logged order, and writes per recording and per window CSVs, a
summary and, with labels, a confusion with a no-decision column.
"""

import csv
import json
import subprocess
import sys

import numpy as np
import pytest
from support.bagfactory import write_bag
from support.foreign_bags import converted
from support.livestream import write_checkpoints

from tactex.cli import main
from tactex_classify.data.dataset import convert, Dataset
from tactex_classify.models.baselines import MiniRocketRidge

RATE_HZ = 120.0
PERIOD_NS = int(1e9 / RATE_HZ)


def texture(kind: str, count: int, seed: int) -> np.ndarray:
    """Ten channels of a texture: a 9 Hz ripple ('ridged') or a 31 Hz one ('fine')."""
    rng = np.random.default_rng(seed)
    t = np.arange(count) / RATE_HZ
    frequency = 9.0 if kind == 'ridged' else 31.0
    values = 0.2 * rng.normal(size=(count, 10)) + np.sin(2 * np.pi * frequency * t)[:, None]
    values[:, 9] += 101_325.0
    return values


@pytest.fixture(scope='module')
def lab(tmp_path_factory):
    """Six labelled live-order recordings of two textures and a MiniRocket trained on them."""
    root = tmp_path_factory.mktemp('predict')
    for index in range(6):
        kind = ('ridged', 'fine')[index % 2]
        stamps = 10**12 + index * 10**11 + np.arange(600, dtype=np.int64) * PERIOD_NS
        write_bag(root / 'recs' / f'{kind}_{index}', stamps, texture(kind, 600, index),
                  metadata={'label': kind, 'trial': index, 'sensor_rate_hz': RATE_HZ},
                  active=[(stamps[30], stamps[-30])], live_order=True)
    dataset = convert([root / 'recs'], window=64, hop=32, progress=lambda line: None)
    dataset.save(root / 'data.npz')
    MiniRocketRidge(dilations=4).fit(dataset.X, dataset.y, dataset.classes).save(
        root / 'model', hop=32, sampling_rate_hz=RATE_HZ)
    return root


def run(capsys, *argv):
    code = main(['predict', *map(str, argv)])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_recordings_get_a_decision_a_time_and_the_files_beside(lab, tmp_path, capsys):
    code, out, _ = run(capsys, lab / 'model', lab / 'recs', '--out', tmp_path / 'p')
    assert code == 0
    assert 'accuracy by recording: 100.0 % of 6 (0 without a decision)' in out
    rows = list(csv.DictReader(open(tmp_path / 'p' / 'recordings.csv')))
    assert [r['decision'] for r in rows] == [r['label'] for r in rows]
    assert all(0 < float(r['decided_s']) < 5 for r in rows)
    windows = list(csv.DictReader(open(tmp_path / 'p' / 'windows.csv')))
    assert len(windows) == sum(int(r['windows']) for r in rows) > 6 * 10
    assert {'p_fine', 'p_ridged'} <= set(windows[0])
    summary = json.loads((tmp_path / 'p' / 'summary.json').read_text())
    assert summary['scores']['accuracy'] == 1.0
    assert summary['scores']['confusion']['predicted'][-1] == 'no decision'
    assert (tmp_path / 'p' / 'confusion.png').stat().st_size > 1000


def test_a_ros1_copy_of_a_recording_gives_the_same_windows_and_decision(lab, tmp_path, capsys):
    old = converted(lab / 'recs' / 'ridged_0', tmp_path / 'ridged_0.bag')
    outputs = []
    for path, out in ((lab / 'recs' / 'ridged_0', tmp_path / 'a'), (old, tmp_path / 'b')):
        assert run(capsys, lab / 'model', path, '--out', out)[0] == 0
        outputs.append([row[1:] for row in csv.reader(open(out / 'windows.csv'))])
    assert outputs[0] == outputs[1] and len(outputs[0]) > 10


def test_a_threshold_of_one_never_decides(lab, capsys):
    code, out, _ = run(capsys, lab / 'model', lab / 'recs' / 'fine_1', '--threshold', '1')
    assert code == 0 and 'fine_1: no decision, 1' in out
    assert '0.0 % of 1 (1 without a decision)' in out


def test_a_dataset_goes_through_the_evidence_recording_by_recording(lab, capsys):
    code, out, _ = run(capsys, lab / 'model', lab / 'data.npz')
    assert code == 0 and out.count('data.npz#') == 6
    assert 'data.npz#0 (recs/ridged_0): ridged' in out  # named by the recording it came from
    assert 'accuracy by recording: 100.0 % of 6' in out


def test_the_dataset_a_model_was_trained_on_is_called_in_sample(lab, tmp_path, capsys):
    dataset = Dataset.load(lab / 'data.npz')
    model = MiniRocketRidge(dilations=4).fit(dataset.X, dataset.y, dataset.classes).save(
        tmp_path / 'model', hop=32, sampling_rate_hz=RATE_HZ, trained_on=dataset.digest())
    code, _, err = run(capsys, model, lab / 'data.npz', '--out', tmp_path / 'report')
    assert code == 0 and 'data.npz is the dataset' in err and 'in-sample' in err
    summary = json.loads((tmp_path / 'report' / 'summary.json').read_text())
    assert summary['trained_on_these'] == [str(lab / 'data.npz')]
    code, _, err = run(capsys, lab / 'model', lab / 'data.npz')  # trained_on not kept
    assert code == 0 and 'in-sample' not in err


def test_labels_the_model_does_not_know_are_named_and_their_recall_is_zero(lab, tmp_path,
                                                                          capsys):
    dataset = Dataset.load(lab / 'data.npz')
    renamed = Dataset(dataset.X, dataset.y, dataset.trial, dataset.t0,  # fine labelled cork
                      [{'fine': 'cork'}.get(c, c) for c in dataset.classes], dataset.info,
                      dataset.channels)
    code, out, err = run(capsys, lab / 'model', renamed.save(tmp_path / 'cork.npz'), '--out',
                         tmp_path / 'report')
    assert code == 0 and 'label(s) cork are not classes of' in err
    scores = json.loads((tmp_path / 'report' / 'summary.json').read_text())['scores']
    assert scores['recall']['cork'] == 0.0 and scores['labels_not_in_model'] == ['cork']
    assert 'accuracy by recording: 50.0 % of 6' in out


def test_a_recording_at_another_rate_is_refused_naming_both_rates(lab, tmp_path, capsys):
    stamps = 10**12 + np.arange(300, dtype=np.int64) * 33_333_333
    write_bag(tmp_path / 'slow', stamps, texture('fine', 300, 9), metadata={'label': 'fine'},
              active=[(stamps[0], stamps[-1])], live_order=True)
    code, _, err = run(capsys, lab / 'model', tmp_path / 'slow')
    assert code == 1
    assert 'the model was trained at 120 Hz, the stream runs at 30 Hz' in err


def test_a_channel_the_model_needs_and_the_recording_lacks_is_named(lab, tmp_path, capsys):
    stamps = 10**12 + np.arange(300, dtype=np.int64) * PERIOD_NS
    write_bag(tmp_path / 'nomag', stamps, texture('fine', 300, 9), mag_stamps_ns=[],
              live_order=True)
    code, _, err = run(capsys, lab / 'model', tmp_path / 'nomag')
    assert code == 1 and 'has no tactile/imu/mag (mx, my, mz)' in err


def test_a_model_on_channels_no_topic_carries_is_refused_for_recordings_naming_them(
        lab, tmp_path, capsys):
    data = Dataset.load(lab / 'data.npz')
    renamed = Dataset(data.X[:, :, :2], data.y, data.trial, data.t0, data.classes, data.info,
                      ['ax', 'pressure'])
    MiniRocketRidge(dilations=2).fit(renamed.X, renamed.y, renamed.classes,
                                     channels=renamed.channels).save(
        tmp_path / 'model', hop=32, sampling_rate_hz=RATE_HZ)
    code, _, err = run(capsys, tmp_path / 'model', lab / 'recs')
    assert code == 1 and 'Traceback' not in err
    assert 'error: CHECKPOINT' in err and '(pressure missing)' in err


def test_a_model_on_some_channels_reads_them_from_a_dataset_with_more(lab, tmp_path, capsys):
    data = Dataset.load(lab / 'data.npz')
    picked = [data.channels.index(c) for c in ('gz', 'ax')]
    MiniRocketRidge(dilations=4).fit(data.X[:, :, picked], data.y, data.classes,
                                     channels=['gz', 'ax']).save(
        tmp_path / 'model', hop=32, sampling_rate_hz=RATE_HZ)
    code, out, _ = run(capsys, tmp_path / 'model', lab / 'data.npz')
    assert code == 0 and 'accuracy by recording: 100.0 % of 6' in out


def test_a_window_with_nan_or_inf_is_skipped_and_counted_the_rest_decides(lab, tmp_path, capsys):
    data = Dataset.load(lab / 'data.npz')
    X = data.X.copy()
    X[0, 3, 1], X[1, 0, 0] = np.nan, np.inf
    Dataset(X, data.y, data.trial, data.t0, data.classes, data.info, data.channels).save(
        tmp_path / 'holes.npz')
    code, out, _ = run(capsys, lab / 'model', tmp_path / 'holes.npz', '--out', tmp_path / 'r')
    assert code == 0 and 'accuracy by recording: 100.0 % of 6' in out
    rows = json.loads((tmp_path / 'r' / 'summary.json').read_text())
    assert sum(r['faults'].get('non_finite', 0) for r in rows['recordings']) == 2


def test_a_hop_longer_than_the_window_is_refused_naming_both(lab, capsys):
    code, _, err = run(capsys, lab / 'model', lab / 'recs', '--hop', '65')
    assert code == 1
    assert "error: --hop 65 is longer than the checkpoint's window 64" in err


def test_a_contact_shorter_than_a_window_says_so_with_its_length(lab, tmp_path, capsys):
    stamps = 10**12 + np.arange(600, dtype=np.int64) * PERIOD_NS
    write_bag(tmp_path / 'brief', stamps, texture('fine', 600, 9), metadata={'label': 'fine'},
              active=[(stamps[100], stamps[139])], live_order=True)
    code, out, _ = run(capsys, lab / 'model', tmp_path / 'brief')
    assert code == 0
    assert 'brief: no decision, 0 windows (at most 40 samples in contact at a time, ' \
           'shorter than one window of 64)' in out


@pytest.mark.slow
def test_an_onnx_checkpoint_predicts_without_torch(lab, tmp_path):
    checkpoint = write_checkpoints(tmp_path) / 'cnn'
    code = ('import sys; from tactex.cli import main; '
            f"code = main(['predict', '{checkpoint}', '{lab / 'recs' / 'fine_1'}', "
            "'--runtime', 'onnxruntime']); print('torch' in sys.modules); sys.exit(code)")
    done = subprocess.run([sys.executable, '-c', code], capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    assert 'fine_1: ' in done.stdout and done.stdout.strip().endswith('False')
