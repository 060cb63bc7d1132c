"""Reading the files a user names: regular files only, of bounded size.

A path in a design or on the command line may name anything: a FIFO that blocks until someone
writes to it, a device that never ends (``/dev/zero``, ``/dev/urandom``), a folder, a file of
gigabytes. A design, a table law's CSV, an outline to inspect and a follower file are read whole
into memory, so they are read only when they are regular files no larger than the reader's
limit, and then at most that many bytes (a file that grows while it is read is refused too).
What the path is, is checked before it is opened (opening a device may do something), and again
on what was opened, which is opened without blocking.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from camfab.errors import InputFileError

#: Flags of the one open of an input file: read only, and without blocking, so that opening a
#: FIFO with no writer returns at once (to be refused); the flags a platform lacks are left out.
_OPEN_FLAGS = (os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0)
               | getattr(os, "O_BINARY", 0))

#: What a path that is not a regular file is, by the test of its mode.
_KINDS = ((stat.S_ISFIFO, "a FIFO (a pipe)"), (stat.S_ISCHR, "a device"),
          (stat.S_ISBLK, "a device"), (stat.S_ISSOCK, "a socket"))


def read_bounded(path: str | Path, limit: int, what: str) -> bytes:
    """The bytes of the regular file *path* (symbolic links followed), at most *limit* of them.

    Parameters
    ----------
    limit
        Largest size accepted (bytes).
    what
        What the file should be, for messages (``"a design file"``, ``"a DXF or CSV outline"``).

    Raises
    ------
    InputFileError
        The file is missing, unreadable, a folder, not a regular file, or larger than *limit*.
    """
    check_bounded(path, limit, what)
    name = str(path)
    try:
        fd = os.open(path, _OPEN_FLAGS)
    except FileNotFoundError:
        raise InputFileError(name, "no such file") from None
    except (OSError, ValueError) as exc:
        raise InputFileError(name, _unreadable(exc)) from None
    try:
        _check_regular(name, os.fstat(fd), limit, what)  # replaced since it was looked at?
    except InputFileError:
        os.close(fd)
        raise
    with os.fdopen(fd, "rb") as stream:
        try:
            data = stream.read(limit + 1)
        except OSError as exc:
            raise InputFileError(name, _unreadable(exc)) from None
    if len(data) > limit:  # it grew since it was looked at
        raise InputFileError(name, f"is larger than {limit:,} bytes; {what} is at most that")
    return data


def check_bounded(path: str | Path, limit: int, what: str) -> None:
    """Refuse *path* unless it is a regular file of at most *limit* bytes, without opening it
    (for a file another reader then reads). Raises :class:`InputFileError` as
    :func:`read_bounded` does."""
    name = str(path)
    try:
        info = os.stat(path)
    except FileNotFoundError:
        raise InputFileError(name, "no such file") from None
    except (OSError, ValueError) as exc:  # ValueError: a NUL in the name
        raise InputFileError(name, _unreadable(exc)) from None
    _check_regular(name, info, limit, what)


def _check_regular(name: str, info: os.stat_result, limit: int, what: str) -> None:
    if stat.S_ISDIR(info.st_mode):
        raise InputFileError(name, f"is a folder, not {what}")
    if not stat.S_ISREG(info.st_mode):
        kind = next((word for test, word in _KINDS if test(info.st_mode)), "something else")
        raise InputFileError(name, f"is not a regular file but {kind}; {what} must be a file")
    if info.st_size > limit:
        raise InputFileError(name, f"is {info.st_size:,} bytes; {what} is at most {limit:,}")


def _unreadable(exc: Exception) -> str:
    return f"cannot be read ({getattr(exc, 'strerror', None) or exc})"
