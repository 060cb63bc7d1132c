"""What STEP adds to a build: ``camfab build`` with and without ``--step``, fresh processes.

    python benchmarks/step_speed.py [DESIGN ...] [--runs N]

For each design (by default a disc cam, seed-10-4, a conjugate pair, demo-conjugate, a drum
cam, demo-cylindrical, and a globoidal cam, demo-globoidal-convex) the two builds alternate in
one run, medians of N; then in process, the libraries loaded, the STEP written and read back (its
check; a drum's or a globoid's held to its STL's volume) for the part. Needs the ``step`` extra
(``pip install 'camfab[step]'``).
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

from timing import ROOT, compile_package, wall

DESIGNS = [ROOT / "designs" / name for name in
           ("seed-10-4.yaml", "demo-conjugate.yaml", "demo-cylindrical.yaml",
            "demo-globoidal-convex.yaml")]


def builds(path: Path, runs: int) -> tuple[float, float]:
    """Median wall seconds of ``camfab build`` without and with ``--step``."""
    compile_package()
    plain, step = [], []
    with tempfile.TemporaryDirectory() as folder:
        base = [sys.executable, "-m", "camfab", "build", str(path), "-o", folder]
        for _ in range(runs + 1):
            plain.append(wall(base))
            step.append(wall([*base, "--step"]))
    return statistics.median(plain[1:]), statistics.median(step[1:])


def in_process(path: Path, runs: int) -> tuple[float, float, int] | None:
    """Median seconds to write the STEP and to read it back and check it, and its bytes (None
    for a part with no exact solid)."""
    sys.path.insert(0, str(ROOT))
    from camfab.export.step import NotExact, check_step, render_step
    from camfab.export.stl import render_stl
    from camfab.kinds import kind_of
    from camfab.pipeline import analyse, load_design

    design = load_design(path)
    analysis = analyse(design)
    solid = kind_of(design.cam.type).part(analysis).solid
    if solid is None:
        return None
    try:
        step = render_step(solid, design.name)
    except NotExact:
        return None
    tolerance = design.manufacturing.tolerance
    stl = render_stl(solid)  # a drum's STEP is held to its STL's volume
    measured = (stl.volume_mm3, tolerance * stl.area_mm2)
    check_step(step, solid, tolerance, measured)  # warm
    written, checked = [], []
    for _ in range(runs):
        start = time.perf_counter()
        step = render_step(solid, design.name)
        middle = time.perf_counter()
        check_step(step, solid, tolerance, measured)
        written.append(middle - start)
        checked.append(time.perf_counter() - middle)
    return statistics.median(written), statistics.median(checked), len(step.data)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("designs", nargs="*", type=Path, default=DESIGNS)
    parser.add_argument("--runs", type=int, default=5)
    options = parser.parse_args()
    for path in options.designs:
        plain, step = builds(path, options.runs)
        inner = in_process(path, options.runs)
        print(f"{path.stem}: camfab build {plain:.3f} s, with --step {step:.3f} s "
              f"(+{step - plain:.3f} s, {step / plain:.2f}×)")
        if inner is None:
            print("  no STEP for this part (no exact solid)")
        else:
            written, checked, size = inner
            print(f"  in process: STEP written {written:.3f} s ({size:,} bytes), read back and "
                  f"checked {checked:.3f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
