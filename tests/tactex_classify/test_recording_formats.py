# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Every common recording format reads, to the same windows; what cannot be read says why.

Formats: rosbag2 folders (MCAP, sqlite3, zstd by file or by message), a folder that lost
its metadata.yaml, ROS 1 bags (plain, bz2, lz4), a lone .mcap or .db3 file, and a folder
mixing them. Topics of other names are found by type and offered, never taken silently.
"""

import shutil

import numpy as np
import pytest
from rosbags.rosbag2 import StoragePlugin
from support.bagfactory import ramp, write_bag
from support.foreign_bags import bare, converted, custom_type_bag, imu_only, lying_files, zeros_bag

from tactex_classify.data import inflation
from tactex_classify.data.bags import read_recording
from tactex_classify.data.dataset import convert
from tactex_classify.data.sources import open_part, read_messages, UnreadablePart
from tactex_classify.errors import BagError

QUIET = {'progress': lambda line: None}


@pytest.fixture(scope='module')
def original(tmp_path_factory):
    """A labelled recording with sweep segments, as the recorder writes it (rosbag2 MCAP)."""
    stamps, values = ramp(300)
    folder = tmp_path_factory.mktemp('formats') / 'rec'
    return write_bag(folder, stamps, values, metadata={'label': 'wood', 'trial': 4},
                     active=[(stamps[20], stamps[140]), (stamps[170], stamps[290])])


def windows(path):
    data = convert([path], window=16, hop=8, **QUIET)
    return data.X, data.y, data.trial, data.classes


FORMATS = {
    'rosbag2 sqlite3 folder': lambda src, tmp: write_bag(
        tmp / 'sqlite', *ramp(300), metadata={'label': 'wood', 'trial': 4},
        active=[(ramp(300)[0][20], ramp(300)[0][140]), (ramp(300)[0][170], ramp(300)[0][290])],
        storage=StoragePlugin.SQLITE3),
    'ROS 1 bag': lambda src, tmp: converted(src, tmp / 'rec.bag'),
    'ROS 1 bag, bz2 chunks': lambda src, tmp: converted(src, tmp / 'rec.bag', compress='bz2'),
    'ROS 1 bag, lz4 chunks': lambda src, tmp: converted(src, tmp / 'rec.bag', compress='lz4'),
    'bare .mcap': lambda src, tmp: bare(src, tmp / 'exported.mcap'),
    'folder without metadata.yaml': lambda src, tmp: bare(src, tmp / 'lost' / 'lost.mcap').parent,
    'zstd, file mode': lambda src, tmp: converted(src, tmp / 'zf', compress='zstd'),
    'zstd, message mode': lambda src, tmp: converted(src, tmp / 'zm', compress='zstd',
                                                     mode='message'),
}


@pytest.mark.parametrize('name', FORMATS)
def test_the_same_recording_converts_to_identical_windows_in_every_format(name, original,
                                                                          tmp_path):
    expected = windows(original)
    path = FORMATS[name](original, tmp_path)
    got = windows(path)
    assert len(expected[0]) > 10
    for mine, theirs in zip(got, expected, strict=True):
        np.testing.assert_array_equal(mine, theirs)


def test_a_lone_db3_file_reads_as_it_is(tmp_path):
    stamps, values = ramp(50)
    folder = write_bag(tmp_path / 'db', stamps, values, metadata={'label': 'x', 'trial': 1},
                       storage=StoragePlugin.SQLITE3)
    lone = bare(folder, tmp_path / 'lone.db3', '.db3')
    recording = read_recording(lone)
    np.testing.assert_array_equal(recording.values, read_recording(folder).values)
    assert recording.metadata['label'] == 'x'


def test_a_folder_mixing_every_format_gives_one_recording_per_item(original, tmp_path):
    mixed = tmp_path / 'mixed'
    mixed.mkdir()
    shutil.copytree(original, mixed / 'rosbag2')
    converted(original, mixed / 'old.bag')
    bare(original, mixed / 'exported.mcap')
    lines = []
    data = convert([mixed], window=16, hop=8, renumber=True, progress=lines.append)
    assert len(data.info['recordings']) == 3 and not data.info['skipped']
    assert len(data.X) == 3 * len(windows(original)[0])


def test_header_stamps_of_zero_fall_back_to_the_log_time_with_a_note(tmp_path):
    log = 10**12 + np.arange(100) * 10_000_000
    for ros1, path in ((True, tmp_path / 'zero.bag'), (False, tmp_path / 'zero')):
        recording = read_recording(imu_only(path, np.zeros(100), log, ros1=ros1))
        np.testing.assert_array_equal(recording.stamps_ns, log)
        assert any('header stamp 0' in note and '100 message' in note
                   for note in recording.notes)
        assert recording.rate_hz == pytest.approx(100.0)


def test_an_mcap_message_logged_past_int64_nanoseconds_is_called_damaged(tmp_path):
    from tactex_classify.data.bag_info import describe  # (MCAP's log time is uint64)
    path = imu_only(tmp_path / 'a.mcap', [10**12 + i for i in range(3)],
                    [2**64 - 3 + i for i in range(3)])
    for read in (read_recording, describe):
        with pytest.raises(BagError, match='past int64 nanoseconds .* damaged'):
            read(path)


def test_an_imu_under_another_name_is_offered_with_count_and_rate_never_taken(tmp_path):
    log = 10**12 + np.arange(300) * 33_333_333
    path = imu_only(tmp_path / 'other.bag', log, log, topics=('/imu/data',), ros1=True)
    with pytest.raises(BagError, match=r'no tactile/imu/data_raw; sensor_msgs/msg/Imu on '
                       r'/imu/data \(300 messages, 30\.0 Hz\): use --topic imu=/imu/data'):
        read_recording(path)
    recording = read_recording(path, remaps={'imu': '/imu/data'})
    assert recording.rate_hz == pytest.approx(30.0) and recording.values.shape == (300, 6)


def test_two_imu_topics_of_other_names_are_both_offered(tmp_path):
    log = 10**12 + np.arange(50) * 10_000_000
    path = imu_only(tmp_path / 'two', log, log, topics=('/imu/data', '/camera/imu'))
    with pytest.raises(BagError, match='on /camera/imu .*: use --topic imu=/camera/imu; '
                       'sensor_msgs/msg/Imu on /imu/data .*: use --topic imu=/imu/data'):
        read_recording(path)


def test_a_custom_message_type_is_named_with_its_fields(tmp_path):
    with pytest.raises(BagError, match=r'no topic of type sensor_msgs/msg/Imu; the recording '
                       r'holds /tactile/raw \(lab_msgs/msg/Tactile; fields ax, ay, az, p\)'):
        read_recording(custom_type_bag(tmp_path / 'lab.bag'))


def test_a_ros1_bag_opened_for_some_topics_indexes_only_their_chunks_and_counts_all(tmp_path):
    from rosbags.rosbag1 import Writer as Ros1Writer
    from rosbags.typesys import get_typestore, Stores
    store = get_typestore(Stores.ROS1_NOETIC)
    text = store.serialize_ros1(store.types['std_msgs/msg/String'](data='x' * 50),
                                'std_msgs/msg/String')
    path = tmp_path / 'two.bag'
    with Ros1Writer(path) as writer:
        writer.chunk_threshold = 2048  # many chunks; /b's messages in the first only
        a, b = (writer.add_connection(topic, 'std_msgs/msg/String', typestore=store)
                for topic in ('/a', '/b'))
        for i in range(2000):
            writer.write(a, 10**12 + i * 10**7, text)
            if i < 10:
                writer.write(b, 10**12 + i * 10**7, text)
    with open_part(path) as reader:
        span = (reader.start_time, reader.end_time)
    with open_part(path, readable=lambda connection: connection.topic == '/b') as reader:
        assert {c.topic: c.msgcount for c in reader.connections} == {'/a': 2000, '/b': 10}
        assert (reader.start_time, reader.end_time) == span
        assert sum(map(len, reader.readers[0].indexes.values())) < 100  # of 2010 entries
        wanted = [c for c in reader.connections if c.topic == '/b']
        assert len(list(read_messages(reader, path, wanted))) == 10
        with pytest.raises(UnreadablePart, match='/a not opened for reading'):
            list(read_messages(reader, path, reader.connections))


LYING = {
    'truncated': 'truncated or unindexed ROS 1 bag .*rosbag reindex',
    'active': r'unindexed ROS 1 bag \(still .active.*rosbag reindex',
    'empty': 'empty file',
    'text': r'not a ROS 1 bag \(it does not start with "#ROSBAG V2.0"\)',
    'fifo': r'FIFO \(named pipe\), not a regular file',
    'huge': 'truncated or unindexed ROS 1 bag',
    'foxglove': r'MCAP file of profile \(none\) holding json messages, not ROS 2',
}


@pytest.fixture(scope='module')
def lying(original, tmp_path_factory):
    folder = tmp_path_factory.mktemp('lying')
    return lying_files(folder, converted(original, folder / 'good.bag'))


@pytest.mark.parametrize('kind', LYING)
def test_a_file_no_reader_can_read_gets_one_reason_naming_it(kind, lying):
    with pytest.raises(BagError, match=LYING[kind]) as raised:
        read_recording(lying[kind])
    assert str(lying[kind]) in str(raised.value)



def test_random_bytes_named_bag_are_called_no_ros1_bag(tmp_path):
    (tmp_path / 'random.bag').write_bytes(bytes([0x00, 0xc7, 0x28]) * 300)
    with pytest.raises(BagError, match='not a ROS 1 bag'):
        read_recording(tmp_path / 'random.bag')


def test_an_mcap_cut_inside_its_first_record_is_called_truncated(tmp_path):
    (tmp_path / 'stub.mcap').write_bytes(b'\x89MCAP0\r\n\x01\x1a' + bytes(10))
    with pytest.raises(BagError, match=r'stub.mcap: cannot read: a truncated or damaged MCAP '
                                       r'file \(a record runs past the end of the file\)'):
        read_recording(tmp_path / 'stub.mcap')


METADATA_LIES = {
    'empty': ('', 'its metadata.yaml is empty or not a rosbag2 description'),
    'not_yaml': ('rosbag2_bagfile_information: [unclosed\n: :\n',
                 r'metadata.yaml cannot be read as plain YAML \(line \d\)'),
    'missing_file': (None, r"lists files the folder lacks \('missing_file/other.mcap'\)"),
    'wrong_storage': (None, 'names sqlite3 storage, the folder holds .mcap, .yaml: correct '
                            'storage_identifier'),
}


@pytest.mark.parametrize('lie', METADATA_LIES)
def test_a_metadata_yaml_that_lies_is_named_with_the_way_out(lie, original, tmp_path):
    folder = shutil.copytree(original, tmp_path / lie)
    text, match = METADATA_LIES[lie]
    metadata = folder / 'metadata.yaml'
    if lie == 'missing_file':
        text = metadata.read_text().replace('rec.mcap', 'other.mcap')
    elif lie == 'wrong_storage':
        text = metadata.read_text().replace('storage_identifier: mcap',
                                            'storage_identifier: sqlite3')
    metadata.write_text(text)
    with pytest.raises(BagError, match=match) as raised:
        read_recording(folder)
    assert 'delete metadata.yaml' in str(raised.value) and '\n' not in str(raised.value)

def test_bag_info_shows_the_file_s_counts_and_span_where_the_metadata_lies(original,
                                                                          tmp_path):
    from tactex_classify.data.bag_info import describe
    folder = shutil.copytree(original, tmp_path / 'lying_counts')
    metadata = folder / 'metadata.yaml'
    truth = describe(original)
    text = metadata.read_text().replace('message_count: 300', 'message_count: 7').replace(
        'nanoseconds: ', 'nanoseconds: 1')
    ghost = ('  - message_count: 50\n    topic_metadata:\n      name: /tactile/temperature\n'
             '      offered_qos_profiles: []\n      serialization_format: cdr\n'
             '      type: sensor_msgs/msg/Temperature\n')  # listed, never in the file
    at = text.index('  topics_with_message_count:\n') + len('  topics_with_message_count:\n')
    metadata.write_text(text[:at] + ghost + text[at:])
    info = describe(folder)
    assert [t.count for t in info.topics if t.count] == [t.count for t in truth.topics]
    assert (info.start_ns, info.end_ns, info.messages) == (truth.start_ns, truth.end_ns,
                                                           truth.messages)
    assert any('the metadata lists 7 message(s), the file holds 300' in note
               for note in info.notes)
    assert any(note.startswith('/tactile/temperature: the metadata lists 50 message(s), the '
                               'file holds 0') for note in info.notes)


@pytest.mark.parametrize('compression', ['bz2', 'lz4', 'zstd'])
def test_a_block_that_inflates_without_bound_is_refused(compression, tmp_path, monkeypatch):
    monkeypatch.setattr(inflation, 'MIN_LIMIT_BYTES', 1024**2)
    path = zeros_bag(tmp_path / ('bomb' + ('' if compression == 'zstd' else '.bag')),
                     16 * 1024**2, compression)
    assert sum(f.stat().st_size for f in [path, *path.glob('*')] if f.is_file()) < 1024**2
    with pytest.raises(inflation.InflationError, match=f'a {compression}-compressed block '
                       'inflates past'), open_part(path) as reader:
        for _ in reader.messages():
            pass


def test_inflation_within_the_limit_is_untouched():
    import bz2
    data = bytes(range(256)) * 1000
    assert inflation._bz2(bz2.compress(data) + bz2.compress(data)) == data + data


def test_a_part_surveyed_again_is_not_reopened_until_its_files_change(original, tmp_path,
                                                                      monkeypatch):
    from tactex_classify.data import topic_inventory
    folder = shutil.copytree(original, tmp_path / 'surveyed')
    opened = []
    real_open = topic_inventory.open_part
    monkeypatch.setattr(topic_inventory, 'open_part',
                        lambda part, **kw: opened.append(part) or real_open(part, **kw))
    first = topic_inventory.survey(folder)
    first.counts.clear()  # a caller's change stays its own
    again = topic_inventory.survey(folder)
    assert len(opened) == 1 and again.counts and again.types == first.types
    metadata = folder / 'metadata.yaml'
    metadata.write_text(metadata.read_text() + '\n')  # another size: surveyed anew
    topic_inventory.survey(folder)
    assert len(opened) == 2
