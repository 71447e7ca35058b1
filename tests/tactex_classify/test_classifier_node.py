# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""classifier_node: waits for the sensor, classifies live, refuses what it does not fit."""

import os
from pathlib import Path
import threading
import time

import pytest
from support.livestream import CLASSES, SensorStandIn, start_node, stop, write_checkpoints

pytestmark = [pytest.mark.integration, pytest.mark.ros, pytest.mark.slow]


@pytest.fixture(scope='module')
def checkpoints(tmp_path_factory):
    return write_checkpoints(tmp_path_factory.mktemp('checkpoints'))


def run_stream(context, process, *, smooth_s=2.0, ridged_s=4.0):
    sensor = SensorStandIn(context)
    assert sensor.spin_until(lambda: sensor.diagnostics, 60.0), 'the node never came up'
    time.sleep(1.2)  # long enough for a warning about the silent sensor
    sensor.publish(smooth_s, ridged=0.0)
    # The change to the ridged texture restarts the evidence. The worker may lag the stream
    # and skip windows on a loaded machine, so the ridged part lasts long enough for several
    # classified windows whatever it skips.
    sensor.publish(ridged_s, ridged=1.0)
    sensor.spin_until(lambda: sensor.estimates and sensor.estimates[-1].label == 'ridged', 20.0)
    return sensor


def test_the_node_waits_for_the_sensor_then_classifies_and_reports(checkpoints, ros_context):
    process = start_node(checkpoints / 'minirocket')
    try:
        sensor = run_stream(ros_context, process)
        assert sensor.estimates, 'no texture/estimate'
        last = sensor.estimates[-1]
        assert list(last.class_names) == CLASSES and last.model_id.startswith('minirocket@')
        assert last.label == 'ridged' and last.header.frame_id == 'sensor_edge'
        assert abs(sum(last.probabilities) - 1.0) < 1e-5
        assert len(last.window_starts) == len(last.window_ends) == last.windows_used >= 1
        assert any(e.label == 'smooth' for e in sensor.estimates)
        values = sensor.values()
        assert float(values['latency_p99_ms']) > 0 and values['runtime'] == 'numpy'
        # The rate counts the samples the worker took since the previous diagnostics: 0
        # once the stream has ended, so it is read from the diagnostics during the stream.
        rates = [float(kv.value) for status in sensor.diagnostics for kv in status.values
                 if kv.key == 'input_rate_hz']
        assert any(80.0 < rate < 160.0 for rate in rates), rates
    finally:
        output = stop(process)
    assert 'no samples for' in output and 'tactile/imu/data_raw' in output, output


def test_the_onnxruntime_runtime_runs_without_torch(checkpoints, ros_context):
    process = start_node(checkpoints / 'cnn', 'runtime:=onnxruntime')
    try:
        sensor = run_stream(ros_context, process)
        assert sensor.estimates and sensor.values()['runtime'] == 'onnxruntime'
        maps = Path(f'/proc/{process.pid}/maps').read_text()
        assert 'libtorch' not in maps and 'onnxruntime' in maps
    finally:
        stop(process)


@pytest.mark.parametrize('params, message', [
    (('rate_hz:=350.0',), 'rate: the model was trained at 120 Hz, the stream runs at 350 Hz'),
    (('window:=64',), 'window: the model was trained on 32-sample windows, the stream is cut '
                      'into 64'),
    (("channels:=['ax','ay','az']",), 'channels: the model was trained on ax, ay, az, gx'),
])
def test_a_stream_the_checkpoint_does_not_fit_is_refused_at_start(checkpoints, params,
                                                                  message):
    process = start_node(checkpoints / 'minirocket', *params)
    output = process.communicate(timeout=60)[0]
    assert process.returncode == 1, output
    assert message in output and 'Traceback' not in output, output


def test_a_malicious_checkpoint_is_refused_and_nothing_in_it_runs(checkpoints, tmp_path):
    import json
    import shutil

    import torch

    from tactex_classify.models.checkpoint import CHECKSUM_FIELD, metadata_sha256, sha256
    folder = shutil.copytree(checkpoints / 'cnn', tmp_path / 'cnn')
    marker = tmp_path / 'pwned'

    class Payload:
        def __reduce__(self):
            return (os.system, (f'touch {marker}',))
    torch.save({'weights': Payload()}, folder / 'weights.pt')
    meta = json.loads((folder / 'checkpoint.json').read_text())
    meta['files'] = {'weights.pt': sha256(folder / 'weights.pt')}
    meta[CHECKSUM_FIELD] = metadata_sha256(meta)
    (folder / 'checkpoint.json').write_text(json.dumps(meta))
    process = start_node(folder)
    output = process.communicate(timeout=60)[0]
    assert process.returncode == 1 and 'refused weights.pt' in output, output
    assert not marker.exists()


def test_the_demo_waits_until_the_classifier_is_ready_and_says_why_it_is_not(checkpoints,
                                                                             ros_context):
    from tactex.demo.session import SystemClient
    from tactex.errors import CommandError
    process = start_node(checkpoints / 'minirocket')
    try:
        sensor = SensorStandIn(ros_context)
        assert sensor.spin_until(lambda: sensor.diagnostics, 60.0), 'the node never came up'
        with SystemClient() as client:
            # Until the client has discovered the node, its error says 'no diagnostics'.
            said = ''
            deadline = time.monotonic() + 60.0
            while (not said or 'no diagnostics' in said) and time.monotonic() < deadline:
                with pytest.raises(CommandError, match='classifier_node was not ready within '
                                                       '1 s;') as refused:
                    client.wait_classifier_ready(1.0)
                said = str(refused.value)
            assert 'its diagnostics: no samples on tactile/imu/data_raw' in said, said
            streaming = threading.Thread(target=sensor.publish, args=(6.0, 0.0))
            streaming.start()
            client.wait_classifier_ready(5.0)
            streaming.join()
    finally:
        stop(process)
