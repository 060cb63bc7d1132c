"""Time of the disc-cam geometry, step by step (run by hand, not in CI).

    python benchmarks/geometry_times.py [REPEATS]

For every disc design in ``designs/``: the dense exact evaluation behind the checks, the sampled
pitch and working curves (the profile computation), the follower simulation over the profile, and
the whole geometry build; then the profile of one design against the tolerance (points, time,
measured deviation and lift error). Median of REPEATS runs (default 20), milliseconds.
"""

from __future__ import annotations

import statistics
import sys
import time
from collections.abc import Callable
from functools import partial
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from camfab.geometry import disc_geometry as G  # noqa: E402
from camfab.pipeline import design_from_text, load_design  # noqa: E402


def median_ms(job: Callable[[], Any], repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        job()
        times.append(time.perf_counter() - start)
    return 1e3 * statistics.median(times)


def main() -> None:
    repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 20
    print(f"{'design':28s} {'dense':>6s} {'pitch':>6s} {'profile':>8s} {'points':>7s} "
          f"{'simulate':>9s} {'all':>6s}   (ms, median of {repeats})")
    for path in sorted((ROOT / "designs").glob("*.yaml")):
        design = load_design(path)
        if design.cam.type != "disc":
            continue
        cam, program = G.disc_cam(design), design.program
        dense = G.dense_curves(cam, program)
        tol = G.segment_tolerances(cam, dense, design.manufacturing.tolerance,
                                   len(program.segments))
        working = G.sample_closed(cam, program, "working", tol)
        profile = G.Profile.from_points(working.xy).ccw()
        print(f"{path.stem:28s} "
              f"{median_ms(partial(G.dense_curves, cam, program), repeats):6.2f} "
              f"{median_ms(partial(G.sample_closed, cam, program, 'pitch', tol), repeats):6.2f} "
              f"{median_ms(partial(G.sample_closed, cam, program, 'working', tol), repeats):8.2f} "
              f"{len(working.xy):7d} "
              f"{median_ms(partial(G.lift_check, cam, program, profile), repeats):9.2f} "
              f"{median_ms(partial(G.disc_geometry, design), repeats):6.2f}")

    text = (ROOT / "designs" / "seed-poly-345.yaml").read_text()
    print("\nseed-poly-345 against the tolerance")
    print(f"{'tolerance mm':>12s} {'points':>7s} {'profile ms':>10s} {'lift error mm':>14s}")
    for tolerance in (0.1, 0.01, 0.001, 0.0001):  # 0.0001 mm: the finest a design takes
        design = design_from_text(text + f"manufacturing: {{tolerance: {tolerance}}}\n")
        cam, program = G.disc_cam(design), design.program
        dense = G.dense_curves(cam, program)
        tol = G.segment_tolerances(cam, dense, tolerance, len(program.segments))
        geom = G.disc_geometry(design)
        ms = median_ms(partial(G.sample_closed, cam, program, "working", tol), repeats)
        print(f"{tolerance:12g} {len(geom.profile.vertices):7d} {ms:10.2f} "
              f"{geom.lift.max_mm:14.2e}")


if __name__ == "__main__":
    main()
