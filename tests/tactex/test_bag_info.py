# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex bag info`: storage, span, label, and per topic type, count, rate, jitter and gaps.

Like `ros2 bag info`, for every format tactex reads; `--json` gives the same for scripts.
"""

import json
import re

import numpy as np
import pytest
from support.bagfactory import ramp, write_bag
from support.foreign_bags import bare, converted, imu_only, zeros_bag

from tactex.cli import main
from tactex_classify.data import bag_info, inflation, mcap_index
from tactex_classify.data.bag_info import describe

PERIOD_NS = 10_000_000  # 100 Hz


@pytest.fixture(scope='module')
def gappy(tmp_path_factory):
    """100 Hz IMU log times with one 0.2 s gap after 1 s, and 0.5 ms jitter."""
    rng = np.random.default_rng(0)
    log = 10**12 + np.arange(300) * PERIOD_NS + rng.integers(-500_000, 500_000, 300)
    log[100:] += 200_000_000
    return imu_only(tmp_path_factory.mktemp('info') / 'gappy.bag', log, log, ros1=True)


def run(capsys, *argv):
    code = main(['bag', 'info', *map(str, argv)])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_text_shows_storage_span_and_each_topics_rate_jitter_and_gaps(gappy, capsys):
    code, out, _ = run(capsys, gappy)
    assert code == 0
    assert 'gappy.bag  ROS 1 bag, format 2.0' in out
    assert 'Duration:    3.19' in out and 'Messages:    300' in out
    row = next(line for line in out.splitlines() if '/tactile/imu/data_raw' in line)
    assert 'sensor_msgs/msg/Imu' in row and '300 msgs' in row
    assert re.search(r' (99\.9\d|100\.0\d) Hz', row) and 'gaps: 0.21' in row and 'at 0.99' in row


def test_json_gives_the_same_numbers_for_scripts(gappy, capsys):
    code, out, _ = run(capsys, '--json', gappy)
    (info,) = json.loads(out)
    (topic,) = info['topics']
    assert code == 0 and info['messages'] == 300 and topic['count'] == 300
    assert topic['rate_hz'] == pytest.approx(100.0, rel=0.01)
    assert 0.1 < topic['jitter_ms'] < 0.5  # uniform +-0.5 ms on both ends of a period
    assert topic['gap_count'] == 1 and topic['gaps'][0][1] == pytest.approx(0.21, abs=0.002)



def test_json_lists_an_unreadable_recording_with_its_reason_beside_the_rest(
        gappy, tmp_path, capsys):
    (tmp_path / 'text.bag').write_text('this is not a bag\n' * 20)
    code, out, err = run(capsys, '--json', gappy, tmp_path / 'text.bag')
    described, unreadable = json.loads(out)
    assert described['messages'] == 300
    assert unreadable == {'path': str(tmp_path / 'text.bag'), 'unreadable':
                          f'{tmp_path / "text.bag"}: cannot read: not a ROS 1 bag (it does not '
                          'start with "#ROSBAG V2.0")'}
    assert code == 1 and 'error: 1 of 2 recordings cannot be read' in err

def test_no_timing_reads_the_index_only(gappy, capsys):
    code, out, _ = run(capsys, '--no-timing', '--json', gappy)
    (topic,) = json.loads(out)[0]['topics']
    assert code == 0 and topic['count'] == 300 and topic['rate_hz'] is None


def test_an_mcap_files_message_indexes_give_the_timing_reading_every_message_gives(
        tmp_path, monkeypatch):
    rng = np.random.default_rng(1)
    log = 10**12 + np.arange(300) * PERIOD_NS + rng.integers(-500_000, 500_000, 300)
    log[200:] += 300_000_000
    path = imu_only(tmp_path / 'gappy', log, log)
    listed = []
    monkeypatch.setattr(bag_info, 'log_times',
                        lambda files: listed.append(mcap_index.log_times(files)) or listed[-1])
    from_indexes = describe(path)
    assert listed and listed[0] is not None  # the indexes were read, and sufficed
    monkeypatch.setattr(bag_info, 'log_times', lambda files: None)  # as if there were none
    assert describe(path).topics == from_indexes.topics
    assert from_indexes.topics[0].gap_count == 1


def test_every_format_of_one_recording_gives_the_same_summary(tmp_path):
    stamps, values = ramp(120)
    folder = write_bag(tmp_path / 'rec', stamps, values, metadata={'label': 'cork', 'trial': 2})
    variants = [folder, converted(folder, tmp_path / 'rec.bag'),
                bare(folder, tmp_path / 'rec.mcap'),
                converted(folder, tmp_path / 'zstd', compress='zstd', mode='message')]
    infos = [describe(path) for path in variants]
    for info in infos:
        assert info.metadata == {'label': 'cork', 'trial': 2}
        assert [(t.topic, t.msgtype, t.count, t.rate_hz) for t in info.topics] == [
            (t.topic, t.msgtype, t.count, t.rate_hz) for t in infos[0].topics]
        assert (info.start_ns, info.end_ns) == (infos[0].start_ns, infos[0].end_ns)
    assert 'zstd compression by message' in infos[3].parts[0].storage
    for path, info in zip(variants, infos, strict=True):  # the index's summary says the same
        summary = describe(path, timing=False)
        assert (summary.metadata, summary.messages, summary.start_ns, summary.end_ns) == (
            info.metadata, info.messages, info.start_ns, info.end_ns)


def test_the_label_is_shown_and_an_unreadable_part_is_listed_beside_the_rest(tmp_path, capsys):
    stamps, values = ramp(60)
    for index in range(3):
        write_bag(tmp_path / 'rec' / f'part_{index:04d}', stamps[20 * index:20 * index + 20],
                  values[20 * index:20 * index + 20], metadata={'label': 'felt', 'trial': 7})
    storage = next((tmp_path / 'rec' / 'part_0001').glob('*.mcap'))
    storage.write_bytes(storage.read_bytes()[:300])
    code, out, _ = run(capsys, tmp_path / 'rec')
    assert code == 0
    assert 'Label:       felt (trial 7)' in out
    assert ('part_0001  rosbag2 folder (.mcap), 0.0 MiB   UNREADABLE: a truncated MCAP file'
            in out)
    assert 'Messages:    122' in out  # the two readable parts: 3 topics of 20, their metadata


def test_a_folder_of_recordings_describes_each(tmp_path, capsys):
    stamps, values = ramp(30)
    write_bag(tmp_path / 'all' / 'a', stamps, values)
    converted(tmp_path / 'all' / 'a', tmp_path / 'all' / 'b.bag')
    code, out, _ = run(capsys, '--no-timing', tmp_path / 'all')
    assert code == 0 and out.count('Recording:') == 2


def test_a_block_that_inflates_without_bound_ends_in_one_error_line(tmp_path, capsys,
                                                                     monkeypatch):
    monkeypatch.setattr(inflation, 'MIN_LIMIT_BYTES', 1024**2)  # (metadata is always read)
    code, _, err = run(capsys, zeros_bag(tmp_path / 'bomb', 16 * 1024**2, 'zstd',
                                         topic='/recording/metadata'))
    assert code == 1 and 'Traceback' not in err
    assert re.search(r'^error: .*bomb: cannot read: a zstd-compressed block inflates past', err)


@pytest.mark.parametrize('ns, shown', [
    (1_700_000_003_990_000_000, '2023-11-14 22:13:23.990 UTC (1700000003.990000000)'),
    (1_700_000_000_009_999_999, '(1700000000.009999999)'),  # a float read .009999990
    (-1, '(-0.000000001)')])
def test_a_stamps_seconds_are_shown_to_the_nanosecond(ns, shown):
    from tactex_classify.data.bag_info import _when
    assert shown in _when(ns)
