# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Bag -> dataset conversion: alignment, filtering, windows, and every awkward recording."""

import json

import numpy as np
import pytest
from rosbags.highlevel import AnyReader, AnyReaderError
from rosbags.rosbag2 import StoragePlugin
from support.bagfactory import ramp, strip_type_definitions, T, write_bag

from tactex.cli import main
from tactex_classify.data.bags import parse_topic_remaps, read_recording, resolve_topics
from tactex_classify.data.dataset import convert, Dataset, window_starts
from tactex_classify.data.stream_alignment import align, Stream
from tactex_classify.errors import BagError, DatasetError
from tactex_common.channels import CHANNELS
from tactex_common.interfaces import typestore

QUIET = {'progress': lambda line: None}


def test_roundtrip_bag_to_dataset_keeps_si_values_and_order(tmp_path):
    stamps, values = ramp(64)
    write_bag(tmp_path / 'a', stamps, values, metadata={'label': 'wood', 'trial': 7})
    data = convert([tmp_path / 'a'], window=16, hop=8, all_samples=True, **QUIET)
    assert data.X.shape == (7, 16, 10) and data.X.dtype == np.float32
    np.testing.assert_array_equal(data.X[1], values[8:24])  # every channel in its place
    assert data.classes == ['wood'] and set(data.trial) == {7}
    np.testing.assert_allclose(data.t0[1], stamps[8] * 1e-9)


def test_save_and_load_roundtrip_without_pickle(tmp_path):
    stamps, values = ramp(40)
    write_bag(tmp_path / 'a', stamps, values, metadata={'label': 'wood', 'trial': 1})
    data = convert([tmp_path / 'a'], window=8, hop=4, all_samples=True, **QUIET)
    loaded = Dataset.load(data.save(tmp_path / 'set.npz'))
    np.testing.assert_array_equal(loaded.X, data.X)
    assert loaded.classes == ['wood'] and loaded.info['window'] == 8
    sidecar = json.loads((tmp_path / 'set.json').read_text())
    assert sidecar['channels'][-1] == 'baro' and sidecar['hop'] == 4


def test_out_of_order_and_duplicated_stamps_are_sorted_and_counted(tmp_path):
    stamps, values = ramp(30)
    order = np.arange(30)
    order[[5, 6]] = order[[6, 5]]
    shuffled = np.concatenate([stamps[order], stamps[10:12]])  # two sent again, at the end
    rows = np.concatenate([values[order], values[10:12]])
    write_bag(tmp_path / 'a', shuffled, rows)
    recording = read_recording(tmp_path / 'a')
    np.testing.assert_array_equal(recording.values[:, 0], np.arange(30))
    assert recording.dropped['imu_duplicates'] == 2
    assert recording.reordered['imu'] == 3  # 5 after 6, and the repeats: sorted, kept
    assert not any('out_of_order' in name for name in recording.dropped)


def test_a_device_clock_that_restarts_keeps_the_samples_in_the_order_they_were_logged(
        tmp_path):
    device, values = ramp(80)  # header stamps from the device's clock, which restarts
    device[40:] -= device[40] - 5_000_000
    logged = 7 * 10**12 + np.arange(80) * 8_333_333
    logged[40:] += 2 * 10**9  # it was away 2 s
    write_bag(tmp_path / 'a', device, values, metadata={'label': 'wood'}, log_ns=logged)
    recording = read_recording(tmp_path / 'a')
    np.testing.assert_array_equal(recording.values[:, 0], np.arange(80))  # none interleaved
    assert recording.clock_resets == 1 and not recording.dropped['unaligned_samples']
    assert any('device clock restarting' in note and '/tactile/imu/data_raw 1 time(s)' in note
               for note in recording.notes)
    data = convert([tmp_path / 'a'], window=20, hop=10, all_samples=True, **QUIET)
    assert data.info['recordings'][0]['clock_resets'] == 1
    assert len(data.X) == 6  # three windows each side, none across the 2 s gap


def test_nan_samples_are_dropped_and_counted(tmp_path):
    stamps, values = ramp(30)
    values[3, 7] = np.nan  # mag chip silent
    values[4, 9] = np.nan  # barometer silent
    write_bag(tmp_path / 'a', stamps, values)
    recording = read_recording(tmp_path / 'a')
    assert recording.dropped['nan_samples'] == 2 and len(recording.values) == 28


def test_a_stream_that_stops_early_limits_the_joined_samples(tmp_path):
    stamps, values = ramp(40)
    write_bag(tmp_path / 'a', stamps, values, pressure_stamps_ns=stamps[:25])
    recording = read_recording(tmp_path / 'a')
    assert len(recording.values) == 25 and recording.dropped['unaligned_samples'] == 15


def test_streams_with_offset_stamps_join_by_nearest(tmp_path):
    stamps, values = ramp(20)
    write_bag(tmp_path / 'a', stamps, values, mag_stamps_ns=stamps + 3_000_000)
    recording = read_recording(tmp_path / 'a')
    np.testing.assert_array_equal(recording.values[:, 6], values[:, 6])


def test_stamps_across_the_device_clock_wrap_stay_continuous(tmp_path):
    from tactex_sensor.clock import DeviceClock
    clock = DeviceClock()
    raw = [(2**32 - 20_000 + i * 8_333) % 2**32 for i in range(30)]
    stamps = np.array([clock.stamp_ns(r, 5 * 10**12 + i * 8_333_000) for i, r in enumerate(raw)])
    _, values = ramp(30)
    write_bag(tmp_path / 'a', stamps, values, metadata={'label': 'x'})
    data = convert([tmp_path / 'a'], window=30, hop=30, all_samples=True, **QUIET)
    assert len(data.X) == 1  # one window spans the wrap: no gap was seen


def test_segment_topic_selects_moving_in_contact_samples(tmp_path):
    stamps, values = ramp(100)
    write_bag(tmp_path / 'a', stamps, values, metadata={'label': 'x'},
              active=[(stamps[20], stamps[59])])
    data = convert([tmp_path / 'a'], window=20, hop=20, **QUIET)
    np.testing.assert_array_equal(data.X[:, 0, 0], [20, 40])


def test_without_segment_topic_motion_and_pressure_decide(tmp_path):
    stamps, values = ramp(100)
    values[:, 9] = 101_000.0
    values[30:80, 9] += 300.0  # pressed
    speed = np.where((np.arange(100) >= 40) & (np.arange(100) < 100), 0.1, 0.0)
    write_bag(tmp_path / 'a', stamps, values, metadata={'label': 'x'}, joint_speed=speed)
    data = convert([tmp_path / 'a'], window=10, hop=10, **QUIET)
    np.testing.assert_array_equal(data.X[:, 0, 0], [40, 50, 60, 70])


def test_windows_exactly_at_the_recording_boundaries():
    keep = np.ones(40, dtype=bool)
    stamps = np.arange(40) * 10
    assert window_starts(keep, stamps, 20, 10) == [0, 10, 20]
    assert window_starts(keep, stamps, 40, 10) == [0]
    assert window_starts(keep, stamps, 41, 10) == []
    gap = stamps.copy()
    gap[20:] += 1000  # a hole in the stream: no window may straddle it
    assert window_starts(keep, gap, 20, 10) == [0, 20]


def test_truncated_bag_is_reported_by_name_and_the_rest_converted(tmp_path):
    stamps, values = ramp(40)
    write_bag(tmp_path / 'good', stamps, values, metadata={'label': 'x', 'trial': 1})
    bad = write_bag(tmp_path / 'bad', stamps, values, metadata={'label': 'x', 'trial': 2})
    (bad / 'metadata.yaml').unlink()  # as after a crash: no metadata, storage cut short
    storage = bad / 'bad.mcap'
    storage.write_bytes(storage.read_bytes()[:-100])
    lines = []
    data = convert([tmp_path], window=10, hop=10, all_samples=True, progress=lines.append)
    assert set(data.trial) == {1}
    assert any('bad' in line and 'truncated MCAP' in line for line in lines)
    assert data.info['skipped'][0]['path'].endswith('bad')


def test_a_folder_that_lost_its_metadata_converts_as_it_is(tmp_path):
    stamps, values = ramp(40)
    write_bag(tmp_path / 'rec', stamps, values, metadata={'label': 'x', 'trial': 2})
    (tmp_path / 'rec' / 'metadata.yaml').unlink()
    data = convert([tmp_path], window=10, hop=10, all_samples=True, **QUIET)
    assert set(data.trial) == {2} and len(data.X) == 4


def test_corrupt_bag_file_is_reported(tmp_path):
    stamps, values = ramp(40)
    write_bag(tmp_path / 'good', stamps, values, metadata={'label': 'x', 'trial': 1})
    bad = write_bag(tmp_path / 'bad', stamps, values, metadata={'label': 'x', 'trial': 2})
    storage = next(bad.glob('*.mcap'))
    storage.write_bytes(storage.read_bytes()[:200])
    data = convert([tmp_path], window=10, hop=10, all_samples=True, **QUIET)
    assert set(data.trial) == {1} and 'cannot read' in data.info['skipped'][0]['reason']


def test_recording_shorter_than_a_window_is_reported(tmp_path):
    stamps, values = ramp(40)
    write_bag(tmp_path / 'long', stamps, values, metadata={'label': 'x', 'trial': 1})
    write_bag(tmp_path / 'short', stamps[:5], values[:5], metadata={'label': 'x', 'trial': 2})
    data = convert([tmp_path], window=10, hop=10, all_samples=True, **QUIET)
    assert 'shorter than one window' in data.info['skipped'][0]['reason']


def test_label_and_trial_options_for_bare_bags(tmp_path):
    stamps, values = ramp(40)
    write_bag(tmp_path / 'a', stamps, values)
    with pytest.raises(DatasetError, match='no label in the recording'):
        convert([tmp_path / 'a'], window=10, hop=10, all_samples=True, **QUIET)
    data = convert([tmp_path / 'a'], window=10, hop=10, label='carpet wool', trial=12,
                   all_samples=True, **QUIET)
    assert data.classes == ['carpet wool'] and set(data.trial) == {12}


def test_part_bags_form_one_recording(tmp_path):
    stamps, values = ramp(60)
    write_bag(tmp_path / 'rec' / 'part_0000', stamps[:30], values[:30],
              metadata={'label': 'x', 'trial': 3})
    write_bag(tmp_path / 'rec' / 'part_0001', stamps[30:], values[30:])
    data = convert([tmp_path / 'rec'], window=60, hop=60, all_samples=True, **QUIET)
    assert len(data.X) == 1 and set(data.trial) == {3}


def test_cli_converts_and_reports(tmp_path, capsys):
    stamps, values = ramp(64)
    write_bag(tmp_path / 'a', stamps, values, metadata={'label': 'wood', 'trial': 1})
    assert main(['convert', str(tmp_path / 'a'), '--out', str(tmp_path / 'd.npz'),
                 '--window', '16', '--all-samples']) == 0
    assert 'wrote' in capsys.readouterr().out
    assert main(['convert', str(tmp_path / 'nothing'), '--out', str(tmp_path / 'e.npz')]) == 1


def test_convert_refuses_an_existing_dataset_unless_forced(tmp_path, capsys):
    stamps, values = ramp(64)
    write_bag(tmp_path / 'a', stamps, values, metadata={'label': 'wood', 'trial': 1})
    command = ['convert', str(tmp_path / 'a'), '--out', str(tmp_path / 'd.npz'), '--window',
               '16', '--all-samples']
    assert main(command) == 0
    before = (tmp_path / 'd.npz').read_bytes()
    capsys.readouterr()
    assert main(command) == 1
    err = capsys.readouterr().err
    assert err.startswith('error: --out') and 'exists; give --force' in err
    assert (tmp_path / 'd.npz').read_bytes() == before
    assert main(command + ['--force']) == 0


def test_two_recordings_with_one_trial_id_are_reported_not_renumbered(tmp_path, capsys):
    stamps, values = ramp(40)
    for name in ('first', 'second'):
        write_bag(tmp_path / 'bags' / name, stamps, values, metadata={'label': 'x', 'trial': 5})
    with pytest.raises(DatasetError, match=r'second \(trial 5, as first\).*--renumber'):
        convert([tmp_path / 'bags'], window=10, hop=10, all_samples=True, **QUIET)
    lines = []
    data = convert([tmp_path / 'bags'], window=10, hop=10, all_samples=True, renumber=True,
                   progress=lines.append)
    assert sorted(set(data.trial.tolist())) == [5, 6]
    assert any("trial 5 is first's; numbered 6" in line for line in lines)
    second = [r for r in data.info['recordings'] if r['path'].endswith('second')]
    assert second[0]['trial'] == 6 and second[0]['renumbered_from'] == 5
    assert main(['convert', str(tmp_path / 'bags'), '--out', str(tmp_path / 'd.npz'),
                 '--window', '10', '--all-samples']) == 1
    assert 'pass --renumber' in capsys.readouterr().err


def texture_estimate(end_ns, windows=2):
    time = T['builtin_interfaces/msg/Time']
    starts = [time(*divmod(int(end_ns - (windows - i) * 10**9), 10**9)) for i in range(windows)]
    ends = [time(*divmod(int(end_ns - (windows - 1 - i) * 10**9), 10**9)) for i in range(windows)]
    return T['tactex_msgs/msg/TextureEstimate'](
        header=T['std_msgs/msg/Header'](stamp=ends[-1], frame_id='sensor_edge'),
        label='wood', class_id=1, confidence=0.75, class_names=['cork', 'wood'],
        probabilities=np.array([0.25, 0.75], dtype=np.float32), decided=False,
        contact_seconds=float(windows), windows_used=windows, window_starts=starts,
        window_ends=ends, model_id='cnn_3@test')


@pytest.mark.parametrize('definitions', ['in the bag', 'none as from ROS 2 Humble'])
def test_bag_with_texture_estimates_converts_without_ros(tmp_path, capsys, definitions):
    stamps, values = ramp(64)
    estimates = [texture_estimate(stamps[i]) for i in (20, 40, 60)]
    bag = tmp_path / 'a'
    if definitions == 'in the bag':
        write_bag(bag, stamps, values, metadata={'label': 'wood', 'trial': 2},
                  estimates=estimates)
    else:
        write_bag(bag, stamps, values, metadata={'label': 'wood', 'trial': 2},
                  estimates=estimates, storage=StoragePlugin.SQLITE3)
        strip_type_definitions(bag)
        with pytest.raises(AnyReaderError, match='no type definitions'), AnyReader([bag]):
            pass  # only the registered tactex_msgs types make this bag readable
    assert main(['convert', str(bag), '--out', str(tmp_path / 'd.npz'), '--window', '16',
                 '--all-samples']) == 0
    assert 'wrote' in capsys.readouterr().out
    data = Dataset.load(tmp_path / 'd.npz')
    assert data.X.shape == (7, 16, 10) and data.classes == ['wood'] and set(data.trial) == {2}
    with AnyReader([bag], default_typestore=typestore()) as reader:
        (connection,) = [c for c in reader.connections if c.topic == '/texture/estimate']
        read = [reader.deserialize(raw, connection.msgtype)
                for _, _, raw in reader.messages(connections=[connection])]
    assert [m.header.stamp for m in read] == [e.header.stamp for e in estimates]
    assert read[0].label == 'wood' and read[0].class_names == ['cork', 'wood']
    np.testing.assert_array_equal(read[0].probabilities, [0.25, 0.75])
    assert read[0].window_ends[-1] == read[0].header.stamp and read[0].windows_used == 2


def test_bad_window_settings_are_refused(tmp_path):
    with pytest.raises(DatasetError, match='window'):
        convert([tmp_path], window=1, hop=1, **QUIET)


# -- labels, duplicates, broken parts: nothing is lost or mislabelled silently ---------

def test_label_option_never_replaces_a_recorded_label(tmp_path):
    stamps, values = ramp(40)
    write_bag(tmp_path / 'a', stamps, values, metadata={'label': 'wood', 'trial': 1})
    write_bag(tmp_path / 'b', stamps, values, metadata={'trial': 2})
    data = convert([tmp_path], window=10, hop=10, label='carpet', all_samples=True, **QUIET)
    assert data.classes == ['carpet', 'wood']
    assert data.classes[data.y[data.trial == 1][0]] == 'wood'


def test_an_unlabelled_recording_is_skipped_and_named_the_rest_converts(tmp_path):
    stamps, values = ramp(40)
    write_bag(tmp_path / 'a', stamps, values, metadata={'label': 'wood', 'trial': 1})
    write_bag(tmp_path / 'b', stamps, values)
    lines = []
    data = convert([tmp_path], window=10, hop=10, all_samples=True, progress=lines.append)
    assert data.classes == ['wood'] and set(data.trial) == {1}
    assert data.info['skipped'][0]['path'].endswith('b')
    assert any('skipped' in line and '--label' in line for line in lines)


def test_a_corrupt_part_is_named_and_the_good_parts_convert(tmp_path):
    stamps, values = ramp(90)
    for index in range(3):
        part = slice(30 * index, 30 * index + 30)
        write_bag(tmp_path / 'rec' / f'part_{index:04d}', stamps[part], values[part],
                  metadata={'label': 'wood', 'trial': 3})
    storage = next((tmp_path / 'rec' / 'part_0001').glob('*.mcap'))
    storage.write_bytes(storage.read_bytes()[:300])
    lines = []
    data = convert([tmp_path / 'rec'], window=10, hop=10, all_samples=True,
                   progress=lines.append)
    np.testing.assert_array_equal(data.X[:, 0, 0], [0, 10, 20, 60, 70, 80])
    assert any('part_0001 skipped' in line for line in lines)
    assert data.info['recordings'][0]['dropped']['unreadable_parts'] == 1


def test_the_same_recording_given_twice_is_converted_once(tmp_path):
    stamps, values = ramp(40)
    write_bag(tmp_path / 'bags' / 'wood_0000', stamps, values,
              metadata={'label': 'wood', 'trial': 1})
    lines = []
    data = convert([tmp_path / 'bags', tmp_path / 'bags' / 'wood_0000',
                    tmp_path / 'bags' / '..' / 'bags' / 'wood_0000'], window=10, hop=10,
                   all_samples=True, progress=lines.append)
    assert len(data.X) == 4 and len(data.info['recordings']) == 1
    assert sum('converted once' in line for line in lines) == 2


@pytest.mark.parametrize('key, value', [('label', 3), ('label', ''), ('trial', 'x'),
                                        ('trial', -2), ('trial', True), ('trial', 1.5)])
def test_metadata_of_the_wrong_type_is_reported_by_bag_and_key(tmp_path, key, value):
    stamps, values = ramp(40)
    write_bag(tmp_path / 'good', stamps, values, metadata={'label': 'wood', 'trial': 1})
    write_bag(tmp_path / 'odd', stamps, values, metadata={'label': 'wood', key: value})
    data = convert([tmp_path], window=10, hop=10, all_samples=True, **QUIET)
    reason = data.info['skipped'][0]['reason']
    assert data.info['skipped'][0]['path'].endswith('odd') and f'"{key}"' in reason


def test_class_names_sort_naturally(tmp_path):
    stamps, values = ramp(20)
    for index, label in enumerate(('mat10', 'mat2', 'Mat1')):
        write_bag(tmp_path / label, stamps, values, metadata={'label': label, 'trial': index})
    data = convert([tmp_path], window=10, hop=10, all_samples=True, **QUIET)
    assert data.classes == ['Mat1', 'mat2', 'mat10']


# -- ground truth: only sliding contact over the labelled texture is labelled -----------

def truth(count, *, contact=(0, None), texture=('wood', 0, None), moving=(0, None),
          speed_m_s=0.015, period_s=8_333_333e-9):
    """Ground truth per sample: touching, texture under the edge, edge positions."""
    index = np.arange(count)

    def within(span):
        return (index >= span[0]) & (index < (count if span[1] is None else span[1]))

    name, *span = texture
    names = np.where(within(span), name, '')
    step = np.where(within(moving), speed_m_s * period_s, 0.0)
    edge = np.zeros((count, 3))
    edge[:, 0] = np.cumsum(step)
    return {'contact': within(contact), 'texture': list(names), 'edge_m': edge}


def test_ground_truth_keeps_only_sliding_contact_over_the_labelled_texture(tmp_path):
    stamps, values = ramp(120)
    write_bag(tmp_path / 'a', stamps, values, metadata={'label': 'wood', 'trial': 1},
              active=[(stamps[0], stamps[-1])],
              truth=truth(120, contact=(20, 100), texture=('wood', 30, None), moving=(0, 80)))
    data = convert([tmp_path / 'a'], window=10, hop=10, **QUIET)
    # touching from 20, over wood from 30, moving until 80 (less the speed span's half)
    assert data.X[0, 0, 0] >= 30 and data.X[-1, -1, 0] < 80
    assert len(data.X) >= 4


@pytest.mark.parametrize('case', ['standing still', 'never touching', 'off the patch',
                                  'another texture'])
def test_scenes_that_never_slide_over_the_texture_give_no_window(tmp_path, case):
    stamps, values = ramp(120)
    ground = {'standing still': truth(120, moving=(0, 0)),
              'never touching': truth(120, contact=(0, 0)),
              'off the patch': truth(120, texture=('', 0, None)),
              'another texture': truth(120, texture=('cork', 0, None))}[case]
    write_bag(tmp_path / 'a', stamps, values, metadata={'label': 'wood', 'trial': 1},
              active=[(stamps[0], stamps[-1])], truth=ground)
    write_bag(tmp_path / 'b', stamps, values, metadata={'label': 'wood', 'trial': 2},
              active=[(stamps[0], stamps[-1])], truth=truth(120))
    data = convert([tmp_path], window=10, hop=10, **QUIET)
    assert set(data.trial) == {2}
    assert data.info['skipped'][0]['reason'].startswith('0 samples slid in contact')


# -- topics: namespaces, remaps, no leading slash, no magnetometer -----------------------

@pytest.mark.parametrize('namespace', ['/left_arm/', 'left_arm/', ''])
def test_topics_are_found_under_a_namespace_and_without_the_leading_slash(tmp_path, namespace):
    stamps, values = ramp(40)
    write_bag(tmp_path / 'a', stamps, values, metadata={'label': 'wood'}, namespace=namespace)
    data = convert([tmp_path / 'a'], window=10, hop=10, all_samples=True, **QUIET)
    assert len(data.X) == 4 and data.channels == list(CHANNELS)


def test_two_namespaces_ask_for_a_remap_which_then_works(tmp_path):
    stamps, values = ramp(40)
    names = {'imu': '/right_arm/tactile/imu/data_raw'}
    write_bag(tmp_path / 'a', stamps, values, metadata={'label': 'wood'},
              namespace='/left_arm/', names={'mag': '/left_arm/tactile/imu/mag'})
    with pytest.raises(DatasetError, match='no windows'):
        convert([tmp_path / 'a'], window=10, hop=10, all_samples=True, **QUIET,
                remaps={'imu': '/nothing/here'})
    write_bag(tmp_path / 'b', stamps, values, metadata={'label': 'wood'}, names=names)
    data = convert([tmp_path / 'b'], window=10, hop=10, all_samples=True, **QUIET,
                   remaps=parse_topic_remaps(['imu=right_arm/tactile/imu/data_raw']))
    assert len(data.X) == 4


def test_a_topic_named_with_topic_that_a_recording_lacks_is_refused_not_dropped(tmp_path):
    stamps, values = ramp(40)
    write_bag(tmp_path / 'a', stamps, values, metadata={'label': 'wood'})
    with pytest.raises(DatasetError, match=r'--topic pressure=/nonexist: 1 recording\(s\) '
                                           r'have no such topic \(a\); check its name'):
        convert([tmp_path / 'a'], window=10, hop=10, all_samples=True, **QUIET,
                remaps={'pressure': '/nonexist'})


def test_ambiguous_namespaces_are_refused_with_the_fix():
    available = {'/left/tactile/imu/data_raw': 'sensor_msgs/msg/Imu',
                 '/right/tactile/imu/data_raw': 'sensor_msgs/msg/Imu'}
    with pytest.raises(BagError, match='several namespaces.*--topic imu=NAME'):
        resolve_topics(available)
    found = resolve_topics(available, {'imu': '/right/tactile/imu/data_raw'})
    assert found['imu'] == '/right/tactile/imu/data_raw'
    with pytest.raises(BagError, match='is sensor_msgs/msg/Imu, expected'):
        resolve_topics(available, {'imu': '/left/tactile/imu/data_raw',
                                   'mag': '/right/tactile/imu/data_raw'})


def test_a_bag_without_magnetometer_converts_without_mag_channels(tmp_path):
    stamps, values = ramp(40)
    values[:, 6:9] = np.nan  # would drop every sample if joined
    write_bag(tmp_path / 'a', stamps, values, metadata={'label': 'wood'}, mag_stamps_ns=[])
    lines = []
    data = convert([tmp_path / 'a'], window=10, hop=10, all_samples=True,
                   progress=lines.append)
    assert data.channels == ['ax', 'ay', 'az', 'gx', 'gy', 'gz', 'baro']
    assert data.X.shape == (4, 10, 7)
    assert any('no mag topic' in line and 'mx, my, mz' in line for line in lines)
    with pytest.raises(DatasetError, match='no tactile/imu/mag topic'):
        convert([tmp_path / 'a'], window=10, hop=10, all_samples=True, channels=CHANNELS,
                **QUIET)
    chosen = convert([tmp_path / 'a'], window=10, hop=10, all_samples=True,
                     channels=['az', 'baro'], **QUIET)
    assert chosen.channels == ['az', 'baro'] and chosen.X.shape == (4, 10, 2)


def test_alignment_is_channel_agnostic_and_counts_what_it_drops():
    stamps = np.arange(10, dtype=np.int64) * 1000
    reference = Stream('a', ('x',), stamps[::-1], np.arange(10.0)[::-1, None])
    other = Stream('b', ('p', 'q'), stamps[:8] + 100, np.ones((8, 2)))
    aligned = align(reference, [other])
    assert aligned.channels == ('x', 'p', 'q') and len(aligned.values) == 8
    assert aligned.dropped['unaligned_samples'] == 2 and aligned.reordered['a'] == 9
    np.testing.assert_array_equal(aligned.stamps_ns, stamps[:8])


def test_a_role_left_out_names_the_topics_of_its_type_another_name_could_be(tmp_path):
    stamps, values = ramp(40)
    write_bag(tmp_path / 'a', stamps, values, metadata={'label': 'wood'},
              names={'mag': '/imu/mag', 'pressure': '/baro'})
    lines = []
    data = convert([tmp_path / 'a'], window=10, hop=10, all_samples=True,
                   progress=lines.append)
    assert data.channels == ['ax', 'ay', 'az', 'gx', 'gy', 'gz']
    assert any('no mag topic' in line and 'sensor_msgs/msg/MagneticField on /imu/mag' in line
               and 'use --topic mag=/imu/mag' in line for line in lines)
    assert any('use --topic pressure=/baro' in line for line in lines)
