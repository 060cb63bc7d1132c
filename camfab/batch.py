"""Batches of designs: run one task per design file, in parallel processes when asked, and sum up.

A failure of one design (invalid, or a failed check, or a worker process dying under it) never
stops the others; the batch's exit status is the worst of them. Worker processes live for the
whole batch (:mod:`camfab.workers`). Where the platform
forks (Linux; not macOS), the batch's process imports what the task needs once, and the workers
are forked from it with all of it imported; elsewhere each worker imports the libraries itself,
once for the whole batch. Results are reported in the order the designs were given, whatever order
they finish in; a progress bar on stderr counts them in that order.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from camfab.workers import Died

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
    workers run and the platform forks (see :func:`camfab.workers.worker_pool`)."""
    bar = progress_bar(len(paths)) if progress else None
    try:
        if jobs == 1 or len(paths) == 1:
            outcomes = []
            for path in paths:
                outcomes.append(_timed(task, path, out_dir))
                if bar is not None:
                    bar.update(1)
            return outcomes
        from camfab.workers import Died, in_order

        outcomes = []
        calls = ((path, out_dir) for path in paths)
        for (path, _), result in in_order(partial(_call, task), calls, min(jobs, len(paths)),
                                          preload, len(paths)):
            outcomes.append(_died(path, result) if isinstance(result, Died) else result)
            if bar is not None:
                bar.update(1)
        return outcomes
    finally:
        if bar is not None:
            bar.render_finish()


def _call(task: Task, call: tuple[str, Path | None]) -> Outcome:
    return _timed(task, *call)


def _died(path: str, died: Died) -> Outcome:
    """The outcome of a design whose worker died under it: FAIL, saying so (its earlier files,
    if any, are left as they were: a build's set is renamed into place whole)."""
    return Outcome(1, out=[f"{Path(path).name}: FAIL — {died.words()}"], name=Path(path).name)


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
