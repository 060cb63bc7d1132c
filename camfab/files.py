"""Reading the files a user names: regular files only, of bounded size.

A design, a table law's CSV, an outline to inspect or a follower file is read whole into memory.
A path to a device (``/dev/zero``, ``/dev/urandom``), a FIFO or a socket would never end or never
start; a huge file would exhaust memory. :func:`read_limited` refuses them before reading: it
checks what the path is without opening it (opening a FIFO blocks until a writer comes), opens it
without blocking, checks again what was opened, and reads at most the limit.
"""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path


class FileRefused(OSError):
    """A path that is not a readable regular file within the limit; ``reason`` says why in a few
    words that fit after the file's name (``"is a FIFO, not a file"``)."""

    def __init__(self, reason: str) -> None:
        super().__init__(reason)
        self.reason = reason


_KINDS = ((stat.S_ISDIR, "is a folder, not a file"),
          (stat.S_ISFIFO, "is a FIFO (a pipe), not a file"),
          (stat.S_ISCHR, "is a device, not a file"),
          (stat.S_ISBLK, "is a device, not a file"),
          (stat.S_ISSOCK, "is a socket, not a file"))


def _kind_problem(mode: int) -> str | None:
    for test, reason in _KINDS:
        if test(mode):
            return reason
    return None if stat.S_ISREG(mode) else "is not a regular file"


def read_limited(path: str | Path, limit: int, what: str = "file") -> bytes:
    """The bytes of the regular file at *path*, which may hold at most *limit* bytes.

    Parameters
    ----------
    path
        The file; symbolic links are followed.
    limit
        The largest size accepted, in bytes.
    what
        How the reason names the file when it is too large (``"a design file"``).

    Raises
    ------
    FileRefused
        Missing, unreadable, not a regular file, or larger than *limit*; ``reason`` says which.
    """
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        raise FileRefused("no such file") from None
    except OSError as exc:
        raise FileRefused(f"cannot be read ({exc.strerror or exc})") from None
    problem = _kind_problem(mode)
    if problem is not None:
        raise FileRefused(problem)
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0)
    try:
        fd = os.open(path, flags)
    except OSError as exc:
        if exc.errno == errno.ENOENT:
            raise FileRefused("no such file") from None
        raise FileRefused(f"cannot be read ({exc.strerror or exc})") from None
    try:
        info = os.fstat(fd)
        problem = _kind_problem(info.st_mode)  # replaced between the stat and the open
        if problem is not None:
            raise FileRefused(problem)
        if info.st_size > limit:
            raise FileRefused(f"is {info.st_size:,} bytes; {what} is at most {limit:,}")
        chunks = []
        size = 0
        while size <= limit:  # a file growing while read stops at the limit too
            chunk = os.read(fd, min(1 << 20, limit + 1 - size))
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
    except OSError as exc:
        if isinstance(exc, FileRefused):
            raise
        raise FileRefused(f"cannot be read ({exc.strerror or exc})") from None
    finally:
        os.close(fd)
    if size > limit:
        raise FileRefused(f"is over {limit:,} bytes; {what} is at most {limit:,}")
    return b"".join(chunks)
