"""How fast ``camfab sweep`` analyses variants, locally and on Dask, and whether its memory
stays flat.

    python benchmarks/sweep_speed.py [--variants N] [--jobs J] [--rounds R]

Sweeps of seed-10-4 (a disc cam) over its base radius, offset and rise law, analysis only:

- local, ``-j 1`` and ``-j J`` (default: every processor), N variants (default 10,000): the
  command's wall time end to end (start, imports, the table and page written) and the
  variants a second the sweep itself reports;
- the same on a Dask cluster on this machine (a scheduler and J single-threaded worker
  processes, ``LocalCluster(processes=True)``), through ``--scheduler``, alternated with the
  local pool (``--rounds`` times each), medians compared;
- memory: the peak resident size of the sweep's process and its workers, sampled every 0.1 s,
  for N/5 and N variants (flat: the same peak for five times the rows).

The tables of the local and the Dask run are compared byte for byte. Needs the ``cluster``
extra (``pip install 'camfab[cluster]'``) for the Dask figures.
"""

from __future__ import annotations

import argparse
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

from timing import ROOT, compile_package

DESIGN = ROOT / "designs" / "seed-10-4.yaml"


def vary_for(count: int) -> list[str]:
    """--vary options giving about *count* variants (base radius × offset × two rise laws)."""
    side = max(2, round(math.sqrt(count / 2)))
    radius_step = 100.0 / (side - 1)
    offset_step = 40.0 / (side - 1)
    return ["--vary", f"cam.base_radius=20:120:{radius_step:.12g}",
            "--vary", f"follower.offset=-20:20:{offset_step:.12g}",
            "--vary", "motion[0].law=harmonic,cycloidal"]


def _tree_rss(pid: int) -> int:
    """Resident bytes of process *pid* and its descendants (Linux /proc; 0 elsewhere)."""
    total = 0
    pids = [pid]
    while pids:
        p = pids.pop()
        try:
            status = Path(f"/proc/{p}/status").read_text()
            total += int(re.search(r"VmRSS:\s+(\d+)", status).group(1)) * 1024  # type: ignore[union-attr]
            children = Path(f"/proc/{p}/task/{p}/children").read_text().split()
        except (OSError, AttributeError):
            continue
        pids.extend(int(c) for c in children)
    return total


def sweep(args: list[str], folder: Path) -> tuple[float, float, int, Path]:
    """Run ``camfab sweep`` with *args* into *folder*: wall seconds, the rate it reports
    (variants a second), the peak resident bytes of its process tree, and its table."""
    command = [sys.executable, "-m", "camfab", "sweep", str(DESIGN), *args, "-o", str(folder),
               "--format", "csv", "--no-progress"]
    peak = [0]
    start = time.perf_counter()
    process = subprocess.Popen(command, cwd=ROOT, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)

    def watch() -> None:
        while process.poll() is None:
            peak[0] = max(peak[0], _tree_rss(process.pid))
            time.sleep(0.1)

    watcher = threading.Thread(target=watch)
    watcher.start()
    out, err = process.communicate()
    wall = time.perf_counter() - start
    watcher.join()
    if process.returncode != 0:
        raise SystemExit(f"camfab sweep failed ({process.returncode}): {out}{err}")
    rate = float(re.search(r"\(([\d.]+) a second\)", out).group(1))  # type: ignore[union-attr]
    return wall, rate, peak[0], folder / "seed-10-4-sweep.csv"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--variants", type=int, default=10_000)
    parser.add_argument("--jobs", type=int, default=len(os.sched_getaffinity(0)))
    parser.add_argument("--rounds", type=int, default=3,
                        help="local and Dask runs alternated (each)")
    options = parser.parse_args()
    compile_package()
    jobs = options.jobs
    big = vary_for(options.variants)
    small = vary_for(options.variants // 5)
    with tempfile.TemporaryDirectory() as temp:
        folder = Path(temp)
        one = sweep([*big, "-j", "1"], folder / "one")
        local = sweep([*big, "-j", str(jobs)], folder / "local")
        rows = sum(1 for _ in local[3].open()) - 1
        print(f"{rows:,} variants of seed-10-4, analysis only, {jobs} processors:")
        print(f"  local -j 1:  {one[0]:6.1f} s end to end, {one[1]:7.1f} variants/s")
        print(f"  local -j {jobs}:  {local[0]:6.1f} s end to end, {local[1]:7.1f} variants/s "
              f"({local[1] / one[1]:.2f}× -j 1)")
        little = sweep([*small, "-j", str(jobs)], folder / "little")
        little_rows = sum(1 for _ in little[3].open()) - 1
        print(f"  memory: peak {little[2] / 2**20:.0f} MiB for {little_rows:,} variants, "
              f"{local[2] / 2**20:.0f} MiB for {rows:,} ({local[2] / little[2]:.2f}×)")
        try:
            from distributed import LocalCluster
        except ImportError:
            print("  dask: not installed (pip install 'camfab[cluster]')")
            return 0
        runs: dict[str, list[tuple[float, float, int, Path]]] = {"local": [], "dask": []}
        with LocalCluster(n_workers=jobs, threads_per_worker=1, processes=True,
                          host="127.0.0.1", dashboard_address=None) as cluster:
            for k in range(options.rounds):  # alternated: the machine's load drifts
                runs["dask"].append(sweep([*big, "--scheduler", cluster.scheduler_address],
                                          folder / f"dask{k}"))
                runs["local"].append(sweep([*big, "-j", str(jobs)], folder / f"local{k}"))
        same = all(run[3].read_bytes() == local[3].read_bytes() for run in runs["dask"])
        for engine in ("local", "dask"):
            walls = ", ".join(f"{run[0]:.1f}" for run in runs[engine])
            rates = ", ".join(f"{run[1]:.1f}" for run in runs[engine])
            print(f"  {engine} alternated ({jobs} processes): {walls} s end to end, {rates} "
                  f"variants/s")
        local_rate, dask_rate = (statistics.median(run[1] for run in runs[engine])
                                 for engine in ("local", "dask"))
        print(f"  dask against local, medians: {dask_rate:.1f} / {local_rate:.1f} variants/s "
              f"= {dask_rate / local_rate:.2f}×; the same table every run: {same}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
