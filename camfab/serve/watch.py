"""The studio's watch of its files on disk: the design file and its table laws' CSV files.

A change made in any editor is read again (:meth:`~camfab.serve.studio.Studio.from_disk`), and
a table changed has the text analysed again. The folders holding the files are watched, not the
files, so an editor that saves by renaming a new file over the old is seen too; a path that is
a symbolic link is followed: the folder of the link, and of each link and file it leads to, is
watched, so both the link pointed elsewhere and its file changed are seen.

What the watch compares is what the files hold: the design's text against the text the studio
loaded, each table's bytes against those read last. It compares when it starts (so a change made
after the studio loaded the file and before the folders were watched is seen too), after each
change the folders report in the files watched, and once more within :data:`LOOK_MS` of the
start, when the folders surely are watched. Every :data:`LOOK_MS` it also looks whether the
files to watch changed (the design's file now a link, an edit in the page naming another table)
and, if so, watches the new set.

No error ends the watch. A file that cannot be read is the design's error, as the studio says
it (its located line); a fault of the watch itself is said in the page in the design's error's
place, and the watch starts again a moment later (the text is analysed again once it runs).
"""

from __future__ import annotations

import asyncio
import hashlib
import os
from contextlib import aclosing
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from camfab.serve.studio import Studio

#: How long after a change on disk the watch waits for more before it reads the files (ms): an
#: editor's save is often a write and a rename.
DEBOUNCE_MS = 40
#: How often the watch looks whether the files to watch changed, with no change on disk (ms).
LOOK_MS = 1000
#: Seconds between the tries to watch again after a fault: the first, and the longest.
RETRY_SECONDS = (0.2, 5.0)
#: Symbolic links followed from a path to its file, at most (the system's own limit is 40).
MAX_LINKS = 40


@dataclass(frozen=True)
class Watched:
    """The files the watch follows, each with the links on its way: every path is its folder
    resolved and its own name, as a change in that folder names it."""

    design: tuple[Path, ...]
    tables: tuple[Path, ...]
    files: frozenset[Path]

    def folders(self) -> list[str]:
        """The folders to watch: those of the files and links that exist."""
        return sorted({str(path.parent) for path in self.files if path.parent.is_dir()})


class Watcher:
    """The watch of *studio*'s files. Made with the studio, before its address is given, so
    that a change from then on is seen; :meth:`run` watches until the server stops."""

    def __init__(self, studio: Studio) -> None:
        self.studio = studio
        self.design_seen: tuple[bool, str] = (True, studio.disk_text)
        self.tables_seen = {path: _content(path) for path in _tables(studio.path, studio.text)}
        self.fault: str | None = None  # the fault of the watch said in the page, if any

    async def run(self, stopping: asyncio.Event) -> None:
        """Watch until *stopping* is set; every error is said in the page, and the watch
        starts again."""
        from starlette.concurrency import run_in_threadpool

        delay = RETRY_SECONDS[0]
        while not stopping.is_set():
            try:
                await self._session(stopping)
                delay = RETRY_SECONDS[0]
            except Exception as exc:  # no error ends the watch: said, then tried again
                if not isinstance(exc, FileNotFoundError):  # (not a folder gone just now)
                    await run_in_threadpool(self._say, exc)
                await asyncio.sleep(delay)
                delay = min(2 * delay, RETRY_SECONDS[1])

    async def _session(self, stopping: asyncio.Event) -> None:
        """Watch the files named now, until they change or the server stops."""
        import watchfiles
        from starlette.concurrency import run_in_threadpool

        watched = await run_in_threadpool(watched_files, self.studio)
        folders = await run_in_threadpool(watched.folders)
        await run_in_threadpool(self.compare)
        if not folders:  # the design's folder is gone: the page says the file is missing
            await asyncio.sleep(LOOK_MS / 1e3)
            return

        def wanted(change: Any, path: str) -> bool:
            return Path(path) in watched.files

        started = False
        async with aclosing(watchfiles.awatch(
                *folders, watch_filter=wanted, debounce=DEBOUNCE_MS, step=10,
                stop_event=stopping, rust_timeout=LOOK_MS, yield_on_timeout=True,
                recursive=False)) as seen:
            async for changes in seen:
                if changes or not started:  # (first: what came before the watch began)
                    await run_in_threadpool(self.compare)
                if not started:
                    started = True
                    if self.fault is not None:  # watched again: the page shows the design
                        self.fault = None
                        await run_in_threadpool(self.studio.again)
                if await run_in_threadpool(watched_files, self.studio) != watched:
                    return

    def compare(self) -> None:
        """Read the files again and follow what changed since they were last read: the
        design's text (:meth:`~camfab.serve.studio.Studio.from_disk`), a table's bytes (the
        text analysed again).

        The tables are read before the text that names them is analysed, so that a table
        changed meanwhile is seen as changed the next time; a table named by a text the studio
        took otherwise (Reload) counts as changed, since what its analysis read is not known."""
        studio = self.studio
        design = _design_content(studio.path)
        fresh = design != self.design_seen
        loads, text = design
        if not (fresh and loads) or studio.edited:  # the text analysed next is the studio's
            text = studio.text
        now = {path: _content(path) for path in _tables(studio.path, text)}
        tables_changed = any(self.tables_seen.get(path) != seen for path, seen in now.items())
        self.tables_seen = now
        if fresh:
            self.design_seen = design
            if studio.from_disk():
                return
        if tables_changed:
            studio.again()

    def _say(self, exc: Exception) -> None:
        """Say the fault *exc* of the watch in the page, in the design's error's place (once
        for the same fault)."""
        line = (f"{self.studio.label}: changes on disk are not followed for now "
                f"({type(exc).__name__}: {exc}); the studio tries again")
        if line != self.fault:
            self.fault = line
            self.studio.fault(line)


def watched_files(studio: Studio) -> Watched:
    """The files *studio* follows: its design file and the table laws' CSV files its text
    names, each with the symbolic links on its way."""
    design = links(studio.path)
    tables = tuple(path for table in _tables(studio.path, studio.text) for path in links(table))
    return Watched(design, tables, frozenset(design + tables))


def links(path: Path) -> tuple[Path, ...]:
    """*path* and each path the symbolic links from it lead to, up to a file that is not a
    link (or one that is missing, or a loop, or :data:`MAX_LINKS` links): each as its folder
    resolved and its own name."""
    found: list[Path] = []
    here = path
    for _ in range(MAX_LINKS + 1):
        try:
            here = here.parent.resolve() / here.name
        except (OSError, RuntimeError, ValueError):  # a folder on the way loops
            break
        if here in found:  # a loop of links
            break
        found.append(here)
        try:
            target = os.readlink(here)
        except (OSError, ValueError):  # not a link, missing, or a name no system takes
            break
        here = here.parent / target
    return tuple(found)


def _tables(design: Path, text: str) -> list[Path]:
    """The table laws' CSV files the *text* of design file *design* names (from its folder),
    at most as many as a design has segments."""
    from camfab.design.rules import MAX_SEGMENTS
    from camfab.serve.yamledit import named_files

    names = list(dict.fromkeys(named_files(text)))[:MAX_SEGMENTS]
    return [design.parent / name for name in names]


def _design_content(path: Path) -> tuple[bool, str]:
    """(True, the design file's text), or (False, the line saying why it cannot be read)."""
    from camfab.design.source import read_design_text
    from camfab.errors import CamfabError

    try:
        return True, read_design_text(path)
    except CamfabError as exc:
        return False, str(exc)


def _content(path: Path) -> str:
    """A digest of a table's bytes, or why it cannot be read (a regular file of at most
    :data:`~camfab.design.loader.MAX_TABLE_BYTES` is read: never a device or a FIFO)."""
    from camfab.design.loader import MAX_TABLE_BYTES
    from camfab.errors import InputFileError
    from camfab.files import read_bounded

    try:
        return hashlib.sha256(read_bounded(path, MAX_TABLE_BYTES, "a table")).hexdigest()
    except InputFileError as exc:  # (a problem is never a digest's 64 hexadecimal digits)
        return exc.problem
