"""Drum-cam build time: the groove solid alone, and the build end to end.

    python benchmarks/drum_speed.py [DESIGN] [--runs N]

The groove solid is timed in process, the libraries loaded: the tube mesh of the exact walls,
the drum with its bore, the one subtraction, and the binary STL. The build runs as
``camfab build DESIGN`` in a fresh process (DXF, SVG, STL, report JSON, motion CSV, and the
verification that reads the STL back and runs the roller through it). Targets: the groove solid
under 0.3 s, the build under 2.5 s.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

from timing import ROOT, build_time

DEFAULT_DESIGN = ROOT / "designs" / "demo-cylindrical.yaml"

MAX_SOLID_S = 0.3
MAX_BUILD_S = 2.5


def solid_time(design_path: Path, runs: int) -> tuple[float, int]:
    """Median seconds to make the groove solid and its STL bytes, and the STL's face count."""
    sys.path.insert(0, str(ROOT))
    from camfab.export.stl import render_stl
    from camfab.kinds import kind_of
    from camfab.pipeline import analyse, load_design

    analysis = analyse(load_design(design_path))
    kind = kind_of(analysis.design.cam.type)
    solid = kind.part(analysis).solid
    assert solid is not None, "the groove folds: no solid"
    data = render_stl(solid).data  # warm every import
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        solid = kind.part(analysis).solid
        assert solid is not None
        data = render_stl(solid).data
        times.append(time.perf_counter() - start)
    return statistics.median(times), int.from_bytes(data[80:84], "little")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("design", nargs="?", type=Path, default=DEFAULT_DESIGN)
    parser.add_argument("--runs", type=int, default=7)
    options = parser.parse_args()
    solid, faces = solid_time(options.design, options.runs)
    build = build_time(options.design, options.runs)
    print(f"design: {options.design.name}")
    print(f"groove solid + STL  {solid:.3f} s (median of {options.runs}; {faces} faces)")
    print(f"camfab build        {build:.3f} s (median of {options.runs}, fresh processes)")
    ok = solid < MAX_SOLID_S and build < MAX_BUILD_S
    print(f"targets: solid < {MAX_SOLID_S} s and build < {MAX_BUILD_S} s: "
          f"{'met' if ok else 'NOT met'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
