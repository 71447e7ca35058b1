# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Bad inputs for every `tactex` subcommand, and the scratch folder they run against.

A case is argv (with `{w}` for the scratch folder), a regex the single `error:` line
must match (it names the argument and the fix) and the path given as output, the one
place a failing command may leave something. `make_workspace` builds the folder: text,
binary and empty files, datasets good and bad, bags, CSV and MUN trees, scenes.
"""

import json
import os
from pathlib import Path
import pickle
import shutil

import numpy as np

from support.bagfactory import ramp, write_bag
from support.foreign_bags import converted, custom_type_bag, imu_only, lying_files
from tactex_classify.data.dataset import Dataset
from tactex_classify.evaluation.model_grid import GridSettings, GridStore
from tactex_classify.models.baselines import MiniRocketRidge


class Case:
    """One bad invocation and what its error line must say."""

    def __init__(self, argv: str, match: str, out: str | None = None, *,
                 needs_non_root: bool = False) -> None:
        self.argv = argv.split()
        self.match = match
        self.out = out
        self.needs_non_root = needs_non_root

    def resolved(self, workspace: Path) -> list[str]:
        """Argv with the scratch folder filled in."""
        return [part.replace('{w}', str(workspace)) for part in self.argv]

    def __repr__(self) -> str:
        return ' '.join(self.argv)


# Files in {w}/foreign (see make_foreign_recordings) and what their error says.
FOREIGN = {
    'truncated.bag': 'truncated or unindexed ROS 1 bag .*rosbag reindex',
    'unclosed.bag.active': r'unindexed ROS 1 bag \(still .active',
    'empty.bag': 'empty file',
    'text.bag': 'not a ROS 1 bag',
    'fifo.bag': r'FIFO \(named pipe\), not a regular file',
    'huge.bag': 'truncated or unindexed ROS 1 bag',
    'foxglove.mcap': 'holding json messages, not ROS 2',
    'lab.bag': r'lab_msgs/msg/Tactile; fields ax, ay, az, p',
    'other_imu.bag': r'sensor_msgs/msg/Imu on /imu/data \(90 messages, 30.0 Hz\): use --topic '
                     'imu=/imu/data',
}


MOVE = ('{{name: {name}, speed: {speed}, press_depth: {press}, edge_tilt: 0.5, '
        'direction: {direction}, contact_length: {length}}}')
# Movement files (in {w}/movements) that `--movements` must refuse, with their error.
MOVEMENT_FILES = {
    'empty.yaml': '',
    'fast.yaml': 'movements:\n  - ' + MOVE.format(name='dash', speed=0.2, press=0.002,
                                                  direction='forward', length=0.05),
    'shallow.yaml': 'movements:\n  - ' + MOVE.format(name='skim', speed=0.02, press=0.0005,
                                                     direction='forward', length=0.05),
    'short.yaml': 'movements:\n  - ' + MOVE.format(name='tap', speed=0.04, press=0.002,
                                                   direction='forward', length=0.02),
    'sideways.yaml': 'movements:\n  - ' + MOVE.format(name='side', speed=0.02, press=0.002,
                                                      direction='sideways', length=0.05),
    'long.yaml': 'movements:\n  - ' + MOVE.format(name='far', speed=0.02, press=0.002,
                                                  direction='forward', length=0.5),
    'typo.yaml': 'movements:\n  - {name: a, sped: 0.02}\n',
    'laughs.yaml': 'movements: [&a0 [x, x, x, x, x, x, x, x, x, x], '
                   '&a1 [*a0, *a0, *a0, *a0, *a0, *a0, *a0, *a0, *a0, *a0]]\n',
    'twice.yaml': 'window: 128\nwindow: 64\nmovements:\n  - ' + MOVE.format(
        name='dash', speed=0.02, press=0.002, direction='forward', length=0.05) + '\n',
    'unclosed.yaml': 'movements:\n  - {name: a, speed: 0.02\n',
}

STANDING_SCENE = """name = "standing"
seed = 1
effects = ["contact", "compliance", "texture"]
[surface]
kind = "flat"
[[patches]]
texture = "wood"
x_m = [0.07, 0.33]
y_m = [-0.08, 0.08]
[sweep]
speed_m_s = 0.0
"""


def toy_dataset(classes: int, recordings: int = 2) -> Dataset:
    rng = np.random.default_rng(0)
    count = classes * recordings * 3
    return Dataset(rng.normal(size=(count, 32, 10)).astype(np.float32),
                   np.repeat(np.arange(classes), recordings * 3),
                   np.repeat(np.arange(classes * recordings), 3), np.zeros(count),
                   [f'class{i}' for i in range(classes)], {'sampling_rate_hz': 100.0, 'hop': 16})


class Boom:
    """Runs a shell command when unpickled."""

    def __reduce__(self):
        import os
        return (os.system, ('echo pwned > /tmp/tactex_pwned',))


def make_mun_with_text(root: Path) -> None:
    """A MUN trial whose IMU columns hold text."""
    import pandas

    from tactex_classify.data.importers import MUN_IMU_COLUMNS
    folder = root / 'pickles_30' / 'texture_01'
    frames = {'full_imu': pandas.DataFrame({c: ['oops'] * 4 for c in MUN_IMU_COLUMNS}),
              'full_baro': pandas.DataFrame({'baro': [1000.0] * 4})}
    for part, frame in frames.items():
        (folder / part).mkdir(parents=True)
        (folder / part / 't.pkl').write_bytes(pickle.dumps(frame))


def make_workspace(w: Path) -> Path:
    """Build the scratch folder the cases refer to."""
    (w / 'text.txt').write_text('hello\n')
    (w / 'binary.bin').write_bytes(bytes(range(256)) * 4)
    (w / 'folder').mkdir()
    (w / 'full').mkdir()
    (w / 'full' / 'keep.txt').write_text('keep')
    toy_dataset(3).save(w / 'data.npz')
    toy_dataset(1).save(w / 'one_class.npz')
    (w / 'garbage.npz').write_bytes(b'PK\x03\x04' + bytes(200))
    (w / 'garbage.json').write_text(json.dumps({'classes': ['a'], 'channels': ['x']}))
    (w / 'pickled.npz').write_bytes(pickle.dumps({'X': [1.0]}))
    (w / 'pickled.json').write_text(json.dumps({'classes': ['a'], 'channels': ['x']}))
    # 10**400: JSON reads any whole number as an int, this one past the float range
    for name, info in (('bad_rate', {'sampling_rate_hz': -5.0}), ('wrong_window', {'window': 64}),
                       ('huge_rate', {'sampling_rate_hz': 10**400}),
                       ('fast_rate', {'sampling_rate_hz': 1e9})):
        toy = toy_dataset(3)
        toy.info.update(info)
        toy.save(w / f'{name}.npz')
    toy = toy_dataset(3)
    np.savez(w / 'bad_labels.npz', X=toy.X, y=toy.y + 5, trial=toy.trial, t0=toy.t0)
    (w / 'bad_labels.json').write_text(json.dumps({'classes': toy.classes,
                                                   'channels': toy.channels}))
    holes = toy_dataset(3)
    holes.X[4, 0, 0] = np.inf
    holes.save(w / 'non_finite.npz')
    (w / 'exists.png').write_bytes(b'a picture kept')
    (w / 'exists.onnx').write_bytes(b'a model kept')
    (w / 'predict_report').mkdir()
    for name in ('recordings.csv', 'windows.csv', 'summary.json'):
        (w / 'predict_report' / name).write_text('{}' if name.endswith('json') else 'a,b\n')
    stamps, values = ramp(64)
    write_bag(w / 'bags' / 'wood_0000', stamps, values, metadata={'label': 'wood', 'trial': 0})
    write_bag(w / 'bags' / 'wood_0001', stamps, values, metadata={'label': 'wood', 'trial': 1})
    write_bag(w / 'mixed_rates' / 'wood_0000', stamps, values,
              metadata={'label': 'wood', 'trial': 0})
    write_bag(w / 'mixed_rates' / 'slow_0000', *ramp(64, period_ns=33_333_333),
              metadata={'label': 'wood', 'trial': 1})
    write_bag(w / 'unlabelled' / 'rec', stamps, values)
    write_bag(w / 'odd_meta' / 'rec', stamps, values, metadata={'label': 7})
    for name, content in (('good', 'pdc,pac\n' + '1,2\n' * 40), ('ragged', 'pdc,pac\n1,2\n3\n'),
                          ('bincsv', '\x00\x01\x02'),
                          ('epoch_ns', 'time,pdc\n' + ''.join(f'{17 * 10**17 + i},1\n'
                                                               for i in range(40)))):
        (w / name / 'wood').mkdir(parents=True)
        (w / name / 'wood' / 'a.csv').write_text(content)
    for label, rows in (('cork', 40), ('wood', 10)):  # wood gives no window of 20
        (w / 'uneven' / label).mkdir(parents=True)
        (w / 'uneven' / label / 'a.csv').write_text('pdc\n' + '1\n' * rows)
    make_mun_with_text(w / 'mun_text')
    mun = w / 'mun' / 'pickles_30' / 'texture_01'
    for part in ('full_imu', 'full_baro'):
        (mun / part).mkdir(parents=True)
        (mun / part / 't.pkl').write_bytes(pickle.dumps(Boom()))
    (w / 'scenes').mkdir()
    (w / 'scenes' / 'standing.toml').write_text(STANDING_SCENE)
    (w / 'scenes' / 'binary.toml').write_bytes(b'\xff\xfe\x00name')
    (w / 'broken.launch.py').write_text('LAUNCH = (\n')
    (w / 'movements').mkdir()
    for name, text in MOVEMENT_FILES.items():
        (w / 'movements' / name).write_text(text)
    dataset = Dataset.load(w / 'data.npz')
    GridStore(w / 'grid').open(GridSettings(folds=2, epochs=3), {32: dataset}, {32: 'data'})
    (w / 'readonly').mkdir()
    (w / 'readonly').chmod(0o555)
    data = toy_dataset(3)
    MiniRocketRidge(dilations=2).fit(data.X, data.y, data.classes).save(
        w / 'minirocket', hop=16, sampling_rate_hz=100.0)
    shutil.copytree(w / 'minirocket', w / 'trained' / 'model')  # a run folder
    Dataset(data.X[:, :16], data.y, data.trial, data.t0, data.classes, data.info).save(
        w / 'window16.npz')
    other = toy_dataset(2)  # other recordings, at another window
    Dataset(other.X[:, :16], other.y, other.trial, other.t0, ['cork', 'felt'], other.info
            ).save(w / 'other16.npz')
    (w / 'corrupt_checkpoint').mkdir()
    (w / 'corrupt_checkpoint' / 'checkpoint.json').write_bytes(b'\xff\xfe\x00garbage')
    make_lying_files(w)
    make_foreign_recordings(w)
    return w


def make_foreign_recordings(w: Path) -> None:
    """Recordings made elsewhere that tactex cannot use as they are, in {w}/foreign."""
    good = converted(w / 'bags' / 'wood_0000', w / 'ros1' / 'wood.bag')
    lying_files(w / 'foreign', good)
    custom_type_bag(w / 'foreign' / 'lab.bag')
    log = 10**12 + np.arange(90) * 33_333_333
    imu_only(w / 'foreign' / 'other_imu.bag', log, log, topics=('/imu/data',), ros1=True)


def make_lying_files(w: Path) -> None:
    """Special files where files are expected, links as outputs, files that lie."""
    for name in ('fifo.npz', 'fifo.toml', 'fifo.urdf', 'fifo.csv'):
        os.mkfifo(w / name)  # opening one for reading would wait for a writer
    shutil.copy(w / 'data.json', w / 'fifo.json')
    shutil.copy(w / 'data.npz', w / 'fifo_sidecar.npz')
    os.mkfifo(w / 'fifo_sidecar.json')
    (w / 'fifocsv' / 'wood').mkdir(parents=True)
    os.mkfifo(w / 'fifocsv' / 'wood' / 'a.csv')
    shutil.copytree(w / 'bags' / 'wood_0000', w / 'fifobag' / 'wood_0000')
    (w / 'fifobag' / 'wood_0000' / 'wood_0000.mcap').unlink()
    os.mkfifo(w / 'fifobag' / 'wood_0000' / 'wood_0000.mcap')
    shutil.copytree(w / 'minirocket', w / 'fifo_checkpoint')
    (w / 'fifo_checkpoint' / 'weights.npz').unlink()
    os.mkfifo(w / 'fifo_checkpoint' / 'weights.npz')
    shutil.copytree(w / 'minirocket', w / 'swapped_checkpoint')
    meta = json.loads((w / 'minirocket' / 'checkpoint.json').read_text())
    meta['classes'][:2] = meta['classes'][1::-1]
    (w / 'swapped_checkpoint' / 'checkpoint.json').write_text(json.dumps(meta))
    shutil.copytree(w / 'minirocket', w / 'nested_checkpoint')
    (w / 'nested_checkpoint' / 'checkpoint.json').write_text('[' * 100_000 + ']' * 100_000)
    (w / 'lying_run').mkdir()
    (w / 'lying_run' / 'metrics.json').write_text(json.dumps({'schemes': {'grouped': 3}}))
    (w / 'garbage_run').mkdir()
    (w / 'garbage_run' / 'metrics.json').write_bytes(b'\xff\xfe\x00garbage')
    (w / 'link').symlink_to(w / 'folder')
    (w / 'dangling.onnx').symlink_to(w / 'nowhere.onnx')
    scene = STANDING_SCENE.replace('speed_m_s = 0.0', 'speed_m_s = 0.015')
    (w / 'scenes' / 'huge_cells.toml').write_text(
        scene.replace('kind = "flat"', 'kind = "flat"\ncells = [100000, 100000]'))
    (w / 'scenes' / 'long_contact.toml').write_text(scene + 'contact_s = 1e7\n')


OUT_NPZ = '{w}/o.npz'
BAD_INPUTS = {
    'tactex': [
        Case('', 'the following arguments are required: COMMAND'),
        Case('nope', "argument COMMAND: invalid choice: 'nope'"),
    ],
    'convert': [
        Case('convert {w}/bags --out=', 'argument --out: must not be empty: give the path'),
        Case('convert {w}/bags', 'the following arguments are required: --out'),
        Case('convert {w}/nothing --out {w}/o.npz', 'BAG_OR_DIR .*nothing does not exist',
             OUT_NPZ),
        Case('convert {w}/text.txt --out {w}/o.npz', r'BAG_OR_DIR .*text.txt is no recording',
             OUT_NPZ),
        Case('convert {w}/folder --out {w}/o.npz', 'no recordings found', OUT_NPZ),
        Case('convert {w}/bags --out {w}/folder', '--out .*folder is a folder; give a file path',
             '{w}/folder'),
        Case('convert {w}/bags --out {w}/text.txt/o.npz', '--out .*text.txt is a file, not a '
             'folder', '{w}/text.txt/o.npz'),
        Case('convert {w}/bags --out {w}/o.csv', '--out .*must end in .npz', '{w}/o.csv'),
        Case('convert {w}/bags --out {w}/readonly/o.npz', '--out .*is not writable',
             '{w}/readonly/o.npz', needs_non_root=True),
        Case('convert {w}/bags --out {w}/o.npz --window 0', 'argument --window: must be a '
             'whole number in 2..65536', OUT_NPZ),
        Case('convert {w}/bags --out {w}/o.npz --window ten', 'argument --window: must be a '
             "whole number in 2..65536, got 'ten'", OUT_NPZ),
        Case('convert {w}/bags --out {w}/o.npz --hop 0', 'argument --hop', OUT_NPZ),
        Case('convert {w}/bags --out {w}/o.npz --window 10 --hop 20', '--hop 20 is longer than '
             '--window 10', OUT_NPZ),
        Case('convert {w}/bags --out {w}/o.npz --trial -1', 'argument --trial', OUT_NPZ),
        Case('convert {w}/bags --out {w}/o.npz --trial 3', '--trial names one recording',
             OUT_NPZ),
        Case('convert {w}/bags --out {w}/o.npz --channels ax,nope', r"--channels .*\['nope'\]",
             OUT_NPZ),
        Case('convert {w}/bags --out {w}/o.npz --topic imu', "--topic 'imu' is not ROLE=TOPIC",
             OUT_NPZ),
        Case('convert {w}/bags --out {w}/o.npz --topic wheel=/x', "unknown role 'wheel'",
             OUT_NPZ),
        Case('convert {w}/bags --out {w}/o.npz --label', 'argument --label: expected one '
             'argument', OUT_NPZ),
        Case('convert {w}/unlabelled --out {w}/o.npz', 'no windows: .*give --label NAME',
             OUT_NPZ),
        Case('convert {w}/odd_meta --out {w}/o.npz', 'no windows: .*metadata key "label" must '
             'be non-empty text', OUT_NPZ),
        Case('convert {w}/bags --out {w}/o.npz --window 1000', 'no windows: .*shorter than '
             'one window', OUT_NPZ),
        Case('convert {w}/bags --out {w}/o.npz --window 1000000000000', 'argument --window: '
             'must be a whole number in 2..65536', OUT_NPZ),
        Case('convert {w}/bags --out {w}/o.npz --trial 100000000000', 'argument --trial: must '
             'be a whole number in 0..4294967295', OUT_NPZ),
        Case('convert {w}/fifobag --out {w}/o.npz', r'wood_0000.mcap is a FIFO \(named pipe\), '
             'not a regular file', OUT_NPZ),
        *[Case(f'convert {{w}}/foreign/{name} --out {{w}}/o.npz', f'no windows: .*{name}.*{why}',
               OUT_NPZ) for name, why in FOREIGN.items()],
        *[Case(f'convert {{w}}/bags --out {{w}}/o.npz --resample {value}', 'argument --resample: '
               'must be a finite number > 0 and <= 100000', OUT_NPZ)
          for value in ('0', 'nan', 'fast', '1e6')],
        Case('convert {w}/bags --out {w}/o.npz --resample', 'argument --resample: expected one '
             'argument', OUT_NPZ),
        Case('convert {w}/bags --out {w}/o.npz --window 16', 'no windows: .*no sweep/active '
             'topic, joint states or ground truth .*give --all-samples', OUT_NPZ),
        Case('convert {w}/bags --out {w}/o.npz --window 16 --all-samples --resample 0.01',
             'no windows: .*cannot resample 120 Hz to 0.01 Hz: .*at most 1000 times apart',
             OUT_NPZ),
        Case('convert {w}/mixed_rates --out {w}/o.npz --window 16 --all-samples',
             r'recordings at different rates: 120 Hz \(wood_0000\), 30 Hz \(slow_0000\); '
             'convert them separately or give --resample HZ', OUT_NPZ),
    ],
    'predict': [
        Case('predict', 'the following arguments are required: CHECKPOINT, '
             'RECORDING_OR_DATASET'),
        Case('predict {w}/minirocket', 'required: RECORDING_OR_DATASET'),
        Case('predict {w}/nothing {w}/bags', 'CHECKPOINT .*nothing does not exist'),
        Case('predict {w}/corrupt_checkpoint {w}/data.npz', 'checkpoint.json'),
        Case('predict {w}/minirocket {w}/nothing', 'RECORDING_OR_DATASET .*nothing does not '
             'exist'),
        Case('predict {w}/minirocket {w}/folder', 'no recordings or datasets in'),
        Case('predict {w}/minirocket {w}/good/wood/a.csv', r'RECORDING_OR_DATASET .*a.csv is a '
             'CSV table: make its folder of CLASS/\\*.csv a dataset with `tactex import csv`'),
        Case('predict {w}/minirocket {w}/data.npz --out {w}/text.txt', '--out .*text.txt is a '
             'file', '{w}/text.txt'),
        Case('predict {w}/minirocket {w}/data.npz --out {w}/full', '--out .*full already holds '
             'files', '{w}/full'),
        Case('predict {w}/minirocket {w}/foreign/text.bag', 'text.bag: cannot read: not a ROS 1 '
             'bag'),
        Case('predict {w}/minirocket {w}/garbage.npz', 'garbage'),
        Case('predict {w}/minirocket {w}/window16.npz', 'RECORDING_OR_DATASET .*window16.npz '
             'holds 16-sample windows, CHECKPOINT .*minirocket takes 32: convert the recordings '
             'with --window 32, or give a checkpoint trained on 16-sample windows'),
        Case('predict {w}/minirocket {w}/pickled.npz', 'pickled.npz is not a tactex dataset: it '
             'is not an .npz of plain arrays .*never does'),
        Case('predict {w}/minirocket {w}/bags --hop 33', "--hop 33 is longer than the "
             "checkpoint's window 32: give at most 32"),
        Case('predict {w}/minirocket {w}/data.npz --threshold 2', 'argument --threshold'),
        Case('predict {w}/minirocket {w}/data.npz --contact nope', 'argument --contact: invalid '
             'choice'),
        Case('predict {w}/minirocket {w}/bags --topic imu', "--topic 'imu' is not ROLE=TOPIC"),
    ],
    'bag': [
        Case('bag', 'the following arguments are required: ACTION'),
        Case('bag info', 'the following arguments are required: RECORDING'),
        Case('bag info {w}/nothing', 'RECORDING .*nothing does not exist'),
        Case('bag info {w}/folder', 'no recordings in .*folder; give rosbag2 folders'),
        Case('bag info {w}/text.txt', 'text.txt: not a recording'),
        Case('bag info {w}/foreign', '7 of 9 recordings cannot be read'),
        Case('bag info {w}/ros1/wood.bag --jason', 'unrecognized arguments: --jason; see '
             '`tactex bag --help`'),
        Case('bag play', 'the following arguments are required: RECORDING'),
        Case('bag play {w}/nothing', 'RECORDING .*nothing does not exist'),
        Case('bag play {w}/text.txt', 'RECORDING .*text.txt is no recording'),
        Case('bag play {w}/bags/wood_0000 --rate-factor 0', 'argument --rate-factor: must be'),
        Case('bag play {w}/bags/wood_0000 --duration -1', 'argument --duration: must be'),
        Case('bag play {w}/bags/wood_0000 --remap /a', "--remap '/a' is not OLD:=NEW"),
        Case('bag play {w}/bags/wood_0000 --remap /a:=/9b', "--remap '/a:=/9b': '9b' is not a "
             'ROS topic name'),
        Case('bag play {w}/bags/wood_0000 --namespace 1bad', 'argument --namespace'),
        Case('bag play {w}/bags/wood_0000 --wait-for /x --wait-timeout 0', 'argument '
             '--wait-timeout: must be a finite number > 0'),
        Case('bag play {w}/bags/wood_0000 --wait-timeout 5', '--wait-timeout bounds the wait '
             'of --wait-for: add --wait-for TOPIC ... or drop --wait-timeout'),
        Case('bag play {w}/bags/wood_0000 --wait-for /a //', "argument --wait-for: must be a "
             "ROS topic name such as /tactile/imu/data_raw .*got '//'"),
        Case('bag play {w}/bags/wood_0000 --wait-for ~/imu', 'argument --wait-for: must be a '
             "ROS topic name .*got '~/imu'"),
        Case('bag play {w}/bags/wood_0000 --wait-for a:=b', 'argument --wait-for: must be a '
             "ROS topic name .*got 'a:=b'"),
        Case('bag play {w}/bags/wood_0000 --wait-for /clock', '--wait-for /clock: /clock is '
             'published only with --clock; add --clock'),
        Case('bag play {w}/foreign/text.bag', 'text.bag: cannot read: not a ROS 1 bag'),
        *[Case(f'bag info {{w}}/foreign/{name}', f'{name}: cannot read: .*{why}')
          for name, why in FOREIGN.items() if name not in ('lab.bag', 'other_imu.bag')],
    ],
    'train': [
        Case('train {w}/data.npz --out=', 'argument --out: must not be empty'),
        Case('train {w}/data.npz --out {w}/run --movements {w}/nothing.yaml',
             '--movements .*nothing.yaml does not exist', '{w}/run'),
        Case('train {w}/data.npz --out {w}/run --movements {w}/movements/typo.yaml',
             '--movements .*unknown keys sped', '{w}/run'),
        Case('train {w}/data.npz --out {w}/run --movements {w}/movements/long.yaml',
             'DATA .*data.npz: 6 recording.* name no movement', '{w}/run'),
        Case('train {w}/nothing.npz --out {w}/run', 'DATA .*nothing.npz does not exist; make one '
             'with `tactex convert BAGS --out DATA.npz`', '{w}/run'),
        Case('train {w} --out {w}/run', 'DATA .* is a folder; give the .npz dataset', '{w}/run'),
        Case('train {w}/text.txt --out {w}/run', 'DATA .*text.txt is not a dataset: give the '
             '.npz file', '{w}/run'),
        Case('train {w}/foreign/text.bag --out {w}/run', 'DATA .*text.bag is not a dataset',
             '{w}/run'),
        Case('train {w}/data.npz --out {w}/run --init=', 'argument --init: must not be empty',
             '{w}/run'),
        Case('train {w}/garbage.npz --out {w}/run', 'garbage.npz is not a tactex dataset',
             '{w}/run'),
        Case('train {w}/bad_rate.npz --out {w}/run', r'bad_rate.json: sampling_rate_hz must be '
             r'a finite number in 0.01..100000 Hz, got -5.0', '{w}/run'),
        Case('train {w}/huge_rate.npz --out {w}/run', r'huge_rate.json: sampling_rate_hz must '
             r'be a finite number in 0.01..100000 Hz, got 1000', '{w}/run'),
        Case('train {w}/fast_rate.npz --out {w}/run', r'fast_rate.json: sampling_rate_hz must '
             r'be a finite number in 0.01..100000 Hz, got 1000000000.0: convert or import the '
             'recordings again', '{w}/run'),
        Case('train {w}/wrong_window.npz --out {w}/run', 'wrong_window.json: window 64 but the '
             'dataset holds 32-sample windows', '{w}/run'),
        Case('train {w}/bad_labels.npz --out {w}/run', r'bad_labels.npz: y holds class indices '
             r'outside 0..2', '{w}/run'),
        Case('train {w}/non_finite.npz --out {w}/run', r'DATA .*non_finite.npz: 1 window\(s\) '
             r'hold NaN or inf \(trials 1\); convert or import the recordings again', '{w}/run'),
        Case('train {w}/data.npz --out {w}/run --epochs 0', 'argument --epochs: must be a whole '
             'number in 1..100000', '{w}/run'),
        Case('train {w}/data.npz --out {w}/run --profile fancy',
             "argument --profile: invalid choice: 'fancy'", '{w}/run'),
        Case('train {w}/data.npz --out {w}/run --scaling robust',
             "argument --scaling: invalid choice: 'robust'", '{w}/run'),
        Case('train {w}/data.npz --out {w}/run --folds 1', 'argument --folds', '{w}/run'),
        Case('train {w}/data.npz --out {w}/run --folds 50', '--folds 50 needs at least 50 '
             'recordings.*lower --folds', '{w}/run'),
        Case('train {w}/data.npz --out {w}/run --threads 0', 'argument --threads', '{w}/run'),
        Case('train {w}/data.npz --out {w}/run --early-stopping -1', 'argument --early-stopping',
             '{w}/run'),
        Case('train {w}/data.npz --out {w}/run --model nope', 'argument --model: invalid choice',
             '{w}/run'),
        Case('train {w}/one_class.npz --out {w}/run', 'DATA has 1 class.*at least two',
             '{w}/run'),
        Case('train {w}/data.npz --out {w}/run --model cnn_3 --epochs 1 --folds 2',
             "--model cnn_3 needs windows of at least 76 samples, the data's are 32: convert "
             r'\(or import\) with --window 76 or more, or choose another --model', '{w}/run'),
        Case('train {w}/data.npz --out {w}/run --init {w}/nothing', '--init .*nothing does not '
             'exist', '{w}/run'),
        Case('train {w}/data.npz --out {w}/run --init {w}/trained', '--init: .*trained: missing '
             'checkpoint.json; give its checkpoint, .*trained/model', '{w}/run'),
        Case('train {w}/data.npz --out {w}/run --init {w}/corrupt_checkpoint', '--init: .*refused '
             'checkpoint.json: .*; retrain or copy the whole folder again', '{w}/run'),
        Case('train {w}/data.npz --out {w}/text.txt', '--out .*text.txt is a file; give a '
             'folder', '{w}/text.txt'),
        Case('train {w}/data.npz --out {w}/full', '--out .*full already holds files; choose a '
             'new folder', '{w}/full'),
        Case('train {w}/data.npz --out {w}/link', '--out .*link is a symbolic link .*give the '
             'path itself', '{w}/link'),
        Case('train {w}/data.npz --out /sys/tactex-run', r'--out /sys/tactex-run: /sys is not '
             r'writable \(Operation not permitted\)'),
        Case('train {w}/data.npz --out {w}/run --seed 100000000000000000000', 'argument --seed: '
             'must be a whole number in 0..4294967295', '{w}/run'),
        Case('train {w}/data.npz --out {w}/run --epochs 1000000000', 'argument --epochs: must '
             'be a whole number in 1..100000', '{w}/run'),
        Case('train {w}/fifo.npz --out {w}/run', r'fifo.npz is a FIFO \(named pipe\), not a '
             'regular file', '{w}/run'),
        Case('train {w}/fifo_sidecar.npz --out {w}/run', 'fifo_sidecar.json is a FIFO',
             '{w}/run'),
    ],
    'compare': [
        Case('compare {w}/data.npz --out=', 'argument --out: must not be empty'),
        Case('compare --out {w}/g', 'the following arguments are required: DATA'),
        Case('compare {w}/data.npz', 'the following arguments are required: --out'),
        Case('compare {w}/data.npz --out {w}/g --profile fancy',
             "argument --profile: invalid choice: 'fancy'", '{w}/g'),
        Case('compare {w}/data.npz --out {w}/g --scaling robust',
             "argument --scaling: invalid choice: 'robust'", '{w}/g'),
        Case('compare {w}/nothing.npz --out {w}/g', 'DATA .*nothing.npz does not exist', '{w}/g'),
        Case('compare {w}/text.txt --out {w}/g', 'text.txt is neither a dataset', '{w}/g'),
        Case('compare {w}/garbage.npz --out {w}/g', 'garbage.npz is not a tactex dataset',
             '{w}/g'),
        Case('compare {w}/data.npz {w}/bags --out {w}/g', 'DATA mixes dataset files with '
             'recordings', '{w}/g'),
        Case('compare {w}/data.npz {w}/ros1/wood.bag --out {w}/g', 'DATA mixes dataset files '
             'with recordings', '{w}/g'),
        Case('compare {w}/data.npz {w}/data.npz --out {w}/g', 'two datasets of window 32',
             '{w}/g'),
        Case('compare {w}/data.npz {w}/other16.npz --out {w}/g', r'DATA .*data.npz and .*'
             r'other16.npz differ in classes, recordings: they are not one set of '
             r'recordings', '{w}/g'),
        Case('compare {w}/folder --out {w}/g --windows 16', 'no recordings found', '{w}/g'),
        Case('compare {w}/data.npz --out {w}/g --models nope', r"argument --models: unknown "
             r"model\(s\) \['nope'\]", '{w}/g'),
        Case('compare {w}/data.npz --out {w}/g --models cnn_1,cnn_1', 'names a model twice',
             '{w}/g'),
        Case('compare {w}/data.npz --out {w}/g --windows 1', 'argument --windows: must be a '
             'whole number in 2', '{w}/g'),
        Case('compare {w}/data.npz --out {w}/g --windows 32,32', 'names a window twice',
             '{w}/g'),
        Case('compare {w}/data.npz --out {w}/g --windows 1000000000000', 'argument --windows: '
             'must be a whole number in 2..65536', '{w}/g'),
        Case('compare {w}/data.npz --out {w}/link', '--out .*link is a symbolic link',
             '{w}/link'),
        Case('compare {w}/data.npz --out {w}/g --windows 64', '--windows 64: no dataset of that '
             r'window in DATA \(they have 32\)', '{w}/g'),
        Case('compare {w}/data.npz --out {w}/g --folds 1', 'argument --folds', '{w}/g'),
        Case('compare {w}/data.npz --out {w}/g --folds 50', 'window 32: --folds 50 needs at '
             'least 50 recordings', '{w}/g'),
        Case('compare {w}/one_class.npz --out {w}/g', 'window 32: DATA has 1 class', '{w}/g'),
        Case('compare {w}/data.npz --out {w}/g --models cnn_3', '--models cnn_3 cannot take '
             'window 32: it needs at least 76 samples; drop the model or the window', '{w}/g'),
        Case('compare {w}/data.npz --out {w}/g --seeds 0', 'argument --seeds', '{w}/g'),
        Case('compare {w}/data.npz --out {w}/g --epochs 0', 'argument --epochs', '{w}/g'),
        Case('compare {w}/data.npz --out {w}/g --threads 0', 'argument --threads', '{w}/g'),
        Case('compare {w}/data.npz --out {w}/g --cpus 0', 'argument --cpus', '{w}/g'),
        Case('compare {w}/data.npz --out {w}/g --cells-per-gpu 0', 'argument --cells-per-gpu',
             '{w}/g'),
        Case('compare {w}/data.npz --out {w}/g --device tpu', 'argument --device: invalid '
             'choice', '{w}/g'),
        Case('compare {w}/data.npz --out {w}/g --device cuda', '--device cuda: this machine has '
             'no usable GPU', '{w}/g'),
        Case('compare {w}/data.npz --out {w}/g --mps', '--mps: this machine has no usable GPU; '
             'drop --mps', '{w}/g'),
        Case('compare {w}/data.npz --out {w}/g --mps --device cpu', '--mps shares a GPU; drop '
             'it with --device cpu', '{w}/g'),
        Case('compare {w}/data.npz --out {w}/g --mps --address 127.0.0.1:1', '--mps starts '
             'NVIDIA MPS on this machine; on a cluster start it on each GPU node', '{w}/g'),
        Case('compare {w}/data.npz --out {w}/g --address nohost', 'argument --address: must be '
             'HOST:PORT', '{w}/g'),
        Case('compare {w}/data.npz --out {w}/g --address 127.0.0.1:1', 'cannot reach Ray at '
             '127.0.0.1:1: Connection refused; start the head with `ray start --head`',
             '{w}/g'),
        Case('compare {w}/data.npz --out {w}/g --address 10.0.0.1:6379 --cpus 2', '--cpus caps '
             'a local Ray instance', '{w}/g'),
        Case('compare {w}/data.npz --out {w}/grid --folds 2 --epochs 4', r'grid was started '
             r'with epochs 3 \(now 4\); give the same settings', '{w}/grid'),
        Case('compare {w}/data.npz --out {w}/text.txt', '--out .*text.txt is a file',
             '{w}/text.txt'),
        Case('compare {w}/data.npz --out {w}/full', '--out .*full already holds files',
             '{w}/full'),
        Case('compare {w}/data.npz --out {w}/readonly/g', '--out .*is not writable',
             '{w}/readonly/g', needs_non_root=True),
    ],
    'param': [
        Case('param', 'the following arguments are required: ACTION'),
        Case('param get', 'the following arguments are required: NODE, NAME'),
        Case('param set madgwick_node gain', 'the following arguments are required: VALUE'),
        Case('param get madgwick_node gain --timeout 0', '--timeout 0.0: give a number of '
             'seconds > 0'),
        Case('param list madgwick_node --timeout nan', '--timeout nan: give a number'),
    ],
    'doctor': [
        Case('doctor --sensor-rate 0', 'argument --sensor-rate: must be a finite number > 0'),
        Case('doctor --listen 100', 'argument --listen: must be a finite number > 0 and <= 60'),
        Case('doctor --only gpu', "argument --only: invalid choice: 'gpu'"),
        Case('doctor --arm-baud fast', 'argument --arm-baud: must be a whole number >= 1'),
        Case('doctor --sensor-port', 'argument --sensor-port: expected one argument'),
    ],
    'probe': [
        Case('probe --span -0.01', '--span: span must be .*got -0.01'),
        Case('probe --step 0', '--step: step must be'),
        Case('probe --direction 1 1 0', '--direction: direction must be a unit vector'),
        Case('probe --start 0.1 0 nan', '--start: start must be 3 finite numbers'),
        Case('probe --start 0.1 0', 'argument --start: expected 3 arguments'),
        Case('probe --server-timeout 0', r'argument --server-timeout: must be a finite number '
             '> 0'),
        Case('probe --score --out {w}/folder', '--out .*folder is a folder', '{w}/folder'),
        Case('probe --namespace nowhere --server-timeout 1', 'no probe action server on '
             r'/nowhere/probe within 1 s: is its node running'),
        Case('probe --namespace nowhere --score --out {w}/s.png', 'no node '
             '/nowhere/mujoco_bridge answers', '{w}/s.png'),
    ],
    'sweep': [
        Case('sweep --speed 0', r'argument --speed: must be a finite number > 0'),
        Case('sweep --edge-offset 2', r'--edge-offset: edge_offset_rad must be in \[0, 1.5708\)'),
        Case('sweep --press-depth 0.5', '--press-depth: press_depth_m must be in'),
        Case('sweep --pathway {w}/nothing.json', '--pathway .*nothing.json does not exist'),
        Case('sweep --pathway {w}/text.txt', '--pathway .*text.txt: .*give a pathway file '
             'probe_node wrote'),
        Case('sweep --pathway=', 'argument --pathway: must not be empty'),
        Case('sweep --trial -1', 'argument --trial: must be a whole number'),
        Case('sweep --movement fast.light', 'argument --movement: must start with a letter '
             'and hold only letters'),
        Case('sweep --namespace nowhere --server-timeout 1', 'no sweep action server on '
             r'/nowhere/sweep within 1 s'),
    ],
    'identify': [
        Case('identify --policy greedy', "argument --policy: invalid choice: 'greedy'"),
        Case('identify --threshold 1.5', 'argument --threshold: must be a finite number > 0 '
             'and <= 1'),
        Case('identify --threshold 0', 'argument --threshold: must be a finite number > 0 '
             'and <= 1'),
        Case('identify --budget-movements 0', 'argument --budget-movements: must be a whole '
             'number'),
        Case('identify --budget-seconds -2', 'argument --budget-seconds: must be a finite '
             'number > 0'),
        Case('identify --seed -1', 'argument --seed: must be a whole number'),
        Case('identify --pathway {w}/text.txt', '--pathway .*text.txt: .*give a pathway file '
             'probe_node wrote'),
        Case('identify --pathway {w}/nothing.json', '--pathway .*nothing.json does not exist; '
             'give a pathway file probe_node wrote'),
        Case('identify --pathway=', 'argument --pathway: must not be empty'),
        Case('identify --namespace nowhere --server-timeout 1', 'no identify action server on '
             r'/nowhere/identify within 1 s: is its node running \(`tactex launch system '
             r'sim:=true bundle:=RUN/bundle`'),
        Case('identify --server-timeout 1e300', 'argument --server-timeout: must be a finite '
             'number > 0 and <= 3600'),
    ],
    'view': [
        Case('view --port 70000', 'argument --port: must be a whole number in 0..65535'),
        Case('view --host 256.0.0.1', "parameter host:='256.0.0.1' is refused; allowed: a host "
             'this machine can listen on'),
        Case('view --namespace a.b', 'argument --namespace: must be a ROS namespace'),
        Case('view --host', 'argument --host: expected one argument'),
    ],
    'status': [
        Case('status --duration 0', r'--duration 0.0: give seconds in \(0, 3600\]'),
        Case('status --duration soon', "argument --duration: invalid float value: 'soon'"),
        Case('status --duration inf', '--duration inf: give seconds'),
    ],
    'watch': [
        Case('watch --count -1', '--count must be >= 0'),
        Case('watch --timeout -3', '--timeout seconds in 0..86400'),
        Case('watch --count many', "argument --count: invalid int value: 'many'"),
        Case('watch --namespace 9lives', 'argument --namespace: must be a ROS namespace'),
    ],
    'plot': [
        Case('plot', 'the following arguments are required: RECORDING|RUN'),
        Case('plot {w}/nothing', r'RECORDING\|RUN .*nothing does not exist'),
        Case('plot {w}/folder', 'neither a recording .* nor a run: it holds none of '
             'metrics.json, summary.json, results.json'),
        Case('plot {w}/text.txt', 'neither a recording'),
        Case('plot {w}/bags/wood_0000', 'a recording needs --out FILE.png'),
        Case('plot {w}/bags/wood_0000 --out {w}/folder', '--out .*folder is a folder',
             '{w}/folder'),
        Case('plot {w}/bags/wood_0000 --out {w}/o.txt', '--out .*must end in .png', '{w}/o.txt'),
        Case('plot {w}/fifobag/wood_0000 --out {w}/o.png', r'wood_0000.mcap is a FIFO',
             '{w}/o.png'),
        Case('plot {w}/grid --out {w}/o.png', "--out is for a recording; a run's plots go "
             'into the run'),
        Case('plot {w}/bags/wood_0000 --out {w}/exists.png', '--out .*exists.png exists; give '
             '--force to replace it'),
        Case('plot {w}/data.npz --out {w}/o.png', r'RECORDING\|RUN .*data.npz is neither a '
             'recording nor a run', '{w}/o.png'),
        Case('plot {w}/predict_report', 'predict_report is a `tactex predict` report: predict '
             'draws its plot'),
        Case('plot {w}/lying_run', r'metrics.json does not hold what a `tactex train` run '
             'keeps'),
        Case('plot {w}/garbage_run', r'metrics.json: not JSON'),
    ],
    'export': [
        Case('export {w}/minirocket', 'nothing to export: give --onnx'),
        Case('export {w}/nothing --onnx', 'CHECKPOINT .*nothing does not exist'),
        Case('export {w}/text.txt --onnx', 'CHECKPOINT .*text.txt is a file; give a folder'),
        Case('export {w}/folder --onnx', 'folder: missing checkpoint.json',
             '{w}/folder/model.onnx'),
        Case('export {w}/corrupt_checkpoint --onnx', 'refused checkpoint.json',
             '{w}/corrupt_checkpoint/model.onnx'),
        Case('export {w}/minirocket --onnx', 'minirocket has no ONNX form; it runs in numpy',
             '{w}/minirocket/model.onnx'),
        Case('export {w}/minirocket --onnx --out {w}/folder', '--out .*folder is a folder',
             '{w}/folder'),
        Case('export {w}/minirocket --onnx --out {w}/m.txt', '--out .*must end in .onnx',
             '{w}/m.txt'),
        Case('export {w}/minirocket --onnx --out {w}/exists.onnx', '--out .*exists.onnx exists; '
             'give --force to replace it'),
        Case('export {w}/minirocket --onnx --out {w}/dangling.onnx', '--out .*dangling.onnx is a '
             'symbolic link', '{w}/dangling.onnx'),
        Case('export {w}/swapped_checkpoint --onnx', 'checkpoint.json does not match its '
             'metadata_sha256: edited or corrupt', '{w}/swapped_checkpoint/model.onnx'),
        Case('export {w}/nested_checkpoint --onnx', 'JSON nested 100000 levels deep; at most 16',
             '{w}/nested_checkpoint/model.onnx'),
        Case('export {w}/fifo_checkpoint --onnx', r'refused weights.npz: .*is a FIFO \(named '
             r'pipe\), not a regular file', '{w}/fifo_checkpoint/model.onnx'),
    ],
    'import': [
        Case('import csv {w}/good --out {w}/o.npz', 'csv needs --rate HZ', OUT_NPZ),
        Case('import csv {w}/good --out {w}/o.npz --rate 0', 'argument --rate: must be a finite '
             'number >= 0.01 and <= 100000', OUT_NPZ),
        Case('import csv {w}/good --out {w}/o.npz --rate 1e9', 'argument --rate: must be a '
             'finite number >= 0.01 and <= 100000', OUT_NPZ),
        Case('import csv {w}/good --out {w}/o.npz --rate nan', 'argument --rate', OUT_NPZ),
        Case('import csv {w}/good --out {w}/o.npz --rate inf', 'argument --rate', OUT_NPZ),
        Case('import mun {w}/mun --out {w}/o.npz --resample 350', '--resample apply to csv '
             'only', OUT_NPZ),
        Case('import csv {w}/good --out {w}/o.npz --rate 9 --resample 0', 'argument '
             '--resample: must be a finite number >= 0.01 and <= 100000', OUT_NPZ),
        Case('import mun {w}/mun --out {w}/o.npz --rate 350', '--rate apply to csv only',
             OUT_NPZ),
        Case('import csv {w}/nothing --out {w}/o.npz --rate 9', 'ROOT .*nothing does not exist',
             OUT_NPZ),
        Case('import csv {w}/text.txt --out {w}/o.npz --rate 9', 'ROOT .*text.txt is a file',
             OUT_NPZ),
        Case('import csv {w}/good --out {w}/o.npz --rate 9', r"no column\(s\) \['ax'.*--columns",
             OUT_NPZ),
        Case('import csv {w}/ragged --out {w}/o.npz --rate 9 --columns pdc,pac',
             'a.csv, line 3: 1 fields, but the header has 2', OUT_NPZ),
        Case('import csv {w}/bincsv --out {w}/o.npz --rate 9 --columns pdc', 'binary file',
             OUT_NPZ),
        Case('import csv {w}/good --out {w}/o.npz --rate 9 --columns ax=', 'bad --columns item',
             OUT_NPZ),
        Case('import csv {w}/good --out {w}/o.npz --rate 9 --columns pdc,pdc', 'repeat',
             OUT_NPZ),
        Case('import csv {w}/good --out {w}/o.npz --rate 9 --columns pdc --delimiter ::',
             "--delimiter '::'", OUT_NPZ),
        Case('import csv {w}/good --out {w}/o.npz --columns pdc --time nocol',
             "no column 'nocol'", OUT_NPZ),
        Case('import csv {w}/good --out {w}/o.npz --rate 9 --columns pdc --window 100',
             'no windows: the longest recording has 40 samples .* give a smaller --window',
             OUT_NPZ),
        Case('import csv {w}/uneven --out {w}/o.npz --rate 9 --columns pdc --window 20',
             r'class\(es\) wood \(longest recording 10 samples\).*smaller --window', OUT_NPZ),
        Case('import csv {w}/epoch_ns --out {w}/o.npz --columns pdc --time time',
             r"a.csv: time column 'time' holds values up to 1.7e\+18 s.*--time-unit", OUT_NPZ),
        Case('import mun {w}/mun_text --out {w}/o.npz --window 2',
             r"t.pkl: column 'imu_ax' holds 'oops', not a number", OUT_NPZ),
        Case('import csv {w}/good --out {w}/data.npz --rate 9 --columns pdc',
             r'--out .*data.npz exists; give --force to replace it'),
        Case('import mun {w}/mun --out {w}/o.npz', 'refusing to load posix.system', OUT_NPZ),
        Case('import mun {w}/folder --out {w}/o.npz', r'no pickles_\*/texture_', OUT_NPZ),
        Case('import mun {w}/mun --out {w}/folder', '--out .*folder is a folder', '{w}/folder'),
        Case('import xls {w}/good --out {w}/o.npz', 'argument kind: invalid choice', OUT_NPZ),
        Case('import csv {w}/fifocsv --out {w}/o.npz --rate 9 --columns pdc',
             r'a.csv is a FIFO \(named pipe\), not a regular file', OUT_NPZ),
        Case('import csv {w}/good --out {w}/o.npz --rate 9 --columns pdc --window 70000',
             'argument --window: must be a whole number in 2..65536', OUT_NPZ),
    ],
    'sim': [
        Case('sim collect --out {w}/bagsout --sweeps 0', 'argument --sweeps', '{w}/bagsout'),
        Case('sim collect --out {w}/bagsout --scene nope', 'no scene file .*nope.toml',
             '{w}/bagsout'),
        Case('sim collect --out {w}/bagsout --scene {w}/scenes/binary.toml', 'not valid TOML',
             '{w}/bagsout'),
        Case('sim collect --out {w}/bagsout --scene {w}/folder', 'is a folder, not a regular file',
             '{w}/bagsout'),
        Case('sim collect --out {w}/bagsout --scene {w}/scenes/standing.toml',
             'speed_m_s and contact_s must be > 0', '{w}/bagsout'),
        Case('sim collect --out {w}/bagsout --textures nope', '--textures: unknown texture',
             '{w}/bagsout'),
        Case('sim collect --out {w}/text.txt', '--out .*text.txt is a file', '{w}/text.txt'),
        Case('sim collect --out {w}/full', '--out .*already holds files', '{w}/full'),
        Case('sim', 'the following arguments are required: ACTION'),
        Case('sim collect --out {w}/bagsout --workers 0', 'argument --workers', '{w}/bagsout'),
        Case('sim collect --out {w}/bagsout --scene {w}/fifo.toml', r'fifo.toml is a FIFO '
             r'\(named pipe\), not a regular file', '{w}/bagsout'),
        Case('sim collect --out {w}/bagsout --scene {w}/scenes/huge_cells.toml', 'cells '
             r'\[100000, 100000\] make 10000000000 heightfield cells; at most 1000000',
             '{w}/bagsout'),
        Case('sim collect --out {w}/bagsout --scene {w}/scenes/long_contact.toml',
             'contact_s must be <= 60 s, got 10000000.0', '{w}/bagsout'),
        Case('sim collect --out {w}/link', '--out .*link is a symbolic link', '{w}/link'),
        Case('sim collect --out {w}/bagsout --address nohost', 'argument --address: must be '
             'HOST:PORT', '{w}/bagsout'),
        Case('sim collect --out {w}/bagsout --movements {w}/nothing.yaml',
             '--movements .*nothing.yaml does not exist', '{w}/bagsout'),
        Case('sim collect --out {w}/bagsout --movements {w}/movements/empty.yaml',
             '--movements .*empty.yaml: no movements', '{w}/bagsout'),
        Case('sim collect --out {w}/bagsout --movements {w}/movements/fast.yaml',
             r'movement 1 \(dash\): speed must be a number in \[0.005, 0.05\] m/s',
             '{w}/bagsout'),
        Case('sim collect --out {w}/bagsout --movements {w}/movements/shallow.yaml',
             r'\(skim\): press_depth must be a number in \[0.0015, ', '{w}/bagsout'),
        Case('sim collect --out {w}/bagsout --movements {w}/movements/short.yaml',
             'movement tap: its contact .* is too short for one window of 128 samples',
             '{w}/bagsout'),
        Case('sim collect --out {w}/bagsout --movements {w}/movements/sideways.yaml',
             'direction must be one of forward, backward', '{w}/bagsout'),
        Case('sim collect --out {w}/bagsout --movements {w}/movements/long.yaml',
             'movement far slides 500 mm and ramps its speed .* the texture patch holds 237 mm',
             '{w}/bagsout'),
        Case('sim collect --out {w}/bagsout --movements {w}/movements/typo.yaml',
             'unknown keys sped; missing speed, press_depth', '{w}/bagsout'),
        Case('sim collect --out {w}/bagsout --movements {w}/folder', 'is a folder', '{w}/bagsout'),
        Case('sim collect --out {w}/bagsout --seed -1', 'argument --seed', '{w}/bagsout'),
    ],
    'record': [
        Case('record --out {w}/full', '--out .*already holds files', '{w}/full'),
        Case('record --out {w}/text.txt', '--out .*text.txt is a file', '{w}/text.txt'),
        Case('record --out {w}/rec --split-s 0', 'argument --split-s', '{w}/rec'),
        Case('record --out {w}/rec --split-s nan', 'argument --split-s', '{w}/rec'),
        Case('record --out {w}/rec --trial -5', 'argument --trial', '{w}/rec'),
        Case('record --out {w}/link', '--out .*link is a symbolic link', '{w}/link'),
        Case('record --out {w}/rec --meta novalue', "--meta 'novalue' is not KEY=VALUE",
             '{w}/rec'),
        Case('record --out {w}/rec --meta label=x', 'give label with --label', '{w}/rec'),
        Case('record --out {w}/rec --meta a=1 --meta a=2', "--meta gives 'a' twice", '{w}/rec'),
    ],
    'emulate': [
        Case('emulate teensy --link {w}/l --rate 0', 'argument --rate', '{w}/l'),
        Case('emulate teensy --link {w}/l --rate nan', 'argument --rate', '{w}/l'),
        Case('emulate teensy --link {w}/l --rate 5000', 'argument --rate: .*<= 2000', '{w}/l'),
        Case('emulate teensy --link {w}/l --duration 0', 'argument --duration', '{w}/l'),
        Case('emulate teensy --link {w}/l --duration -inf', 'argument --duration', '{w}/l'),
        Case('emulate teensy --link {w}/l --roll nan', 'argument --roll', '{w}/l'),
        Case('emulate teensy --link {w}/l --start-time-us -1', 'argument --start-time-us',
             '{w}/l'),
        Case('emulate teensy --link {w}/l --fault stall@nan:1', "--fault: bad fault "
             "'stall@nan:1'", '{w}/l'),
        Case('emulate teensy --link {w}/l --fault garbage@-1:5', '--fault: bad fault', '{w}/l'),
        Case('emulate teensy --link {w}/l --fault stall@0:1e300', "--fault: bad fault "
             "'stall@0:1e300': the argument of stall is at most 86400", '{w}/l'),
        Case('emulate teensy --link {w}/l --fault garbage@0:1e300', '--fault: bad fault .*'
             'garbage is at most 1e\\+06', '{w}/l'),
        Case('emulate teensy --link {w}/text.txt', '--link .*text.txt is an existing file',
             '{w}/text.txt'),
        Case('emulate teensy --link {w}/folder', '--link .*folder is an existing folder',
             '{w}/folder'),
        Case('emulate teensy --link {w}/nothing/l', '--link .*nothing is not a folder',
             '{w}/nothing/l'),
        Case('emulate teensy --link {w}/l --replay {w}/binary.bin', '--replay: .*binary file',
             '{w}/l'),
        Case('emulate teensy --link {w}/l --replay {w}/folder', '--replay .*folder is a folder',
             '{w}/l'),
        Case('emulate teensy --link {w}/l --replay {w}/fifo.csv', r'--replay .*fifo.csv is a '
             r'FIFO \(named pipe\), not a regular file', '{w}/l'),
        Case('emulate teensy --link {w}/l --seed 100000000000', 'argument --seed: must be a '
             'whole number in 0..4294967295', '{w}/l'),
        Case('emulate teensy --link {w}/l --replay {w}/good/wood/a.csv', '--replay: .*missing '
             'column', '{w}/l'),
        Case('emulate dynamixel --link {w}/l --fault silence@1:99', r'servo\(s\) \[99\], not '
             'on the chain', '{w}/l'),
        Case('emulate dynamixel --link {w}/l --fault melt@1:11', "--fault 'melt@1:11'",
             '{w}/l'),
        Case('emulate dynamixel --link {w}/text.txt', '--link .*text.txt is an existing file',
             '{w}/text.txt'),
        Case('emulate arduino', 'argument device: invalid choice'),
    ],
    'description': [
        Case('description --write-urdf {w}/folder', '--write-urdf .*folder is a folder',
             '{w}/folder'),
        Case('description --write-mjcf {w}/text.txt/arm.xml', '--write-mjcf .*text.txt is a '
             'file, not a folder', '{w}/text.txt/arm.xml'),
        Case('description --check-urdf {w}/nothing.urdf', '--check-urdf .*does not exist'),
        Case('description --check-urdf {w}/binary.bin', '--check-urdf .*not a text file'),
        Case('description --check-urdf {w}/folder', '--check-urdf .*folder is a folder'),
        Case('description --check-urdf {w}/fifo.urdf', r'--check-urdf .*fifo.urdf is a FIFO '
             r'\(named pipe\), not a regular file'),
        Case('description --write-urdf {w}/dangling.onnx', '--write-urdf .*dangling.onnx is a '
             'symbolic link', '{w}/dangling.onnx'),
        Case('description --check-urdf {w}/text.txt', 'is stale; regenerate it with `make '
             'urdf`'),
    ],
    'report': [
        Case('report', 'the following arguments are required: REPORT'),
        Case('report nope --out {w}/report', "invalid choice: 'nope'", '{w}/report'),
        Case('report accuracy-time', 'the following arguments are required: --out'),
        Case('report accuracy-time --out {w}/text.txt --quick', '--out .*text.txt is a file',
             '{w}/text.txt'),
        Case('report accuracy-time --out {w}/full --quick', '--out .*already holds files',
             '{w}/full'),
        Case('report accuracy-time --out {w}/text.txt/report --quick', 'text.txt is a file, '
             'not a folder', '{w}/text.txt/report'),
        Case('report accuracy-time --out {w}/report --threads 0', 'argument --threads',
             '{w}/report'),
        Case('report accuracy-time --out {w}/report --seed -1', 'argument --seed', '{w}/report'),
        Case('report accuracy-time --out {w}/report --seed 100000000000000000000', 'argument '
             '--seed: must be a whole number in 0..4294967295', '{w}/report'),
        Case('report accuracy-time --out {w}/report --epochs 1000000000', 'argument --epochs: '
             'must be a whole number in 1..100000', '{w}/report'),
        Case('report accuracy-time --out {w}/link --quick', '--out .*link is a symbolic link',
             '{w}/link'),
        Case('report accuracy-time --out {w}/report --epochs 0', 'argument --epochs',
             '{w}/report'),
        Case('report accuracy-time --out {w}/report --quick=yes', 'ignored explicit argument',
             '{w}/report'),
        Case('report identification {w}/data.npz --out {w}/report',
             'DATA .*data.npz: 6 recording.* name no movement.*sim collect --movements',
             '{w}/report'),
        Case('report identification {w}/nothing.npz --out {w}/report', 'DATA .*nothing.npz does '
             'not exist; make one with `tactex convert', '{w}/report'),
        Case('report identification {w} --out {w}/report', 'DATA .* is a folder; give the .npz',
             '{w}/report'),
        Case('report identification {w}/text.txt --out {w}/report', 'DATA .*text.txt is not a '
             'dataset', '{w}/report'),
        Case('report identification {w}/data.npz --out {w}/report --movements=',
             'argument --movements: must not be empty', '{w}/report'),
        Case('report identification {w}/data.npz --out {w}/report --policies active,greedy',
             'argument --policies: must be distinct names of active, random, fixed, '
             'round-robin', '{w}/report'),
        Case('report identification {w}/data.npz --out {w}/report --policies active,active',
             'argument --policies', '{w}/report'),
        Case('report identification {w}/data.npz --out {w}/report --threshold 1.5',
             'argument --threshold', '{w}/report'),
        Case('report identification {w}/data.npz --out {w}/report --repeats 0',
             'argument --repeats', '{w}/report'),
        Case('report identification {w}/data.npz --out {w}/report --budget-seconds -1',
             'argument --budget-seconds', '{w}/report'),
        Case('report identification {w}/data.npz --out {w}/report --threshold 0',
             'argument --threshold: must be a finite number > 0 and <= 1', '{w}/report'),
        Case('report identification {w}/data.npz --out {w}/report --movements '
             '{w}/movements/long.yaml --budget-seconds 1', '--budget-seconds 1 is shorter than '
             r'every movement: the shortest contact lasts 25.00 s', '{w}/report'),
        Case('report identification {w}/non_finite.npz --out {w}/report',
             r'DATA .*non_finite.npz: 1 window\(s\) hold NaN or inf', '{w}/report'),
        Case('report identification {w}/data.npz --out {w}/report --folds 1',
             'argument --folds', '{w}/report'),
        Case('report identification {w}/data.npz --out {w}/report --model nope',
             "--model: unknown model 'nope'", '{w}/report'),
        Case('report identification {w}/data.npz --out {w}/report --movements '
             '{w}/movements/fast.yaml', r'--movements .*\(dash\): speed must be', '{w}/report'),
        Case('report identification {w}/data.npz --out {w}/report --movements '
             '{w}/movements/laughs.yaml', r'laughs.yaml: line 1, column 13: a movement file '
             r'takes no anchors or aliases', '{w}/report'),
        Case('report identification {w}/data.npz --out {w}/report --movements '
             '{w}/movements/twice.yaml', "twice.yaml: line 2, column 1: key 'window' is given "
             'twice in one mapping', '{w}/report'),
        Case('report identification {w}/data.npz --out {w}/report --movements '
             '{w}/movements/unclosed.yaml', r'unclosed.yaml: not a YAML movement file: line 3, '
             'column 1', '{w}/report'),
        Case('report identification {w}/data.npz --out {w}/report --movements {w}/nothing.yaml',
             '--movements .*nothing.yaml does not exist', '{w}/report'),
        Case('report identification {w}/data.npz --out {w}/full', '--out .*already holds files',
             '{w}/full'),
        Case('report identification {w}/data.npz --out {w}/report --threshold 0.3',
             r'DATA .*data.npz: --threshold 0.3 is at or below 1/3 = 0.333, the starting belief '
             r'over 3 textures: give more than 0.333 \(e.g. 0.99\)$', '{w}/report'),
        Case('report identification {w}/data.npz --out {w}/report --policies active,,random',
             "argument --policies: must be distinct names .*got 'active,,random'", '{w}/report'),
    ],
    'launch': [
        Case('launch', 'name a launch file'),
        Case('launch nope', "no launch file 'nope'.*known: "),
        Case('launch {w}/binary.bin', 'no launch file .*binary.bin'),
        Case('launch {w}/broken.launch.py', 'broken.launch.py cannot be loaded: SyntaxError'),
        Case('launch sim nope', "launch argument 'nope' is not NAME:=VALUE"),
        Case('launch sim nope:=1 --print', r"unknown launch argument\(s\) \['nope'\]"),
        Case('launch sim scen:=probe --print', r"\['scen'\] \('scen': did you mean 'scene'\?\)"),
        Case('launch sim scene:=no_such_scene --print', "scene:='no_such_scene': no scene file "
             '.*; give a scene under config/scenes/ or a .toml path'),
        Case('launch sim scene:={w}/scenes/binary.toml --print', 'scene:=.*not valid TOML'),
        Case('launch sim rate_factor:=-1 --print', "rate_factor:='-1' must be from 0 to 1000"),
        Case('launch sim rate_factor:=fast --print', "rate_factor:='fast' is not a finite "
             'number'),
        Case('launch sim namespace:=left-arm --print', "namespace:='left-arm' is not a ROS "
             'namespace: .*e.g. left_arm'),
        Case('launch sim patch_texture:=velvet --print', "patch_texture:='velvet': unknown "
             "texture 'velvet'; known: .*wood.*; or '' for the scene's"),
        Case('launch system sim:=true checkpoint:={w}/folder --print', 'checkpoint:=.*folder: '
             'missing checkpoint.json'),
        Case('launch classify source:=sim --print', r'checkpoint:=\.\.\. is required: '
             r'checkpoint folder \(RUN/model/ of tactex train\)'),
        Case('launch classify source:=sim checkpoint:={w}/corrupt_checkpoint --print',
             'checkpoint:=.*corrupt_checkpoint: refused checkpoint.json'),
        Case('launch system threshold:=2 --print', r"threshold:='2': threshold must be in "
             r'\[0, 1\]'),
        Case('launch system recording_root:={w}/text.txt --print', 'recording_root .*text.txt is '
             'a file; give a folder'),
        Case('launch probe pathway_file:= --print', "pathway_file:='' names no file"),
        Case('launch probe pathway_file:={w}/folder --print', 'pathway_file .*folder is a folder; '
             'give a file path'),
        Case('launch sensor port:={w}/text.txt --print', "port:='.*text.txt' is not a serial "
             'device'),
    ],
    'demo': [
        Case('demo --out {w}/text.txt', r'--out .*text.txt is a file; give a folder',
             '{w}/text.txt'),
        Case('demo --out {w}/full', r'--out .*full already holds files; choose a new folder',
             '{w}/full'),
        Case('demo --out {w}/text.txt/demo', r'--out .*text.txt is a file, not a folder',
             '{w}/text.txt/demo'),
        Case('demo --out {w}/readonly/demo', 'is not writable', '{w}/readonly/demo',
             needs_non_root=True),
        Case('demo --sweeps 1', 'argument --sweeps: must be a whole number in 2..50'),
        Case('demo --sweeps many', 'argument --sweeps: must be a whole number'),
        Case('demo --live-sweeps 0', 'argument --live-sweeps: must be a whole number in 1..20'),
        Case('demo --rate-factor 0', r'argument --rate-factor: must be a finite number > 0'),
        Case('demo --rate-factor nan', 'argument --rate-factor'),
        Case('demo --rate-factor 11', r'argument --rate-factor: .*<= 10'),
        Case('demo --points 3', 'unrecognized arguments: --points'),
    ],
}
