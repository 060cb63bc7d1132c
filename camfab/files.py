"""Reading input files within bounds.

A path on the command line may name anything: a pipe that blocks until someone writes to it, a
device that never ends (``/dev/zero``), a folder, a file of gigabytes. Inputs are read only when
they are regular files no larger than the reader's limit, and then at most that many bytes (a
file that grows while it is read is refused too), so a bad path is refused at once instead of
hanging or filling the memory.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from camfab.errors import InputFileError

#: Flags of the one open of an input file: read only, and without blocking, so that opening a
#: pipe with no writer returns at once (to be refused); the flags a platform lacks are left out.
_OPEN_FLAGS = (os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0)
               | getattr(os, "O_BINARY", 0))


def read_bounded(path: Path, limit: int, what: str) -> bytes:
    """The bytes of the regular file *path*, at most *limit* of them.

    Parameters
    ----------
    limit
        Largest size accepted (bytes).
    what
        What the file should be, for messages ("a DXF or CSV outline").

    Raises
    ------
    InputFileError
        The file is missing, unreadable, a folder, not a regular file, or larger than *limit*.
    """
    name = str(path)
    try:
        fd = os.open(path, _OPEN_FLAGS)
    except FileNotFoundError:
        raise InputFileError(name, "no such file") from None
    except IsADirectoryError:
        raise InputFileError(name, f"is a folder, not {what}") from None
    except (OSError, ValueError) as exc:  # ValueError: a NUL in the name
        raise InputFileError(name, f"cannot be read ({getattr(exc, 'strerror', None) or exc})"
                             ) from None
    try:
        _check_regular(name, os.fstat(fd), limit, what)
    except InputFileError:
        os.close(fd)
        raise
    with os.fdopen(fd, "rb") as stream:
        try:
            data = stream.read(limit + 1)
        except OSError as exc:
            raise InputFileError(name, f"cannot be read ({exc.strerror or exc})") from None
    if len(data) > limit:  # it grew since it was looked at
        raise InputFileError(name, f"is larger than {limit:,} bytes; {what} is at most that")
    return data


def check_bounded(path: Path, limit: int, what: str) -> None:
    """Refuse *path* unless it is a regular file of at most *limit* bytes (for files another
    reader then reads). Raises :class:`InputFileError` as :func:`read_bounded` does."""
    name = str(path)
    try:
        info = os.stat(path)
    except FileNotFoundError:
        raise InputFileError(name, "no such file") from None
    except (OSError, ValueError) as exc:
        raise InputFileError(name, f"cannot be read ({getattr(exc, 'strerror', None) or exc})"
                             ) from None
    _check_regular(name, info, limit, what)


def _check_regular(name: str, info: os.stat_result, limit: int, what: str) -> None:
    if stat.S_ISDIR(info.st_mode):
        raise InputFileError(name, f"is a folder, not {what}")
    if not stat.S_ISREG(info.st_mode):
        raise InputFileError(name, f"is not a regular file (a pipe, device or socket); {what} "
                             "must be a file")
    if info.st_size > limit:
        raise InputFileError(name, f"is {info.st_size:,} bytes; {what} is at most {limit:,}")
