# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex_common.ros.spin`: a node stops on a signal, and a failing callback fails the node."""

import os
import signal
import threading

import pytest

pytestmark = pytest.mark.ros


def test_a_callback_that_raises_fails_the_node_as_if_it_spun_in_the_main_thread():
    import rclpy.node

    from tactex_common.ros import spin

    def make_node():
        node = rclpy.node.Node('spin_test_failing')

        def fail():
            raise RuntimeError('callback failed')
        node.create_timer(0.01, fail)
        return node

    with pytest.raises(RuntimeError, match='callback failed'):
        spin(make_node, [])


def test_a_stop_signal_ends_the_spin_and_restores_the_handlers():
    import rclpy.node

    from tactex_common.ros import spin

    before = signal.getsignal(signal.SIGHUP)
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGHUP))
    timer.start()
    try:
        spin(lambda: rclpy.node.Node('spin_test_stopping'), [])
    finally:
        timer.cancel()
    assert signal.getsignal(signal.SIGHUP) == before
