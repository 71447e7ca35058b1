# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex watch`: live estimates with their evidence and decisions, without the ros2 CLI."""

from pathlib import Path
import subprocess
import sys
import time

import pytest
from support.processes import stop

from tactex.launching.environment import ros_environment

BIN = Path(sys.executable).parent


def estimate(decided: bool, confidence: float):
    from tactex_msgs.msg import TextureEstimate
    return TextureEstimate(label='wood', class_id=1, confidence=confidence,
                           class_names=['cork', 'wood'],
                           probabilities=[1 - confidence, confidence], decided=decided,
                           contact_seconds=2.5, windows_used=4)


def test_an_estimate_reads_as_leader_runner_up_evidence_and_verdict():
    from tactex.commands.watch import line
    assert line(estimate(False, 0.75)) == ('deciding  wood 75.0 %, then cork 25.0 %; '
                                           '4 windows, 2.5 s of contact')
    assert line(estimate(True, 0.995)).startswith('DECIDED   wood 99.5 %')


@pytest.mark.integration
@pytest.mark.ros
def test_watch_shows_the_estimates_of_its_namespace_and_stops_after_count(ros_context):
    import rclpy

    from tactex_common.ros import COMMAND
    from tactex_msgs.msg import TextureEstimate
    node = rclpy.create_node('fake_classifier', namespace='left', context=ros_context)
    publisher = node.create_publisher(TextureEstimate, 'texture/estimate', COMMAND)
    watch = subprocess.Popen([BIN / 'tactex', 'watch', '--namespace', 'left', '--count', '3',
                              '--timeout', '60'], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, env=ros_environment())
    try:
        deadline, sent = time.monotonic() + 60, 0
        while watch.poll() is None and time.monotonic() < deadline:
            publisher.publish(estimate(sent % 3 == 2, 0.6 + 0.1 * (sent % 3)))
            sent += 1
            time.sleep(0.3)
        out, err = watch.communicate(timeout=10)
    finally:
        stop([watch])
        node.destroy_node()
    assert watch.returncode == 0, err
    lines = out.splitlines()
    assert len(lines) == 3 and all('wood' in text and '4 windows' in text for text in lines)
    for text in lines:  # every third estimate sent (at 80 %) is a decision
        assert text.startswith('DECIDED' if 'wood 80.0 %' in text else 'deciding'), text


def test_watch_names_the_topic_when_no_estimate_comes():
    result = subprocess.run([BIN / 'tactex', 'watch', '--namespace', 'nobody', '--timeout',
                             '1'], capture_output=True, text=True, env=ros_environment(),
                            timeout=60)
    assert result.returncode == 1
    assert result.stderr.startswith('error: no estimate on /nobody/texture/estimate for 1 s')
