"""Batches of designs: run one task per design file, in parallel processes when asked, and sum up.

A failure of one design (invalid, or a failed check) never stops the others; the batch's exit
status is the worst of them. Worker processes live for the whole batch. Where the platform
forks (Linux; not macOS), the batch's process imports what the task needs once, and the workers
are forked from it with all of it imported; elsewhere each worker imports the libraries itself,
once for the whole batch. Results are reported in the order the designs were given, whatever order
they finish in; a progress bar on stderr counts them as they finish.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager, suppress
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from concurrent.futures import ProcessPoolExecutor

#: A batch of at least this many designs shows a progress bar when stderr is a terminal.
PROGRESS_FROM = 8

#: Status words of the summary by exit status.
STATUS = {0: "OK", 1: "FAIL", 2: "INVALID"}


@dataclass
class Outcome:
    """What one design's run printed, its exit status, and what the summary shows of it."""

    code: int
    out: list[str] = field(default_factory=list)
    err: list[str] = field(default_factory=list)
    name: str = ""
    errors: int = 0
    warnings: int = 0
    files: int = 0
    seconds: float = 0.0


Task = Callable[[str, Path | None], Outcome]


def _timed(task: Task, path: str, out_dir: Path | None) -> Outcome:
    start = time.perf_counter()
    outcome = task(path, out_dir)
    outcome.seconds = time.perf_counter() - start
    if not outcome.name:
        outcome.name = Path(path).name
    return outcome


def run_all(paths: Sequence[str], out_dir: Path | None, jobs: int, task: Task,
            progress: bool = False, preload: Callable[[], object] | None = None) -> list[Outcome]:
    """*task* on every design of *paths*, in *jobs* worker processes (1: in this process), the
    outcomes in the order of *paths*; *progress* shows a bar on stderr. *preload* imports what
    *task* needs: called once in this process before the workers are forked from it, when
    workers run and the platform forks (see :func:`worker_pool`)."""
    bar = progress_bar(len(paths)) if progress else None
    try:
        if jobs == 1 or len(paths) == 1:
            outcomes = []
            for path in paths:
                outcomes.append(_timed(task, path, out_dir))
                if bar is not None:
                    bar.update(1)
            return outcomes
        from concurrent.futures import as_completed

        results: list[Outcome | None] = [None] * len(paths)
        pool = worker_pool(min(jobs, len(paths)), preload)
        try:
            with signals_held():  # the pool is set up whole; the workers ignore Ctrl-C
                futures = {pool.submit(_timed, task, path, out_dir): i
                           for i, path in enumerate(paths)}
            for future in as_completed(futures):
                results[futures[future]] = future.result()
                if bar is not None:
                    bar.update(1)
        except BaseException:  # Ctrl-C, SIGTERM: the designs being built are finished (their
            # files written whole), the others not started
            with signals_held():  # a second signal must not break off the shutdown
                pool.shutdown(wait=True, cancel_futures=True)
            raise
        with signals_held():
            pool.shutdown()
        return [r for r in results if r is not None]
    finally:
        if bar is not None:
            bar.render_finish()


def worker_pool(workers: int, preload: Callable[[], object] | None) -> ProcessPoolExecutor:
    """A pool of *workers* processes, forked from this one after *preload* where the platform
    forks: they start with what *preload* imported instead of each importing it again, and with
    this process's signal handlers, as :func:`_worker` expects.

    Forking is safe because *preload* only imports: no thread of this process is left running
    that a worker could inherit holding a lock. A stopping signal waits for *preload* to end (a
    fraction of a second): raised inside an import, it can be printed as ignored there, or leave
    half-made objects that complain on the way out. What is loaded by then is frozen out of the
    garbage collector's reach (:func:`gc.freeze`): the workers' collections skip it, and this
    process, which ends with the batch, does not sweep it again on the way out.

    Without fork, and on macOS, whose system libraries are not safe to fork, the platform's
    default start (spawn): each worker imports what it needs itself."""
    import gc
    import multiprocessing
    import sys
    from concurrent.futures import ProcessPoolExecutor

    context = None
    if "fork" in multiprocessing.get_all_start_methods() and sys.platform != "darwin":
        if preload is not None:
            # a stop waits for the imports (broken off, they leave noise); an import that fails
            # fails again in each design's build, which reports it as that design's error
            with signals_held(), suppress(Exception):
                preload()
        gc.freeze()
        context = multiprocessing.get_context("fork")
    return ProcessPoolExecutor(max_workers=workers, mp_context=context, initializer=_worker)


#: The signals that stop camfab (Ctrl-C, SIGTERM, SIGHUP), by name.
_STOPPING = ("SIGINT", "SIGTERM", "SIGHUP")


@contextmanager
def signals_held() -> Iterator[None]:
    """Hold the signals that stop camfab while the pool of workers is set up: a stop raised
    inside ``submit``, between forking the workers and starting the thread that feeds them,
    leaves workers that wait for work forever and a process that waits for them at exit. The
    signals come once the pool is whole, and the workers start with them held."""
    import signal

    if not hasattr(signal, "pthread_sigmask"):
        yield
        return
    held = {getattr(signal, name) for name in _STOPPING if hasattr(signal, name)}
    old = signal.pthread_sigmask(signal.SIG_BLOCK, held)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def _worker() -> None:
    """A worker ignores Ctrl-C: the batch's process stops the batch and lets a worker finish
    the design it is writing; SIGTERM and SIGHUP stop it as they stop camfab."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {getattr(signal, name) for name in _STOPPING
                                                    if hasattr(signal, name)})


def same_names(paths: Sequence[str]) -> dict[int, Outcome]:
    """The designs of *paths* whose ``name`` an earlier design of the batch already has, by
    position, each refused (status 2) with a line naming both: they would write the same files.
    Designs that cannot be read are left to the build, which says why."""
    from camfab.design.source import read_design_file
    from camfab.errors import CamfabError

    first: dict[str, str] = {}
    refused: dict[int, Outcome] = {}
    for i, path in enumerate(paths):
        try:
            doc = read_design_file(path)
        except CamfabError:
            continue
        name = doc.data.get("name")
        if not isinstance(name, str):
            continue
        if name in first:
            where = doc.locate(("name",))
            refused[i] = Outcome(2, err=[f"{where}: '{name}' is also the name of {first[name]} in "
                                         "this batch: both would write the same files (give "
                                         "each design its own name)"], name=name)
        else:
            first[name] = path
    return refused


def progress_bar(count: int, label: str = "building") -> Any:
    """A progress bar of *count* steps on stderr, drawn at once."""
    import click

    bar = click.progressbar(length=count, label=label, file=sys.stderr,
                            show_pos=True, show_eta=True)
    bar.render_progress()
    return bar


def summary(outcomes: Sequence[Outcome], wall_seconds: float) -> list[str]:
    """A table of the batch: each design's status, errors, warnings, files and build time, and
    the totals with the throughput."""
    width = max([len("design"), *(len(o.name) for o in outcomes)])
    head = f"{'design':<{width}}  {'status':<7}  {'errors':>6}  {'warnings':>8}  {'files':>5}  " \
           f"{'seconds':>7}"
    lines = [head, "-" * len(head)]
    for o in outcomes:
        lines.append(f"{o.name:<{width}}  {STATUS.get(o.code, str(o.code)):<7}  {o.errors:>6}  "
                     f"{o.warnings:>8}  {o.files:>5}  {o.seconds:>7.2f}")
    counts = {word: sum(1 for o in outcomes if STATUS.get(o.code) == word)
              for word in STATUS.values()}
    rate = len(outcomes) / wall_seconds if wall_seconds > 0 else float("inf")
    lines.append("-" * len(head))
    lines.append(f"{len(outcomes)} design(s): {counts['OK']} OK, {counts['FAIL']} FAIL, "
                 f"{counts['INVALID']} INVALID; {sum(o.files for o in outcomes)} file(s) in "
                 f"{wall_seconds:.2f} s ({rate:.1f} designs/s)")
    return lines
