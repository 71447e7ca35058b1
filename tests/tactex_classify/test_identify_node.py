# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""identify_node in simulation: `tactex identify` chooses movements and drives the sweep action.

The simulator, Madgwick, probe_node, sweep_node and identify_node run as processes under
/left, as `tactex launch system sim:=true bundle:=...` starts them. The bundle is trained on
the small three-movement dataset of tests/support/movement_data.py (its models know noise,
not the simulator's textures: these tests check the action, bench/bench_identify_live.py
measures the accuracy). The movement file makes tells_all slide 100 mm, longer than the
40 mm probed pathway, so only tells_wood (20 mm) and tells_nothing (15 mm) can run, each
with 12.6 mm of speed ramps around its contact. Two more identify_nodes have no sweep
server: under /right one that gives up after 2 s, under /patient one that would wait
120 s (a cancel must end that wait at once).
"""

import json
import math
from pathlib import Path
import re
import signal
import subprocess
import sys
import time
from types import SimpleNamespace

from action_msgs.msg import GoalStatus
from action_msgs.srv import CancelGoal
import pytest
from support.movement_data import movement_dataset, movement_file
from support.processes import running_nodes, stop, tactex, wait_for

from tactex.cli import main
from tactex.goal_client import canceled_end
from tactex.launching.environment import ros_environment
from tactex_msgs.action import Identify

pytestmark = [pytest.mark.integration, pytest.mark.ros, pytest.mark.slow]
BIN = Path(sys.executable).parent
CONFIG = Path(__file__).resolve().parents[2] / 'config'
SIM_TIME = ['-p', 'use_sim_time:=true']
CONTACT_S = (5.0, 1.0, 0.75)  # at 20 mm/s: 100, 20 and 15 mm (+ 12.6 mm of speed ramps)
PATIENT_S = 120.0  # how long /patient's identify_node waits for a sweep server


def node(name: str, namespace: str, *parameters: str) -> list:
    """The command line of a node under `namespace` with its config file and `parameters`."""
    package_config = {'madgwick_node': 'sensor.yaml', 'probe_node': 'probe.yaml',
                      'sweep_node': 'sweep.yaml', 'identify_node': 'identify.yaml'}
    return [BIN / name, '--ros-args', '-r', f'__ns:=/{namespace}', '--params-file',
            CONFIG / package_config[name], *SIM_TIME, *parameters]


@pytest.fixture(scope='module')
def bundle(tmp_path_factory):
    """(bundle folder, movement file) trained on the three-movement dataset."""
    folder = tmp_path_factory.mktemp('bundle')
    movement_dataset(folder)
    movements = movement_file(folder, contact_s=CONTACT_S)
    assert main(['train', str(folder / 'data.npz'), '--movements', str(movements),
                 '--model', 'extratrees', '--folds', '2', '--out', str(folder / 'run')]) == 0
    return folder / 'run' / 'bundle', movements


@pytest.fixture(scope='module')
def system(tmp_path_factory, bundle):
    """The system in simulation under /left, probed along 40 mm; its folder (logs, pathway)."""
    folder = tmp_path_factory.mktemp('system')
    bundle_folder, movements = bundle
    identify = ['-p', f'bundle:={bundle_folder}', '-p', f'movements:={movements}']
    commands = {
        'bridge': [BIN / 'mujoco_bridge', '--ros-args', '-r', '__ns:=/left', '-p',
                   'scene:=uneven_texture', '-p', 'rate_factor:=0.5'],
        'madgwick': node('madgwick_node', 'left'),
        'probe': node('probe_node', 'left', '-p', f'pathway_file:={folder / "pathway.json"}'),
        'sweep': node('sweep_node', 'left', '-p', f'recording_root:={folder / "recordings"}'),
        'identify': node('identify_node', 'left', *identify),
        # No sweep node under /right: its goals meet no sweep server.
        'lonely': node('identify_node', 'right', *identify, '-p', 'server_timeout_s:=2.0'),
        'patient': node('identify_node', 'patient', *identify, '-p',
                        f'server_timeout_s:={PATIENT_S}'),
    }
    with running_nodes(commands, folder):
        probe = tactex('probe', '--namespace', 'left', '--start', '0.10', '0', '0.018',
                       '--span', '0.04')
        assert probe.returncode == 0, probe.stdout + probe.stderr
        yield folder


def test_identify_runs_the_movements_that_fit_the_pathway_and_reports_each(system):
    run = tactex('identify', '--namespace', 'left', '--policy', 'round-robin', '--threshold',
                 '1', '--budget-movements', '2')
    log = (system / 'identify.log').read_text()[-3000:]
    assert run.returncode == 0, run.stdout + run.stderr + log
    lines = run.stdout.splitlines()
    assert lines[0] == 'identify goal succeeded: undecided', run.stdout
    movements = lines[1].split('movements: ')[1].split(', ')
    assert [m.split()[0] for m in movements] == ['tells_wood', 'tells_nothing'], run.stdout
    assert all(int(m.split('(')[1].split()[0]) >= 1 for m in movements), run.stdout
    assert lines[2].startswith('  belief: ') and lines[2].count('%') == 3, run.stdout
    contact = float(lines[3].split()[0])
    assert 1.5 < contact < 2.5, run.stdout  # 1 s and 0.75 s at speed
    assert lines[4] == '  stopped: movement budget'
    bar = run.stderr.replace('\r', '\n')
    assert 'tells_wood: ' in bar and 'tells_nothing: ' in bar, bar


def test_a_goal_without_a_fitting_movement_is_refused_with_both_lengths(system, tmp_path):
    short = tmp_path / 'short.json'
    data = json.loads((system / 'pathway.json').read_text())
    data['probes'] = data['probes'][:2]  # about 10 mm: shorter than every movement
    short.write_text(json.dumps(data))
    first, second = (probe['position'] for probe in data['probes'])
    length_mm = 1e3 * math.dist(first, second)  # the 1 cm step, tilted by the surface
    run = tactex('identify', '--namespace', 'left', '--pathway', str(short))
    assert run.returncode == 1
    assert run.stdout.startswith(f'identify goal aborted (refused: the pathway is '
                                 f'{length_mm:.0f} mm long; '
                                 'the shortest movement needs 28 mm (its contact and speed '
                                 'ramps): probe a longer pathway)'), run.stdout


def test_a_contact_budget_shorter_than_every_movement_is_refused(system):
    run = tactex('identify', '--namespace', 'left', '--budget-seconds', '0.5')
    assert run.returncode == 1
    assert run.stdout.startswith('identify goal aborted (refused: budget_seconds 0.5 is shorter '
                                 'than every movement: the shortest contact lasts 0.75 s; give '
                                 'at least that)'), run.stdout


def test_ctrl_c_cancels_the_running_sweep_and_the_goal(system):
    sweep_log = system / 'sweep.log'
    planned = sweep_log.read_text().count('planned in')
    errors = system / 'interrupted.err'
    with open(errors, 'w') as sink:
        process = subprocess.Popen([BIN / 'tactex', 'identify', '--namespace', 'left',
                                    '--threshold', '1'], stdout=subprocess.DEVNULL,
                                   stderr=sink, env=ros_environment())
        try:
            assert wait_for(lambda: sweep_log.read_text().count('planned in') > planned, 120)
            time.sleep(2.0)  # the sweep is under way
            process.send_signal(signal.SIGINT)
            code = process.wait(timeout=120)
        finally:
            stop([process])
    text = errors.read_text()
    assert code == 130, text
    assert 'identify: the goal ended canceled (' in text, text
    assert text.rstrip().endswith('error: stopped by SIGINT')
    assert 'canceled: the edge was lifted off' in sweep_log.read_text().split('planned in')[-1]


def test_without_a_sweep_server_the_goal_is_aborted_with_the_reason(system):
    run = tactex('identify', '--namespace', 'right', '--pathway',
                 str(system / 'pathway.json'))
    assert run.returncode == 1
    assert re.match(r'identify goal aborted \((tells_wood|tells_nothing): no sweep action '
                    r'server within 2 s: is sweep_node running in this namespace\?\)',
                    run.stdout), run.stdout


def test_a_cancel_ends_the_wait_for_the_sweep_server_and_the_goal_is_canceled(system):
    from tactex.commands.sweep import pathway_of
    from tactex.goal_client import spinning
    from tactex.ros_client import client_node
    from tactex_common.goals import GoalSender
    goal = Identify.Goal(policy='round-robin', threshold=1.0,
                         pathway=pathway_of(system / 'pathway.json'))
    with client_node('identify_cancel_test') as (ros_node, executor), spinning(executor):
        sender = GoalSender(ros_node, Identify, '/patient/identify')
        assert sender.client.wait_for_server(timeout_sec=60.0)
        handle = sender.answer(goal, answer_s=5.0, timeout_s=60.0)
        assert handle is not None and handle.accepted
        result = handle.get_result_async()
        time.sleep(1.0)  # the goal waits for the sweep server
        assert not result.done()
        handle.cancel_goal_async()
        # Well under the node's 120 s wait for a sweep server, which it used to sit out.
        assert wait_for(result.done, PATIENT_S / 2), 'the cancel was not noticed'
        ended = result.result()
    log = (system / 'patient.log').read_text()[-3000:]
    assert ended.status == GoalStatus.STATUS_CANCELED, (ended.status, ended.result.message, log)
    assert re.fullmatch(r'(tells_wood|tells_nothing): canceled before the sweep started',
                        ended.result.message), ended.result.message
    assert ended.result.movements == [] and ended.result.contact_seconds == 0.0


def test_past_its_timeout_identify_cancels_the_goal_and_says_it_was_canceled(system):
    run = tactex('identify', '--namespace', 'patient', '--pathway',
                 str(system / 'pathway.json'), '--timeout', '2')
    assert run.returncode == 1, run.stdout + run.stderr
    errors = [line for line in run.stderr.splitlines() if line.startswith('error:')]
    assert errors == ['error: the identify goal did not finish within 2 s (--timeout); it was '
                      'canceled'], run.stderr
    assert 'Traceback' not in run.stdout + run.stderr
    assert wait_for(lambda: 'identify goal cancel: ' in (system / 'patient.log').read_text(),
                    10), (system / 'patient.log').read_text()[-3000:]
    assert 'identify goal abort' not in (system / 'patient.log').read_text()


def test_the_launch_the_no_server_error_suggests_starts_identify_node(bundle):
    run = tactex('identify', '--namespace', 'nowhere', '--server-timeout', '1')
    assert run.returncode == 1
    suggested = re.search(r'`tactex launch ([^`]+)`', run.stderr)
    assert suggested, run.stderr
    # The bundle was trained for its own movement file, which the launch is then given
    # (with the shipped one, the launch check refuses the bundle, as identify_node would).
    arguments = suggested[1].replace('RUN/bundle', str(bundle[0])).split()
    printed = tactex('launch', '--print', *arguments, f'movements:={bundle[1]}')
    assert printed.returncode == 0, printed.stdout + printed.stderr
    assert 'identify_node' in printed.stdout and 'sweep_node' in printed.stdout


class Done:
    """A future that is done with `value`."""

    def __init__(self, value) -> None:
        self.value = value

    def done(self) -> bool:
        return True

    def result(self):
        return self.value


class Pending:
    """A future never done."""

    def done(self) -> bool:
        return False


class Handle:
    """A goal handle whose cancel is answered with `return_code`; it records the call."""

    def __init__(self, return_code: int) -> None:
        self.return_code, self.canceled = return_code, False

    def cancel_goal_async(self) -> Done:
        self.canceled = True
        return Done(CancelGoal.Response(return_code=self.return_code))


def finished(status: int, message: str = '') -> Done:
    """A done result future of a goal that ended with `status` and `message`."""
    return Done(SimpleNamespace(status=status, result=Identify.Result(message=message)))


@pytest.mark.parametrize('cancel, result, said', [
    (CancelGoal.Response.ERROR_NONE, finished(GoalStatus.STATUS_CANCELED, 'tells_wood: canceled'),
     'it was canceled'),
    (CancelGoal.Response.ERROR_GOAL_TERMINATED,
     finished(GoalStatus.STATUS_ABORTED, 'tells_wood: no sweep action server within 2 s'),
     'asked to cancel, it ended aborted (tells_wood: no sweep action server within 2 s)'),
    (CancelGoal.Response.ERROR_GOAL_TERMINATED, finished(GoalStatus.STATUS_SUCCEEDED),
     'asked to cancel, it ended succeeded'),
    (CancelGoal.Response.ERROR_REJECTED, Pending(),
     'the node refused to cancel it: it may still be running'),
    (CancelGoal.Response.ERROR_NONE, Pending(),
     'the node did not end it within 0.2 s of the cancel; the node log says why'),
])
def test_a_timed_out_goal_is_reported_as_it_really_ended(cancel, result, said):
    handle = Handle(cancel)
    assert canceled_end(handle, result, timeout_s=0.2) == said
    assert handle.canceled


@pytest.mark.parametrize('parameters, said', [
    ([], 'parameter bundle is empty: give identification bundle'),
    (['movements:={config}/movements.yaml'], 'the bundle holds movements tells_all, tells_wood, '
     'tells_nothing; the movement file lists slow_light'),
    (['movements:={folder}/nothing.yaml'], 'nothing.yaml'),
])
def test_a_bundle_it_cannot_use_stops_the_node_with_one_line(bundle, tmp_path, parameters, said):
    bundle_folder, movements = bundle
    given = {'bundle': str(bundle_folder), 'movements': str(movements)}
    for parameter in parameters:
        name, value = parameter.split(':=')
        given[name] = value.format(config=CONFIG, folder=tmp_path)
    if not parameters:
        del given['bundle']  # left at its default, ''
    argv = [BIN / 'identify_node', '--ros-args',
            *[item for name, value in given.items() for item in ('-p', f'{name}:={value}')]]
    run = subprocess.run(argv, capture_output=True, text=True, env=ros_environment(),
                         timeout=60)
    output = run.stdout + run.stderr
    assert run.returncode == 1, output
    assert said in output and 'Traceback' not in output, output
