"""What the HTML report adds to a build, the Jinja2 import included.

    python benchmarks/report_speed.py [DESIGN] [--runs N]

Each run is a fresh process that builds everything else first (analysis, DXF, SVG, STL and their
verification, so the libraries those use are loaded), then times rendering the report page: the
import of Jinja2, the figures (camfab.export.chart) and the template. Target: under 0.6 s.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
from pathlib import Path

from timing import ROOT, compile_package

DEFAULT_DESIGN = ROOT / "designs" / "seed-jump-eccentric.yaml"

MAX_REPORT_S = 0.6

_RUN = r"""
import sys, time
from camfab.pipeline import load_design
from camfab.pipeline import analyse
from camfab.pipeline import verify_exports
analysis, _ = verify_exports(analyse(load_design(sys.argv[1])), ("dxf", "svg", "stl"))
start = time.perf_counter()
from camfab.export.report_html import render_report_html
page = render_report_html(analysis)
print(time.perf_counter() - start, len(page))
"""


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("design", nargs="?", type=Path, default=DEFAULT_DESIGN)
    parser.add_argument("--runs", type=int, default=7)
    options = parser.parse_args()
    compile_package()
    times, size = [], 0
    for _ in range(options.runs):
        out = subprocess.run([sys.executable, "-c", _RUN, str(options.design)], cwd=ROOT,
                             capture_output=True, text=True, check=True).stdout.split()
        times.append(float(out[0]))
        size = int(out[1])
    report = statistics.median(times)
    print(f"design: {options.design.name}; page of {size / 1024:.0f} KiB")
    print(f"report added: {report:.3f} s (median of {options.runs}; min {min(times):.3f}, "
          f"max {max(times):.3f})")
    ok = report < MAX_REPORT_S
    print(f"target: < {MAX_REPORT_S} s: {'met' if ok else 'NOT met'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
