"""A stop that arrives where code must not be broken into (a library half imported, manifold3d
at work) waits for the end of that code, then stops camfab as any other."""

from __future__ import annotations

import signal

import pytest

from camfab import cli, stopping
from camfab.stopping import deferred


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_a_stop_inside_a_deferred_block_is_raised_at_its_end(monkeypatch, signum: int) -> None:
    stopping.RECEIVED.clear()
    old = signal.signal(signum, stopping.raise_interrupted)
    reached = []
    try:
        with pytest.raises((cli.Interrupted, KeyboardInterrupt)) as caught, deferred():
            signal.raise_signal(signum)
            reached.append("after the signal")
            with deferred():  # an inner block does not raise it: the outer one does
                pass
            reached.append("after the inner block")
    finally:
        signal.signal(signum, old)
    assert reached == ["after the signal", "after the inner block"]
    assert stopping.RECEIVED == [signum]
    if signum == signal.SIGTERM:
        assert isinstance(caught.value, cli.Interrupted) and caught.value.signum == signum


def test_outside_a_deferred_block_a_stop_raises_where_the_program_is(monkeypatch) -> None:
    stopping.RECEIVED.clear()
    old = signal.signal(signal.SIGTERM, stopping.raise_interrupted)
    reached = []
    try:
        with pytest.raises(cli.Interrupted):
            signal.raise_signal(signal.SIGTERM)
            reached.append("after the signal")
        with deferred():
            reached.append("a block without a stop ends quietly")
    finally:
        signal.signal(signal.SIGTERM, old)
    assert reached == ["a block without a stop ends quietly"]
