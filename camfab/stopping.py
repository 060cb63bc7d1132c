"""Signals that stop camfab: caught from the program's first instruction, raised where the
program is, and put off while code runs that an exception must not break into.

camfab's handlers of Ctrl-C, SIGTERM and SIGHUP (:func:`catch`, installed by
:mod:`camfab.start` before anything else is imported) raise where the program is, so that every
``finally`` and cleanup runs; the command line turns the stop into one line and the status
128 + the signal (130, 143). Some places must not see that raise: a library half imported (its
objects half made, which complain as they are collected), or a native library's call that runs
Python inside it (an exception there ends the process). Code in :func:`deferred` has a stop
noted instead, and raised as the block ends; the handler asks :func:`defer` whether to wait. A
stop still comes within the block's time (a fraction of a second) and ends camfab as any other.
"""

from __future__ import annotations

import os
import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

#: The signals that stop camfab (Ctrl-C, SIGTERM, SIGHUP), by name.
STOPPING = ("SIGINT", "SIGTERM", "SIGHUP")


class Interrupted(BaseException):
    """A signal asking camfab to stop (SIGTERM, SIGHUP): raised where the program is, so that
    every ``finally`` and cleanup runs, as Ctrl-C's KeyboardInterrupt does."""

    def __init__(self, signum: int) -> None:
        super().__init__(signum)
        self.signum = signum


#: The signals received, noted as well as raised: a library that catches every exception while
#: it is imported (optional imports tried in a ``try``) swallows the raise, not the note.
RECEIVED: list[int] = []

#: How deep the program is in :func:`deferred` blocks, and the stops noted meanwhile.
_DEPTH: list[int] = []
_PENDING: list[int] = []


@contextmanager
def deferred() -> Iterator[None]:
    """Put off the stopping signals until the block ends; then the first one noted is raised
    again (by :func:`signal.raise_signal`, so its handler raises at the block's end)."""
    _DEPTH.append(1)
    try:
        yield
    finally:
        if _DEPTH:  # (empty in a process forked inside the block: see _forget)
            _DEPTH.pop()
        if not _DEPTH and _PENDING:
            signum = _PENDING[0]
            _PENDING.clear()
            signal.raise_signal(signum)


def _forget() -> None:
    """In a process forked inside a :func:`deferred` block (a batch's worker): its own stops
    are not put off, and those the parent had noted are not its own."""
    _DEPTH.clear()
    _PENDING.clear()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget)


def defer(signum: int) -> bool:
    """True, with *signum* noted, when the program is in a :func:`deferred` block: the
    handler then returns and the block's end raises the signal again."""
    if _DEPTH:
        _PENDING.append(signum)
        return True
    return False


def raise_interrupted(signum: int, frame: Any) -> None:
    """The handler of the stopping signals: note *signum*, then raise KeyboardInterrupt (Ctrl-C)
    or :class:`Interrupted` where the program is, unless it is put off (:func:`deferred`) or
    the program is where Python would print and drop the exception.

    It imports nothing: a signal can come inside the import system's lock (between its note
    of the thread that waits and the removal of that note), and an import run there by the
    handler takes and drops the note first, so the lock's own cleanup fails with a KeyError."""
    if signum not in RECEIVED:
        RECEIVED.append(signum)
    if defer(signum):  # raised again where the code that must not be broken into ends
        return
    if _ignores_exceptions(frame):
        # raised here it would be printed as "Exception ignored" and lost: deliver the signal
        # again in a moment, when the main thread is back in ordinary code
        timer = threading.Timer(0.02, signal.pthread_kill,
                                (threading.main_thread().ident, signum))
        timer.daemon = True
        timer.start()
        return
    if signum == signal.SIGINT:
        raise KeyboardInterrupt
    raise Interrupted(signum)


def _ignores_exceptions(frame: Any) -> bool:
    """True when *frame* runs where Python prints and drops an exception: the import system's
    callbacks, and the logging module's fork hooks (a library starting a subprocess)."""
    if frame is None:
        return False
    code = frame.f_code
    return (code.co_filename.startswith("<frozen importlib")
            or code.co_name in ("_releaseLock", "_acquireLock", "_at_fork_reinit",
                                "_after_at_fork_child_reinit_locks"))


def catch() -> None:
    """Ctrl-C, SIGTERM and SIGHUP raise where the program is (unless they are ignored, as in a
    shell's background job) and are noted in :data:`RECEIVED`."""
    if signal.getsignal(signal.SIGINT) in (signal.default_int_handler, raise_interrupted):
        signal.signal(signal.SIGINT, raise_interrupted)
    for name in STOPPING[1:]:
        number = getattr(signal, name, None)
        if number is not None and signal.getsignal(number) in (signal.SIG_DFL,
                                                                raise_interrupted):
            signal.signal(number, raise_interrupted)


def stop_line(signum: int) -> str:
    """The one line a stop by *signum* prints."""
    return ("camfab: interrupted" if signum == signal.SIGINT else
            f"camfab: stopped by signal {signum}")


@contextmanager
def signals_held() -> Iterator[None]:
    """Hold the signals that stop camfab for the block (they come, in order, as it ends): for
    work that must be done whole or not at all — a set of files renamed into place, a pool of
    workers set up (a stop raised inside ``submit``, between forking the workers and starting
    the thread that feeds them, leaves workers that wait for work forever).

    The signals are blocked in this thread, and camfab's handler puts them off too
    (:func:`deferred`): a signal blocked here goes to another thread of the process that does
    not block it (numpy's BLAS, manifold3d's workers), whose handler has this thread run
    Python's handler of it all the same. Only this thread's mask changes: never a handler."""
    with deferred():
        if not hasattr(signal, "pthread_sigmask"):
            yield
            return
        held = {getattr(signal, name) for name in STOPPING if hasattr(signal, name)}
        old = signal.pthread_sigmask(signal.SIG_BLOCK, held)
        try:
            yield
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, old)


def hold_to_the_end() -> int | None:
    """Hold the stopping signals for the rest of the process (its exit and the interpreter's
    shutdown, when Python's own handlers are gone and a signal would kill it without a word),
    and return the first one that came meanwhile or was noted (None: none).

    For the ``camfab`` program's main thread alone (it sets handlers): from here on camfab's
    handler notes a stop and returns (:func:`deferred`, never ended); the signals are blocked
    in this thread; those that came are noted, then ignored (``SIG_IGN``, which the
    interpreter's shutdown keeps, in every thread: a thread of a native library that does not
    block them would otherwise die of one, and the process with it)."""
    _DEPTH.append(1)  # first: a stop from here on is noted, not raised
    held = {getattr(signal, name) for name in STOPPING if hasattr(signal, name)}
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_BLOCK, held)
        pending = sorted(signal.sigpending() & held)
        if pending and not RECEIVED:
            RECEIVED.append(pending[0])
    for number in sorted(held):
        if signal.getsignal(number) is raise_interrupted:  # (checks for a stop first)
            signal.signal(number, signal.SIG_IGN)
    _PENDING.clear()
    return RECEIVED[0] if RECEIVED else None
