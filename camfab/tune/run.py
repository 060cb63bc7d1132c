"""``camfab tune`` end to end: the tuning planned (:mod:`camfab.tune.plan`), the search
(:mod:`camfab.tune.search`), then the tuned design (when a candidate meets every limit) and the
comparison report written as one set, atomically. Where no candidate meets every limit, only
the report is written, saying why (exit 1). A stop (Ctrl-C) writes the best found so far, the
report saying the search was stopped, then stops (130).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from camfab.stopping import Interrupted
from camfab.tune.plan import Plan, TuneOptions, plan, tuned_text
from camfab.tune.search import Search


@dataclass
class Tuned:
    """A tuning's outcome: the exit status, the lines to print, the files written."""

    code: int
    lines: list[str]
    written: list[Path]


def tune(options: TuneOptions, echo: Callable[[str], None] = print,
         progress_write: Callable[[str], None] | None = None,
         terminal: bool = False) -> Tuned:
    """Tune the design of *options* (see the module): *echo* prints the lines of a stop,
    *progress_write* the progress line (with *options*.progress)."""
    from camfab.tune.search import Progress

    tuning = plan(options)
    progress = (Progress(progress_write, terminal) if options.progress
                and progress_write is not None else None)
    search = Search(tuning.evaluator, tuning.start, options.starts, progress)
    try:
        search.run()
    except (KeyboardInterrupt, Interrupted):
        # a stop: the best found so far is written, then the stop goes on
        if progress is not None:
            progress.finish()
        if search.before is None or not search.before.checked:
            raise  # stopped before the design itself was measured: nothing to write
        done = finish(tuning, search, stopped=True)
        for line in done.lines:
            echo(line)
        raise
    if progress is not None:
        progress.finish()
    return finish(tuning, search, stopped=False)


def finish(tuning: Plan, search: Search, stopped: bool) -> Tuned:
    """Write the tuned design (when a candidate meets every limit) and the report; the lines
    that say what was found."""
    from camfab.tune.page import render_report
    from camfab.tune.summary import summary_lines
    from camfab.writing import write_files

    best = search.best
    files: dict[str, bytes] = {}
    folder = tuning.tuned_path.parent
    if best is not None:
        files[tuning.tuned_path.name] = tuned_text(tuning, best.written).encode("utf-8")
    files[tuning.report_path.name] = render_report(tuning, search, stopped)
    # what the tuned laws gain over the best standard law in their place (not after a stop)
    standard = (None if best is None or stopped else
                tuning.evaluator.standard(sorted({f.index for f in tuning.families})))
    written = write_files(folder, files)
    lines = summary_lines(tuning, search, stopped, written, standard)
    return Tuned(0 if best is not None else 1, lines, written)


