"""Batch throughput: disc-cam designs built per second by ``camfab build DESIGNS -j N``, all
outputs included (DXF, SVG, STL, HTML and JSON report, motion CSV), against the goal of 10 per
second with two workers, and what the workers gain over one process: the same batch with
``-j 1``, against the goal of 1.5 times its designs per second with two workers.

The batch is N copies (renamed) of the disc-cam examples seed-10-4 and seed-c11-shm-ua, built in
a fresh process from the command line, so the time includes starting camfab, its imports and
the workers. ``-j 1`` and ``-j N`` are run in alternation, so that a change of the machine's
load falls on both; each is the median of the runs, with the processor time (user + system, the
workers included) of its median run. The script also times one design in process (after
imports), the cost each worker pays per design, and splits it into the HTML report and the rest.

    python benchmarks/batch_speed.py --designs 40 --jobs 2 --runs 3
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
from pathlib import Path

from timing import ROOT, compile_package, median_seconds, use_checkout, wall_and_cpu

#: The designs-per-second goal of a batch of disc cams on two workers.
GOAL = 10.0

#: The goal of two workers against one process: designs per second of ``-j 2`` over ``-j 1``.
SPEEDUP_GOAL = 1.5

#: The disc-cam examples the batch is made of.
EXAMPLES = ("seed-10-4", "seed-c11-shm-ua")


def _batch(folder: Path, count: int) -> list[Path]:
    """*count* copies of the examples, each with its own name."""
    paths = []
    for i in range(count):
        stem = EXAMPLES[i % len(EXAMPLES)]
        text = (ROOT / "designs" / f"{stem}.yaml").read_text()
        lines = [f"name: {stem}-{i}" if line.startswith("name:") else line
                 for line in text.splitlines()]
        path = folder / f"{stem}-{i}.yaml"
        path.write_text("\n".join(lines) + "\n")
        paths.append(path)
    return paths


def _per_design(runs: int) -> tuple[float, float]:
    """Seconds of one build in process after imports, and of its HTML report."""
    use_checkout()
    from camfab.export.report_html import render_report_html
    from camfab.pipeline import analyse, build, load_design, verify_exports

    path = ROOT / "designs" / f"{EXAMPLES[0]}.yaml"
    with tempfile.TemporaryDirectory() as out:
        whole = median_seconds(lambda: build(path, Path(out)), runs)
    analysis, _ = verify_exports(analyse(load_design(path)), ("dxf",))
    report = median_seconds(lambda: render_report_html(analysis), runs)
    return whole, report


def _timed_batches(paths: list[Path], out: Path, jobs: tuple[int, ...],
                   runs: int) -> dict[int, list[tuple[float, float]]]:
    """Wall and processor seconds of *runs* builds of the batch *paths* with each of *jobs*,
    the job counts taken in turn within every run."""
    times: dict[int, list[tuple[float, float]]] = {j: [] for j in jobs}
    for _ in range(runs):
        for j in jobs:
            command = [sys.executable, "-m", "camfab", "build", *map(str, paths), "-j", str(j),
                       "-o", str(out / f"j{j}"), "--no-progress"]
            times[j].append(wall_and_cpu(command))
    return times


def _median_run(runs: list[tuple[float, float]]) -> tuple[float, float]:
    """The run of median wall time (the upper one of an even count), with its processor time."""
    return sorted(runs)[len(runs) // 2]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--designs", type=int, default=40, help="designs in the batch")
    parser.add_argument("--jobs", type=int, default=2, help="worker processes (-j) compared "
                                                              "with -j 1")
    parser.add_argument("--runs", type=int, default=3, help="batches timed (median)")
    args = parser.parse_args()
    if args.jobs < 2:
        parser.error("--jobs: at least 2 (the batch is compared with -j 1)")
    compile_package()
    jobs = (1, args.jobs)
    load = [_load()]
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        paths = _batch(folder, args.designs)
        times = _timed_batches(paths, folder / "out", jobs, args.runs)
    load.append(_load())
    rates = {}
    for j in jobs:
        batch, cpu = _median_run(times[j])
        rates[j] = args.designs / batch
        goal = (f"; goal {GOAL:g}/s: {'met' if rates[j] >= GOAL else 'not met'}"
                if j == args.jobs else "")
        print(f"batch: {args.designs} disc designs, -j {j}: {batch:.2f} s (median of "
              f"{args.runs}), {rates[j]:.1f} designs/s, {cpu:.2f} s of processor time{goal}")
    ratio = rates[args.jobs] / rates[1]
    print(f"-j {args.jobs} against -j 1: {ratio:.2f}x the designs per second; goal "
          f"{SPEEDUP_GOAL:g}x: {'met' if ratio >= SPEEDUP_GOAL else 'not met'}")
    whole, report = _per_design(max(args.runs, 3))
    print(f"per design in a worker after imports: {whole:.3f} s, of which the HTML report "
          f"{report:.3f} s; {args.jobs} workers at most {args.jobs / whole:.1f} designs/s")
    print(f"machine: {os.cpu_count()} cores, load average (1 min) {load[0]} before the batches, "
          f"{load[1]} after")


def _load() -> str:
    """The machine's load average over the last minute, or "unknown" where there is none."""
    try:
        return f"{os.getloadavg()[0]:.2f}"
    except (AttributeError, OSError):  # not on Windows
        return "unknown"


if __name__ == "__main__":
    main()
