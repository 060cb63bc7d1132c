"""How a build's cost grows with the motion program: disc cams of 10, 100 and 1,000 segments,
analysed and rendered (every output) in process, against the goal that 1,000 segments build in
under 1.5 s and cost at most twice as much per segment as 10 do.

    python benchmarks/segment_scaling.py [--runs N] [--counts 10 100 1000] [--profile [N]]

Each design is a disc cam with an offset roller follower whose motion repeats a pattern of five
segments (rise, dwell, return, rise, return) with a cycle of standard laws (cycloidal, harmonic,
3-4-5 polynomial, modified sine, 4-5-6-7 polynomial, modified trapezoid) and unequal angles. The
lift of a segment shrinks with the square of its angle, so that every design keeps the same
pressure angles and the same radii of curvature of the pitch curve (the roller never undercuts):
each is a valid design, loaded with ``camfab.pipeline.design_from_text``.

The time of a design is ``render(analyse(design))``: the motion, the geometry, every check, the
DXF, SVG and STL written and read back with the follower run over them, the HTML and JSON
report and the motion CSV; the median of N runs after one untimed build (imports, caches). The
design's loading (YAML and its rules) is timed apart. ``--profile`` prints the N costliest
functions (cumulative time, cProfile) of one build of the largest design.
"""

from __future__ import annotations

import argparse
import cProfile
import io
import math
import pstats
import sys

from timing import median_seconds, seconds, use_checkout

#: Build time goal of the largest design (s), and the largest growth of the cost per segment.
GOAL_SECONDS = 1.5
GOAL_RATIO = 2.0

#: One period of the motion: (kind, relative angle); rises and returns of one lift each.
PATTERN = (("rise", 1.2), ("dwell", 0.6), ("return", 1.2), ("rise", 1.0), ("return", 1.0))

#: The laws rises and returns take in turn.
LAWS = ("cycloidal", "harmonic", "polynomial-345", "modified-sine", "polynomial-4567",
        "modified-trapezoid")

#: Lift per squared radian of segment angle (mm/rad²): s″ stays below 7.5 × 40 mm/rad² (the
#: 4-5-6-7 polynomial's peak), which keeps the pitch curve's convex radius above 5.6 mm, clear of
#: the roller's 4 mm, however many segments share the turn.
LIFT_PER_RAD2 = 40.0

#: The largest lift of one segment (mm): keeps the pressure angle of few long segments sane.
MAX_LIFT = 6.0


def design_text(count: int) -> str:
    """The YAML of a disc cam whose motion program has *count* segments (a multiple of 5)."""
    if count % len(PATTERN):
        raise ValueError(f"the segment count must be a multiple of {len(PATTERN)}")
    unit = 360.0 / (count // len(PATTERN) * sum(weight for _, weight in PATTERN))
    lines = [f"name: segments-{count}",
             f"description: offset roller follower, {count} motion segments",
             "cam:", "  type: disc", "  rotation: ccw", "  speed_rpm: 300",
             "  base_radius: 40", "  thickness: 8", "  bore: 10",
             "follower:", "  type: roller", "  motion: translating", "  offset: 5",
             "  roller_radius: 4", "motion:"]
    laws = 0
    for i in range(count):
        kind, weight = PATTERN[i % len(PATTERN)]
        angle = unit * weight
        if kind == "dwell":
            lines.append(f"  - dwell: {{angle: {angle!r}}}")
            continue
        lift = min(MAX_LIFT, LIFT_PER_RAD2 * math.radians(angle) ** 2)
        law = LAWS[laws % len(LAWS)]
        laws += 1
        lines.append(f"  - {kind}: {{angle: {angle!r}, lift: {lift!r}, law: {law}}}")
    return "\n".join(lines) + "\n"


def build_seconds(count: int, runs: int) -> tuple[float, float, int]:
    """Median seconds of loading the design of *count* segments and of analysing and rendering
    it, and the number of points of its cut profile."""
    from camfab.pipeline import analyse, design_from_text, render

    text = design_text(count)
    load = median_seconds(lambda: design_from_text(text), runs)
    design = design_from_text(text)
    analysis = analyse(design)
    if analysis.exit_code or analysis.geometry is None:
        raise SystemExit(f"the design of {count} segments fails a check")
    build = median_seconds(lambda: render(analyse(design)), runs)
    return load, build, len(analysis.geometry.profile.vertices)


def profile_build(count: int, top: int) -> str:
    """The *top* functions by cumulative time of one build of *count* segments (cProfile)."""
    from camfab.pipeline import analyse, design_from_text, render

    design = design_from_text(design_text(count))
    render(analyse(design))
    profiler = cProfile.Profile()
    profiler.enable()
    render(analyse(design))
    profiler.disable()
    out = io.StringIO()
    pstats.Stats(profiler, stream=out).sort_stats("cumulative").print_stats(top)
    return out.getvalue()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=5, help="runs per median (default 5)")
    parser.add_argument("--counts", type=int, nargs="+", default=[10, 100, 1000],
                        help="segment counts (multiples of 5; default 10 100 1000)")
    parser.add_argument("--profile", type=int, nargs="?", const=25, default=0, metavar="N",
                        help="print the N costliest functions of the largest build (default 25)")
    options = parser.parse_args()
    use_checkout()
    seconds(lambda: build_seconds(min(options.counts), 1))  # imports
    per_segment = {}
    for count in options.counts:
        load, build, points = build_seconds(count, options.runs)
        per_segment[count] = build / count
        print(f"{count:5d} segments: analyse + render {build:.3f} s, "
              f"{1e3 * build / count:.3f} ms per segment ({points} profile points; "
              f"load {load:.3f} s; median of {options.runs})", flush=True)
    small, large = min(options.counts), max(options.counts)
    ratio = per_segment[large] / per_segment[small]
    total = per_segment[large] * large
    print(f"per-segment cost {large} vs {small}: {ratio:.2f}x; goal <= {GOAL_RATIO:g}x: "
          f"{'met' if ratio <= GOAL_RATIO else 'not met'}")
    print(f"{large} segments: {total:.3f} s; goal < {GOAL_SECONDS:g} s: "
          f"{'met' if total < GOAL_SECONDS else 'not met'}")
    if options.profile:
        print(profile_build(large, options.profile))
    return 0


if __name__ == "__main__":
    sys.exit(main())
