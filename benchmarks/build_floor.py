"""A disc cam's and a drum cam's whole build against the import floor of the libraries no build
can do without.

    python benchmarks/build_floor.py [--runs N] [--before CHECKOUT]

Each build is ``camfab build DESIGN`` in a fresh process, as a user runs it, with every output
(DXF, SVG, STL, HTML and JSON report, motion CSV) and the verification that reads the files
back. The floor is a bare ``python -c "import numpy, ezdxf, manifold3d"``: a disc build needs
numpy for its curves, ezdxf for its DXF and manifold3d for its solid. camfab is byte-compiled
first, as ``pip install`` leaves it. The floor and the builds run in turn, N times each, and
the medians are compared, all in one run (the machine is shared: only ratios from one run
mean anything).

With ``--before``, the same builds of another checkout of camfab (its folder, put first on
``PYTHONPATH``) run in the same rounds, for the numbers before a change next to those after.

Targets: the disc build (designs/seed-10-4.yaml) at most 1.5× the floor and under 1.0 s; the
drum build (designs/demo-cylindrical.yaml) at most 1.8× the floor.

Beside the floor, the same rounds time the import of every library a disc build loads, the ones
the project names for their jobs (shapely for the plate's booleans, pydantic for the design
file, PyYAML to read it, click for the command line, Jinja2 for the report) with the floor's
three: what no build of camfab, however lean its own code, can take less than. And for each build,
its imports alone: every module the build ends with (camfab's and the libraries'), ezdxf loaded
as camfab loads it and the report's template compiled, nothing built, and the exit camfab has
(the objects frozen out of the collector's reach); the build less this is its work.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
from pathlib import Path

from timing import ROOT, compile_package, modules_of_build, wall_in

FLOOR = "import numpy, ezdxf, manifold3d"
#: Every library a disc build imports (``sys.modules`` after ``camfab build``, less the standard
#: library and their own dependencies).
LIBRARIES = "import numpy, ezdxf, manifold3d, shapely, pydantic, yaml, click, jinja2"
#: (label, design, largest ratio to the floor, largest wall time in seconds or None)
BUILDS = (("disc", ROOT / "designs" / "seed-10-4.yaml", 1.5, 1.0),
          ("drum", ROOT / "designs" / "demo-cylindrical.yaml", 1.8, None))


def _imports_of(design: Path) -> str:
    """A program that imports what ``camfab build`` of *design* imports, and builds nothing."""
    names = [name for name in modules_of_build(design)
             if name.startswith("camfab.") or "." not in name]
    return (f"import {', '.join(names)}\n"
            "from camfab.export.ezdxf_import import load_ezdxf\n"
            "from camfab.export.report_html import REPORT_TEMPLATE, page_template\n"
            "load_ezdxf()\npage_template(REPORT_TEMPLATE)\n"
            "import atexit, gc\natexit.register(gc.freeze)\n")  # the exit camfab's has


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=9)
    parser.add_argument("--before", type=Path, help="another checkout of camfab to time too")
    options = parser.parse_args()
    compile_package()
    with tempfile.TemporaryDirectory() as folder:
        commands: dict[str, tuple[list[str], dict[str, str] | None]] = {
            "floor": ([sys.executable, "-c", FLOOR], None),
            "libraries": ([sys.executable, "-c", LIBRARIES], None)}
        for label, design, _, _ in BUILDS:
            build = [sys.executable, "-m", "camfab", "build", str(design), "-o"]
            commands[label] = ([*build, str(Path(folder) / label)], None)
            commands[f"{label} imports"] = ([sys.executable, "-c", _imports_of(design)], None)
            if options.before is not None:
                env = {**os.environ, "PYTHONPATH": str(options.before.resolve())}
                commands[f"{label} before"] = ([*build, str(Path(folder) / f"{label}-0")], env)
        if options.before is not None:
            compile_package(options.before)
        times = {label: [] for label in commands}
        for command, env in commands.values():
            wall_in(command, env)  # warm the file cache
        for _ in range(options.runs):
            for label, (command, env) in commands.items():
                times[label].append(wall_in(command, env))
    floor = statistics.median(times["floor"])
    libraries = statistics.median(times["libraries"])
    print(f"floor ({FLOOR}): {floor:.3f} s (median of {options.runs}, "
          f"min {min(times['floor']):.3f})")
    print(f"libraries ({LIBRARIES}): {libraries:.3f} s (min {min(times['libraries']):.3f}); "
          f"{libraries / floor:.2f}× the floor")
    ok = True
    for label, design, most, seconds in BUILDS:
        if options.before is not None:
            before = statistics.median(times[f"{label} before"])
            print(f"{label} build before ({design.name}): {before:.3f} s "
                  f"(min {min(times[f'{label} before']):.3f}); {before / floor:.2f}× the floor")
        build = statistics.median(times[label])
        imports = statistics.median(times[f"{label} imports"])
        print(f"{label} build's imports alone: {imports:.3f} s "
              f"(min {min(times[f'{label} imports']):.3f}); {imports / floor:.2f}× the floor, "
              f"its work {build - imports:.3f} s")
        ratio = build / floor
        met = ratio <= most and (seconds is None or build < seconds)
        ok = ok and met
        limit = f"≤ {most}×" + (f" and < {seconds} s" if seconds is not None else "")
        print(f"{label} build ({design.name}): {build:.3f} s (min {min(times[label]):.3f}); "
              f"{ratio:.2f}× the floor, {build / libraries:.2f}× the libraries; target {limit}: "
              f"{'met' if met else 'NOT met'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
