"""Globoidal-cam build time: each step in process, and the build end to end.

    python benchmarks/globoid_speed.py [DESIGN ...] [--runs N]

In process, the libraries loaded, each step of a build of each design (by default the two demo
globoids, at their type's default tolerance of 0.01 mm) is timed: the analysis (the pressure
angle along the contact line, the undercut limit, the groove's fit), the part (the groove's
tube sampled to the tolerance), the files (the blank revolved less the tube with manifold3d,
the STL, DXF and SVG), and the verification (the STL read back and the roller put at 720
poses in it); their shares of the whole come from the same run. Then ``camfab build DESIGN``
in a fresh process, every output. Target: the build under 5 s.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

from timing import ROOT, build_time

DESIGNS = sorted((ROOT / "designs").glob("demo-globoidal-*.yaml"))
MAX_BUILD_S = 5.0


def steps(design_path: Path, runs: int) -> tuple[dict[str, float], int, int]:
    """Median seconds of each step, the tube's vertex count and the STL's face count."""
    sys.path.insert(0, str(ROOT))
    from camfab.export.serialise import serialise
    from camfab.kinds import kind_of
    from camfab.pipeline import ALL_OUTPUTS, analyse, load_design

    design = load_design(design_path)
    kind = kind_of(design.cam.type)
    times: dict[str, list[float]] = {"analysis": [], "part": [], "files": [], "verification": []}
    faces = vertices = 0
    for _ in range(runs + 1):  # the first warms every import
        start = time.perf_counter()
        analysis = analyse(design)
        analysed = time.perf_counter()
        part = kind.part(analysis)
        parted = time.perf_counter()
        files = serialise(design, part, ALL_OUTPUTS)
        written = time.perf_counter()
        kind.verify(analysis, part, files)
        done = time.perf_counter()
        for name, seconds in zip(times, (analysed - start, parted - analysed,
                                         written - parted, done - written), strict=True):
            times[name].append(seconds)
        assert files.stl is not None
        faces = int.from_bytes(files.stl.data[80:84], "little")
        vertices = len(part.made.vertices)
    return ({name: statistics.median(t[1:]) for name, t in times.items()}, vertices, faces)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("designs", nargs="*", type=Path, default=DESIGNS)
    parser.add_argument("--runs", type=int, default=5)
    options = parser.parse_args()
    ok = True
    for path in options.designs:
        step, vertices, faces = steps(path, options.runs)
        build = build_time(path, options.runs)
        total = sum(step.values())
        print(f"{path.stem}: tube of {vertices} vertices, STL of {faces} faces")
        for name, seconds in step.items():
            print(f"  {name:<13} {seconds:.3f} s  ({seconds / total:.0%} of the in-process "
                  "build)")
        print(f"  camfab build  {build:.3f} s (median of {options.runs}, fresh processes; "
              f"target < {MAX_BUILD_S:g} s)")
        ok = ok and build < MAX_BUILD_S
    print(f"target: every build under {MAX_BUILD_S:g} s: {'met' if ok else 'NOT met'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
