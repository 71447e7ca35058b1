# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""A command that is stopped says by which signal, in one line, whoever raised the interrupt.

Ray (tactex compare, sim collect --workers) catches the `Stopped` our handler raises
inside its wait and raises a bare KeyboardInterrupt in its place: the command must still
end with `error: stopped by SIG...`, the shell's code for that signal, and no traceback.
"""

import os
import signal

import pytest

from tactex.cli import guarded
from tactex_common import stopping
from tactex_common.stopping import as_stopped, raise_on_stop_signals, Stopped


@pytest.fixture
def stop_handlers():
    """The command's stop handlers for the test, Python's afterwards."""
    previous = {signum: signal.getsignal(signum)
                for signum in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)}
    raise_on_stop_signals()
    yield
    for signum, handler in previous.items():
        signal.signal(signum, handler)


def swallowing_library(signum: int):
    """A library call that, like Ray's wait, turns the stop into a bare KeyboardInterrupt."""
    def run():
        try:
            os.kill(os.getpid(), signum)
            signal.sigtimedwait([], 0.1)  # let the handler run
        except Stopped:
            raise KeyboardInterrupt from None
        raise AssertionError('the signal never arrived')
    return run


@pytest.mark.parametrize('signum', [signal.SIGINT, signal.SIGTERM, signal.SIGHUP],
                         ids=lambda s: s.name)
def test_a_stop_a_library_re_raised_as_a_bare_interrupt_is_reported_as_its_signal(
        stop_handlers, signum, capsys):
    assert guarded(swallowing_library(signum)) == 128 + signum
    assert capsys.readouterr().err == f'error: stopped by {signal.Signals(signum).name}\n'


def test_our_own_stop_is_reported_as_it_is(stop_handlers, capsys):
    def stopped():
        raise Stopped(signal.SIGTERM)
    assert guarded(stopped) == 128 + signal.SIGTERM
    assert capsys.readouterr().err == 'error: stopped by SIGTERM\n'


def test_an_interrupt_when_no_stop_signal_arrived_is_ctrl_c(monkeypatch):
    monkeypatch.setattr(stopping, '_received', [])
    assert as_stopped(KeyboardInterrupt()).signum == signal.SIGINT
    fresh = Stopped(signal.SIGHUP)
    assert as_stopped(fresh) is fresh
