"""The ``camfab`` program's first instructions (its entry point, and ``python -m camfab``).

The stopping signals (Ctrl-C, SIGTERM, SIGHUP) are caught before anything else is imported
(:func:`camfab.stopping.catch`): a stop while the command line's modules load is the same one
line and status (130, 143) as a stop during a build, not Python's traceback. The standard
streams are then made camfab's (:func:`camfab.terminal.install`): written in any encoding, and
a failure to write standard output (a full disk, a closed stdout, a pipe whose reader is gone)
said at the end in one line with status 74. At the end, the signals are held for the process's
exit (:func:`camfab.stopping.hold_to_the_end`): Python gives up its handlers as it shuts down,
and a signal then would end camfab without a word; one that came after the command's own line
is said the same way.
"""

from __future__ import annotations

import sys


def main() -> None:
    """Run the command line as the ``camfab`` program, and exit with its status."""
    from camfab.stopping import RECEIVED, catch, hold_to_the_end, stop_line

    code: int | None = None
    try:
        catch()  # (a stop while its handlers go in raises here, already noted)
        from camfab import terminal

        terminal.install()
        from camfab.cli import main as command

        code = command.main(prog_name="camfab", standalone_mode=False, process=True)
    except BaseException:
        if not RECEIVED:
            raise
    while True:
        try:
            signum = hold_to_the_end()
            break
        except BaseException:  # a stop raised as it began (noted): hold again
            if not RECEIVED:
                raise
    if signum is not None:
        if code != 128 + signum:  # the stop came after the command's line
            sys.stderr.write(stop_line(signum) + "\n")
            code = 128 + signum
    else:
        from camfab.terminal import CANNOT_WRITE, failure, failure_line

        failed = failure()
        if failed is not None:
            sys.stderr.write(failure_line(failed) + "\n")
            code = CANNOT_WRITE
    sys.stdout.flush()
    if RECEIVED:
        _stopped(code)
    sys.exit(code)


def _stopped(code: int | None) -> None:
    """End a process stopped by a signal at once when threads of its own are still at work
    (the studio's build of a version): its command has cleaned up and said its line, and the
    interpreter's shutdown would tear those threads' native objects down under them, which
    manifold3d's bindings report as leaks in a hundred lines on stderr."""
    import os
    import threading

    if threading.active_count() > 1:
        sys.stderr.flush()
        os._exit(code if isinstance(code, int) else 1)
