"""Batch throughput: disc-cam designs built per second by ``camfab build DESIGNS -j N``, all
outputs included (DXF, SVG, STL, HTML and JSON report, motion CSV), against the goal of 10 per
second with two workers.

The batch is N copies (renamed) of the disc-cam examples seed-10-4 and seed-c11-shm-ua, built in
a fresh process from the command line, so the time includes starting the workers and their one
import of the libraries each. The script also times one design in process (after imports), the
cost each worker pays per design, and splits it into the HTML report and the rest.

    python benchmarks/batch_speed.py --designs 40 --jobs 2 --runs 3
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
from pathlib import Path

from timing import ROOT, compile_package, median_seconds, use_checkout, wall

#: The designs-per-second goal of a batch of disc cams on two workers.
GOAL = 10.0

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
    from camfab.design import load_design
    from camfab.export.report_html import render_report_html
    from camfab.pipeline import analyse, build, verify_exports

    path = ROOT / "designs" / f"{EXAMPLES[0]}.yaml"
    with tempfile.TemporaryDirectory() as out:
        whole = median_seconds(lambda: build(path, Path(out)), runs)
    analysis, _ = verify_exports(analyse(load_design(path)), ("dxf",))
    report = median_seconds(lambda: render_report_html(analysis), runs)
    return whole, report


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--designs", type=int, default=40, help="designs in the batch")
    parser.add_argument("--jobs", type=int, default=2, help="worker processes (-j)")
    parser.add_argument("--runs", type=int, default=3, help="batches timed (median)")
    args = parser.parse_args()
    compile_package()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        paths = _batch(folder, args.designs)
        command = [sys.executable, "-m", "camfab", "build", *map(str, paths), "-j",
                   str(args.jobs), "-o", str(folder / "out"), "--no-progress"]
        times = [wall(command) for _ in range(args.runs)]
    batch = statistics.median(times)
    rate = args.designs / batch
    whole, report = _per_design(max(args.runs, 3))
    print(f"batch: {args.designs} disc designs, -j {args.jobs}: {batch:.2f} s (median of "
          f"{args.runs}), {rate:.1f} designs/s; goal {GOAL:g}/s: "
          f"{'met' if rate >= GOAL else 'not met'}")
    print(f"per design in a worker after imports: {whole:.3f} s, of which the HTML report "
          f"{report:.3f} s; {args.jobs} workers at most {args.jobs / whole:.1f} designs/s")


if __name__ == "__main__":
    main()
