# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex probe` and `tactex sweep` drive the real nodes in simulation, no ros2 CLI needed.

The simulator, Madgwick, probe_node and sweep_node run as processes under the namespace
/left, as `tactex launch` starts them. Each command sends its goal there, shows the
feedback as a progress bar, prints the result, and cancels its goal on Ctrl-C; a missing
server is one error line (tests/support/badinputs.py).
"""

import json
from pathlib import Path
import signal
import subprocess
import sys

import pytest
from support.processes import running_nodes, stop, tactex, wait_for

from tactex.launching.environment import ros_environment
from tactex_classify.data.bags import read_recording

pytestmark = [pytest.mark.integration, pytest.mark.ros, pytest.mark.slow]
BIN = Path(sys.executable).parent
CONFIG = Path(__file__).resolve().parents[2] / 'config'
NAMESPACE = ['-r', '__ns:=/left']
SIM_TIME = ['-p', 'use_sim_time:=true']


@pytest.fixture(scope='module')
def system(tmp_path_factory):
    """The probe and sweep system in simulation under /left; its folder (logs, files)."""
    folder = tmp_path_factory.mktemp('system')
    commands = {
        'bridge': [BIN / 'mujoco_bridge', '--ros-args', *NAMESPACE, '-p', 'scene:=uneven_texture',
                   '-p', 'rate_factor:=0.5'],
        'madgwick': [BIN / 'madgwick_node', '--ros-args', *NAMESPACE, '--params-file',
                     CONFIG / 'sensor.yaml', *SIM_TIME],
        'probe': [BIN / 'probe_node', '--ros-args', *NAMESPACE, '--params-file',
                  CONFIG / 'probe.yaml', *SIM_TIME, '-p',
                  f'pathway_file:={folder / "pathway.json"}'],
        'sweep': [BIN / 'sweep_node', '--ros-args', *NAMESPACE, '--params-file',
                  CONFIG / 'sweep.yaml', *SIM_TIME, '-p',
                  f'recording_root:={folder / "recordings"}'],
    }
    with running_nodes(commands, folder):
        # `probe --score` asks the bridge for its scene: wait until MuJoCo is loaded.
        assert wait_for(lambda: 'rate factor' in (folder / 'bridge.log').read_text(), 120)
        yield folder


def interrupted(argv: list[str], shown: str, folder: Path) -> tuple[int, str]:
    """Run `tactex ARGV`; once its progress shows `shown`, Ctrl-C; (exit code, stderr)."""
    errors = folder / 'interrupted.err'
    with open(errors, 'w') as sink:
        process = subprocess.Popen([BIN / 'tactex', *argv], stdout=subprocess.DEVNULL,
                                   stderr=sink, env=ros_environment())
        try:
            assert wait_for(lambda: shown in errors.read_text(), 240), errors.read_text()
            process.send_signal(signal.SIGINT)
            code = process.wait(timeout=120)
        finally:
            stop([process])
    return code, errors.read_text()


@pytest.fixture(scope='module')
def probed(system):
    """`tactex probe --score` over three points of the uneven plate: (run, plot path)."""
    plot = system / 'score.png'
    run = tactex('probe', '--namespace', 'left', '--start', '0.10', '0', '0.018', '--span',
                 '0.02', '--score', '--out', str(plot))
    return run, plot


def test_probe_shows_progress_prints_each_contact_and_scores_them(probed, system):
    run, plot = probed
    assert run.returncode == 0, run.stderr + (system / 'probe.log').read_text()[-3000:]
    lines = run.stdout.splitlines()
    assert lines[0].startswith('probe goal succeeded in ')
    assert lines[0].endswith('3 of 3 probes gave a contact')
    assert [line.split()[:2] for line in lines[2:5]] == [['1', 'ok'], ['2', 'ok'], ['3', 'ok']]
    assert 'pathway broadcast on /left/probe/pathway (latched)' in run.stdout
    score = next(line for line in lines if line.startswith('score against scene'))
    normal_deg = float(score.split('normal error ')[1].split()[0])
    position_mm = float(score.split('position error ')[1].split()[0])
    assert normal_deg < 8.0 and position_mm < 2.0, score
    assert plot.stat().st_size > 10_000
    bar = run.stderr.replace('\r', '\n')
    assert 'probe 1 descending' in bar and 'probe 2 measuring' in bar
    assert '3/3 probes' in bar
    assert (system / 'pathway.json').is_file()


def test_sweep_slides_along_the_probed_pathway_and_records_it(probed, system):
    assert probed[0].returncode == 0
    run = tactex('sweep', '--namespace', 'left', '--label', 'wood', '--trial', '7', '--record',
                 '--movement', 'default')
    assert run.returncode == 0, run.stdout + run.stderr + (system / 'sweep.log').read_text()
    assert run.stdout.startswith('sweep goal succeeded\n')
    contact = float(run.stdout.split('in contact ')[1].split()[0])
    speed = float(run.stdout.split('sliding speed ')[1].split()[0])
    assert contact > 75 and abs(speed - 15.0) < 3.0, run.stdout
    recording = Path(run.stdout.split('recorded to ')[1].split()[0])
    assert recording.parent == system / 'recordings' and recording.name.startswith('wood_0007')
    assert read_recording(recording).metadata['movement'] == 'default'
    assert 'in contact' in run.stderr and '100/100 %' in run.stderr


def test_a_sweep_goal_the_node_cannot_run_fails_with_its_reason(probed, system, tmp_path):
    pathway = json.loads((system / 'pathway.json').read_text())
    for probe in pathway['probes']:
        probe['position'][0] += 0.5  # half a metre beyond the arm's reach
    far = tmp_path / 'far.json'
    far.write_text(json.dumps(pathway))
    run = tactex('sweep', '--namespace', 'left', '--pathway', str(far))
    assert run.returncode == 1
    assert run.stdout.startswith('sweep goal aborted: '), run.stdout
    assert 'error' not in run.stderr


def test_ctrl_c_cancels_the_sweep_goal_and_the_edge_is_lifted(probed, system):
    code, errors = interrupted(['sweep', '--namespace', 'left', '--speed', '0.005'],
                               'in contact', system)
    assert code == 130
    assert 'sweep: the goal ended canceled' in errors
    assert errors.rstrip().endswith('error: stopped by SIGINT')


def test_ctrl_c_cancels_the_probe_goal_before_the_command_ends(probed, system):
    code, errors = interrupted(['probe', '--namespace', 'left', '--start', '0.12', '0',
                                '0.018', '--span', '0.03'], 'descending', system)
    assert code == 130
    assert 'probe: canceling the goal' in errors
    assert 'probe: the goal ended canceled' in errors
    assert errors.rstrip().endswith('error: stopped by SIGINT')
    assert 'probe goal canceled' in (system / 'probe.log').read_text()
    pathway = json.loads((system / 'pathway.json').read_text())
    assert len(pathway['probes']) == 3  # canceled before a contact: the last pathway stays


def test_a_short_pathway_on_the_rising_flank_is_swept_to_the_end(system):
    """Probed at x = 0.14-0.16 m, where the arm rests sagged below the goal its servos hold.

    The sweep's goal steps the arm by that sag as it arrives; the sweep node took the step
    for the arm leaving its start, ran its clock 0.37 s early, and aborted in the lift
    ('the edge is 10.1 mm from where it is commanded ... (lift; tolerance 10 mm)').
    """
    probe = tactex('probe', '--namespace', 'left', '--start', '0.14', '0', '0.018', '--span',
                   '0.02')
    assert probe.returncode == 0, probe.stdout + probe.stderr
    run = tactex('sweep', '--namespace', 'left')
    assert run.returncode == 0, run.stdout + run.stderr + (system / 'sweep.log').read_text()
    assert run.stdout.startswith('sweep goal succeeded\n')
    speed = float(run.stdout.split('sliding speed ')[1].split()[0])
    assert abs(speed - 15.0) < 1.5, run.stdout
