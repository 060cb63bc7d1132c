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

import errno
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


def replace_file(path: Path, data: bytes, label: str | None = None) -> None:
    """Replace the contents of the existing file *path* (*label*: its name in the message
    of an error; the path when None) with *data*, so that a stop sees the
    old contents or the new, never a part (and so does a reader, but of a file written in
    place), and the file stays the same file:

    - a file this process may not write (read-only) is refused, as its folder would refuse;
    - a symbolic link is followed: its target is written (the temporary file beside the
      target), the link stays;
    - the file keeps its permissions, its owner and its group (a program run as root gives
      the new file the old one's owner);
    - a file with more than one name (a hard link), or whose owner or group this process
      cannot give a new file, is written in place (:func:`_write_in_place`), so that every
      name sees the change and the file keeps its owner;
    - otherwise the data goes to a temporary file beside it, flushed to the disk, then renamed
      over it (the stopping signals held).

    The temporary file is removed on every way out.

    Raises
    ------
    OutputError
        The file cannot be written; it is unchanged then. Its ``errno`` is the system's
        (``EACCES`` for a read-only file or folder, ``ENOSPC`` for a full disk).
    """
    import stat

    target = Path(os.path.realpath(path))
    temp: Path | None = None
    try:
        info = os.stat(target)
        if not os.access(target, os.W_OK):  # a read-only file is not replaced behind its back
            raise PermissionError(errno.EACCES, os.strerror(errno.EACCES), str(target))
        if info.st_nlink == 1:
            with deferred():  # a stop comes once the temporary file is made and noted
                temp, stream = open_temp(target.parent, target.name)
            with stream:
                stream.write(data)
                stream.flush()
                os.fsync(stream.fileno())
            if _owned_as(temp, info):
                os.chmod(temp, stat.S_IMODE(info.st_mode))  # after the owner, whose change
                with signals_held():                      # clears the set-id bits
                    os.replace(temp, target)
                temp = None
                _sync_folder(target.parent)
                return
        _write_in_place(target, data)
    except OSError as exc:
        error = OutputError(f"{label or path}: cannot write the design file "
                            f"({exc.strerror or exc})")
        error.errno = exc.errno
        raise error from None
    finally:
        if temp is not None:
            with deferred():
                temp.unlink(missing_ok=True)


def _owned_as(temp: Path, info: os.stat_result) -> bool:
    """Give the new file *temp* the owner and group of the file it replaces (*info*: its
    status); False when this process may not (a file of another user's, or of a group it is
    not in)."""
    made = os.stat(temp)
    if (made.st_uid, made.st_gid) == (info.st_uid, info.st_gid):
        return True
    try:
        os.chown(temp, info.st_uid, info.st_gid)
    except (PermissionError, AttributeError):  # AttributeError: a system without chown
        return False
    return True


def _write_in_place(target: Path, data: bytes) -> None:
    """Write *data* into the file *target* itself, keeping its inode (every name of a hard
    link, its owner, group, permissions): first a temporary copy beside it, flushed to the
    disk (it proves there is room and holds the new contents should the power fail during
    the copy), then the data written over the old from the start and the rest cut off, the
    stopping signals held. A write that fails half way puts the old contents back.
    Raises OSError."""
    old = target.read_bytes()
    with deferred():
        temp, stream = open_temp(target.parent, target.name)
    try:
        with stream:
            stream.write(data)
            stream.flush()
            os.fsync(stream.fileno())
        handle = os.open(target, os.O_WRONLY | _O_BINARY)
        try:
            with signals_held():
                try:
                    _overwrite(handle, data)
                except OSError:
                    _overwrite(handle, old)  # the old contents fit where they were
                    raise
        finally:
            os.close(handle)
    finally:
        with deferred():
            temp.unlink(missing_ok=True)


def _overwrite(handle: int, data: bytes) -> None:
    """The open file *handle* made to hold *data* exactly, flushed to the disk."""
    os.lseek(handle, 0, os.SEEK_SET)
    done = 0
    while done < len(data):
        done += os.write(handle, data[done:])
    os.ftruncate(handle, len(data))
    os.fsync(handle)


def _sync_folder(folder: Path) -> None:
    """Flush *folder*'s entries to the disk (a rename made durable), where the system can."""
    try:
        handle = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(handle)
    except OSError:
        pass
    finally:
        os.close(handle)


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
