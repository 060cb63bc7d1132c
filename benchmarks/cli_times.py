"""Wall time of the command line and of the in-process pipeline (run by hand, not in CI).

    python benchmarks/cli_times.py [REPEATS]

Prints the median wall time of ``camfab --version`` and ``camfab check`` per example design (each
a fresh process, so import cost included), and the in-process cost of analysing and rendering every
example design once the libraries are loaded.
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DESIGNS = sorted((ROOT / "designs").glob("*.yaml"))


def wall(args: list[str], repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        subprocess.run([sys.executable, "-m", "camfab", *args], cwd=ROOT, check=False,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 5
    print(f"{'command':40s} median wall time (s), {repeats} runs")
    print(f"{'camfab --version':40s} {wall(['--version'], repeats):.3f}")
    for path in DESIGNS:
        label = f"camfab check {path.name}"
        print(f"{label:40s} {wall(['check', str(path)], repeats):.3f}")

    sys.path.insert(0, str(ROOT))
    from camfab.pipeline import analyse, load_design, render

    for path in DESIGNS:  # warm every import once
        render(analyse(load_design(path)))
    rounds = 20
    start = time.perf_counter()
    for _ in range(rounds):
        for path in DESIGNS:
            render(analyse(load_design(path)))
    per_design = (time.perf_counter() - start) / (rounds * len(DESIGNS))
    print(f"{'in-process load+analyse+render':40s} {per_design * 1000:.2f} ms per design")


if __name__ == "__main__":
    main()
