"""Writing a set of output files: each to a temporary file first, then all renamed into place, so
an interrupted or failed build (or sweep, or inspection) leaves the earlier set intact.

The set is replaced as a set: the renames run with the stopping signals held
(:func:`~camfab.stopping.signals_held`: blocked in this thread, and put off by camfab's handler
when another thread of the process takes them), so a Ctrl-C or SIGTERM lands before the first
rename (the earlier files stay, the new ones are removed) or after the last (the new set is
whole), never between. A temporary file is noted as it is made (a stop waits for that), and the
temporary files are removed with a second stop put off. Only what no program can put off —
SIGKILL, a power cut — can stop it between two renames (each file still whole, a mix of old and
new); the temporary files such a stop leaves are removed by the next build of the same files. A
folder made for the set is removed again when nothing could be written into it.
"""

from __future__ import annotations

import glob
import os
import secrets
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import BinaryIO

from camfab.errors import OutputError
from camfab.stopping import deferred, signals_held

#: A temporary file older than this (seconds) is stale even when its process id is in use again.
STALE_TEMP_SECONDS = 24 * 3600

_O_BINARY = getattr(os, "O_BINARY", 0)


def write_files(folder: Path, files: Mapping[str, bytes],
                written: Sequence[tuple[Path, Path]] = ()) -> list[Path]:
    """Write *files* (bytes by file name) into *folder* as one set: all to temporary files
    first, then renamed; *written* are temporary files already written (temporary path, final
    path), renamed with them.

    The files get the permissions the umask allows (as any other program's would), not a
    temporary file's private 0600. Temporary files are removed on every way out (an error,
    Ctrl-C, SIGTERM); those a killed build left behind are removed by the next build of the
    same files.

    Raises
    ------
    OutputError
        The folder or a file cannot be written; no file of the set is changed then, and a
        folder made for it is removed again.
    """
    made = make_folder(folder)
    temps = list(written)
    try:
        remove_stale_temps(folder, files)
        for name, data in files.items():
            with deferred():  # a stop comes once the temporary file is made and noted
                temp, stream = open_temp(folder, name)
                temps.append((temp, folder / name))
            with stream:
                stream.write(data)
        for _, final in temps:  # a folder in the way would stop the renames half done
            if final.is_dir():
                raise IsADirectoryError(21, "Is a directory", str(final))
        with signals_held():
            for temp, final in temps:
                os.replace(temp, final)
    except BaseException as exc:
        with deferred():  # a second stop waits for the removal of the temporary files
            for temp, _ in temps:
                temp.unlink(missing_ok=True)
            remove_made(folder, made)
        if isinstance(exc, OSError) and not isinstance(exc, OutputError):
            raise cannot_write(folder, exc) from None
        raise
    return [final for _, final in temps]


def replace_file(path: Path, data: bytes) -> None:
    """Replace the contents of the existing file *path* with *data* as one step: written to a
    temporary file beside it, given the file's own permissions, then renamed over it (the
    stopping signals held), so a reader or a stop sees the old file or the new, never a part.
    The temporary file is removed on every way out.

    Raises
    ------
    OutputError
        The file cannot be written; it is unchanged then.
    """
    import stat

    folder = path.parent
    temp: Path | None = None
    try:
        mode = stat.S_IMODE(os.stat(path).st_mode)
        with deferred():  # a stop comes once the temporary file is made and noted
            temp, stream = open_temp(folder, path.name)
        with stream:
            stream.write(data)
        os.chmod(temp, mode)
        with signals_held():
            os.replace(temp, path)
        temp = None
    except OSError as exc:
        raise OutputError(f"{path}: cannot write the design file ({exc.strerror or exc})"
                          ) from None
    finally:
        if temp is not None:
            with deferred():
                temp.unlink(missing_ok=True)


def cannot_write(folder: Path, exc: OSError) -> OutputError:
    """The one line for a write that failed: ``FOLDER: cannot write the outputs (reason)``."""
    reason = exc.strerror or str(exc) or type(exc).__name__
    return OutputError(f"{folder}: cannot write the outputs ({reason})")


def make_folder(folder: Path) -> Path | None:
    """Make *folder* and the folders above it that are missing; the topmost one it made (None
    when *folder* was there). Raises :class:`OutputError`."""
    top = None
    for above in (folder, *folder.parents):
        if above.exists() or above == above.parent:
            break
        top = above
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        remove_made(folder, top)
        raise OutputError(f"{folder}: cannot create the output folder "
                          f"({exc.strerror or exc})") from None
    return top


def remove_made(folder: Path, top: Path | None) -> None:
    """Remove *folder* and the folders above it up to *top* (as :func:`make_folder` made them),
    each only when empty."""
    if top is None:
        return
    for path in (folder, *folder.parents):
        try:
            path.rmdir()
        except OSError:
            return
        if path == top:
            return


def open_temp(folder: Path, name: str) -> tuple[Path, BinaryIO]:
    """A new temporary file for the file *name* in *folder*, ``.NAME.PID.RANDOM.tmp`` (hidden,
    and telling which process writes it), open for writing, with the permissions the umask
    allows (not a temporary file's private 0600): its path and its stream."""
    temp = folder / f".{name}.{os.getpid()}.{secrets.token_hex(4)}.tmp"
    handle = os.open(temp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | _O_BINARY, 0o666)
    return temp, os.fdopen(handle, "wb")


def remove_stale_temps(folder: Path, names: Iterable[str]) -> None:
    """Remove the temporary files of *names* in *folder* that no running build writes: their
    process is gone (a build killed with SIGKILL, a power cut), or they are older than
    :data:`STALE_TEMP_SECONDS`. A concurrent build's temporary files are left alone."""
    import time

    now = time.time()
    for name in names:
        for temp in folder.glob(f".{glob.escape(name)}.*.tmp"):
            pid_text = temp.name[len(name) + 2:].split(".", 1)[0]
            try:
                old = now - temp.stat().st_mtime > STALE_TEMP_SECONDS
                if old or not pid_text.isdigit() or not _running(int(pid_text)):
                    temp.unlink()
            except OSError:  # gone already, or not ours to remove
                continue


def _running(pid: int) -> bool:
    """True when a process *pid* exists on this machine."""
    if pid == os.getpid() or os.name == "nt":  # Windows' os.kill(pid, 0) sends a Ctrl-C
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OSError, OverflowError):
        return True  # someone else's process, or a platform that cannot tell: leave it
    return True
