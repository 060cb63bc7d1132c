"""Slice every STL camfab writes with PrusaSlicer, as a 3-D printing user would (run by hand).

    python benchmarks/slice_stls.py [--out DIR] [--markdown]

Builds every example design and every starter (``camfab new KIND``), then runs
``prusa-slicer --export-gcode`` on each STL with PrusaSlicer's default configuration (no
printer profile: a 200 × 200 mm bed, 0.4 mm nozzle, 0.3 mm layers), one fresh process per file.
A part longer than the bed (a linear cam's plate) is refused ("Objects could not fit on the
bed") and sliced again on a square bed of :data:`LARGE_BED_MM`. For each file it prints whether
it sliced, the wall and processor time of the slicer (both runs for a large part), its warnings
and errors (``--loglevel 2``), the layer count and PrusaSlicer's estimate of the printing time.
Needs ``prusa-slicer`` (Debian: ``apt-get install prusa-slicer``); runs without a display.
"""

from __future__ import annotations

import argparse
import os
import re
import resource
import subprocess
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from timing import ROOT, use_checkout

#: The side (mm) of the bed a part too large for the default one is sliced on.
LARGE_BED_MM = 400


@dataclass(frozen=True)
class Sliced:
    """What slicing one STL gave."""

    name: str
    ok: bool
    wall_s: float
    cpu_s: float
    layers: int
    estimate: str
    messages: tuple[str, ...]


def build_all(folder: Path) -> list[Path]:
    """Every example and starter built into *folder*; their STL files."""
    use_checkout()
    from camfab.cli import STARTER_KINDS
    from camfab.pipeline import analyse, load_design, render

    sources = sorted((ROOT / "designs").glob("*.yaml"))
    sources += [ROOT / "camfab" / "starters" / f"{kind}.yaml" for kind in STARTER_KINDS]
    stls = []
    for path in sources:
        artifacts = render(analyse(load_design(path)))
        for name, data in artifacts.files.items():
            if name.endswith(".stl"):
                (folder / name).write_bytes(data)
                stls.append(folder / name)
    return stls


def slice_one(stl: Path, home: Path, bed_mm: int | None = None) -> Sliced:
    """Slice *stl* with PrusaSlicer's defaults (or on a square bed of *bed_mm*) into a G-code
    file beside it; a part too large for the bed is sliced again on :data:`LARGE_BED_MM`."""
    gcode = stl.with_suffix(".gcode")
    env = {**os.environ, "HOME": str(home), "QT_QPA_PLATFORM": "offscreen"}
    bed = [] if bed_mm is None else ["--bed-shape",
                                     f"0x0,{bed_mm}x0,{bed_mm}x{bed_mm},0x{bed_mm}"]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    run = subprocess.run(["prusa-slicer", "--loglevel", "2", *bed, "--export-gcode", "--output",
                          str(gcode), str(stl)], capture_output=True, text=True, env=env,
                         timeout=3600, check=False)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    messages = tuple(line.strip() for line in (run.stdout + run.stderr).splitlines()
                     if re.search(r"warning|error|fail|what\(\)", line, re.IGNORECASE)
                     and "terminate called" not in line)
    if bed_mm is not None:
        messages = (f"sliced on a {bed_mm} x {bed_mm} mm bed", *messages)
    layers, estimate = 0, ""
    ok = run.returncode == 0 and gcode.exists()
    if ok:
        text = gcode.read_text(errors="replace")
        layers = text.count(";LAYER_CHANGE")
        found = re.search(r"; estimated printing time \(normal mode\) = (.+)", text)
        estimate = found.group(1).strip() if found else ""
    elif bed_mm is None and "could not fit on the bed" in run.stderr:
        again = slice_one(stl, home, LARGE_BED_MM)
        return Sliced(stl.name, again.ok, wall + again.wall_s, cpu + again.cpu_s, again.layers,
                      again.estimate, (*messages, *again.messages))
    return Sliced(stl.name, ok, wall, cpu, layers, estimate, messages)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, help="keep the STL and G-code files here")
    parser.add_argument("--markdown", action="store_true", help="print a Markdown table")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as scratch:
        folder = args.out or Path(scratch)
        folder.mkdir(parents=True, exist_ok=True)
        home = Path(scratch) / "home"
        home.mkdir()
        results = [slice_one(stl, home) for stl in build_all(folder)]
    if args.markdown:
        print("| STL | sliced | wall (s) | CPU (s) | layers | estimated print | messages |")
        print("| --- | --- | --- | --- | --- | --- | --- |")
    for r in results:
        messages = "; ".join(r.messages) or "none"
        if args.markdown:
            print(f"| {r.name} | {'yes' if r.ok else 'NO'} | {r.wall_s:.2f} | {r.cpu_s:.2f} | "
                  f"{r.layers} | {r.estimate} | {messages} |")
        else:
            print(f"{r.name:34s} {'sliced' if r.ok else 'FAILED':7s} {r.wall_s:6.2f} s wall "
                  f"{r.cpu_s:6.2f} s CPU {r.layers:4d} layers {r.estimate:>12s}  {messages}")
    failed = [r.name for r in results if not r.ok]
    print(f"{len(results) - len(failed)} of {len(results)} sliced; total "
          f"{sum(r.wall_s for r in results):.1f} s wall"
          + (f"; failed: {', '.join(failed)}" if failed else ""))


if __name__ == "__main__":
    main()
