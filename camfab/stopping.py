"""Signals that stop camfab, put off while code runs that an exception must not break into.

camfab's handlers of Ctrl-C, SIGTERM and SIGHUP (:mod:`camfab.cli`) raise where the program
is. Some places must not see that raise: a library half imported (its objects half made, which
complain as they are collected), or a native library's call that runs Python inside it (an
exception there ends the process). Code in :func:`deferred` has a stop noted instead, and
raised as the block ends; the handler asks :func:`defer` whether to wait. A stop still comes
within the block's time (a fraction of a second) and ends camfab as any other.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

#: How deep the program is in :func:`deferred` blocks, and the stops noted meanwhile.
_DEPTH: list[int] = []
_PENDING: list[int] = []


@contextmanager
def deferred() -> Iterator[None]:
    """Put off the stopping signals until the block ends; then the first one noted is raised
    again (by :func:`signal.raise_signal`, so its handler raises at the block's end)."""
    import signal

    _DEPTH.append(1)
    try:
        yield
    finally:
        _DEPTH.pop()
        if not _DEPTH and _PENDING:
            signum = _PENDING[0]
            _PENDING.clear()
            signal.raise_signal(signum)


def defer(signum: int) -> bool:
    """True, with *signum* noted, when the program is in a :func:`deferred` block: the
    handler then returns and the block's end raises the signal again."""
    if _DEPTH:
        _PENDING.append(signum)
        return True
    return False
