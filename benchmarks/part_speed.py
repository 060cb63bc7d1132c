"""3-D parts against plates: ``camfab build`` of a disc, a drum and the two globoids, with and
without ``--step``, in fresh processes beside the import floor; and in process, each 3-D
part's files and their read-back.

    python benchmarks/part_speed.py [--runs N] [--before CHECKOUT]

The floor is a bare ``python -c "import numpy, ezdxf, manifold3d"``, timed in the same rounds
as the builds (the machine is shared: only ratios from one run mean anything). Each build
writes every output (DXF, SVG, STL, report, motion CSV) and reads them back; with ``--step``
it writes and checks the STEP too (the ``step`` extra). In process, the libraries loaded and
the part made, the files are written and read back (``serialise`` and the kind's ``verify``),
beside what manifold3d alone takes to build the solid and hand over its mesh (the part of the
files no change of camfab's can cut).

With ``--before``, the same builds of another checkout of camfab (its folder, put first on
``PYTHONPATH``) run in the same rounds, for the numbers before a change next to those after.

Targets: the drum's build at most 2.4× the floor and each globoid's at most 3.5×; ``--step``
adding at most 1.0 s to the disc's build and 2.0 s to the drum's and each globoid's; in
process, the drum's files and read-back within 0.12 s and each globoid's within 0.4 s.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from timing import ROOT, compile_package, wall_in

FLOOR = "import numpy, ezdxf, manifold3d"
#: (label, design, largest build ratio to the floor or None, most seconds --step may add,
#: most seconds in process for the files and their read-back or None)
PARTS = (("disc", "seed-10-4", None, 1.0, None),
         ("drum", "demo-cylindrical", 2.4, 2.0, 0.12),
         ("globoid concave", "demo-globoidal-concave", 3.5, 2.0, 0.4),
         ("globoid convex", "demo-globoidal-convex", 3.5, 2.0, 0.4))

#: Run with a design's path and a count: the median seconds of its files and their read-back,
#: in process, and of manifold3d building its solid alone (JSON).
_IN_PROCESS = """
import json, statistics, sys, time
from pathlib import Path
from camfab.export.serialise import serialise
from camfab.export.stl import build
from camfab.kinds import kind_of
from camfab.pipeline import ALL_OUTPUTS, analyse, load_design
design = load_design(Path(sys.argv[1]))
kind = kind_of(design.cam.type)
analysis = analyse(design)
part = kind.part(analysis)
files_s, solid_s = [], []
for _ in range(int(sys.argv[2]) + 1):  # the first warms every import
    start = time.perf_counter()
    files = serialise(design, part, ALL_OUTPUTS)
    kind.verify(analysis, part, files)
    files_s.append(time.perf_counter() - start)
    start = time.perf_counter()
    held = []
    build(part.solid, held).to_mesh64()
    solid_s.append(time.perf_counter() - start)
print(json.dumps({"files": statistics.median(files_s[1:]),
                  "solid": statistics.median(solid_s[1:])}))
"""


def _env(checkout: Path | None) -> dict[str, str]:
    """The environment that runs *checkout*'s camfab (None: this one's)."""
    return {**os.environ, "PYTHONPATH": str((checkout or ROOT).resolve())}


def _in_process(design: Path, runs: int, env: dict[str, str]) -> dict[str, float]:
    """The files and read-back of *design*, in process (see :data:`_IN_PROCESS`)."""
    out = subprocess.run([sys.executable, "-c", _IN_PROCESS, str(design), str(runs)],
                         check=True, capture_output=True, text=True, env=env,
                         cwd=env["PYTHONPATH"]).stdout
    return json.loads(out.splitlines()[-1])


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--before", type=Path, help="another checkout of camfab to time too")
    options = parser.parse_args()
    compile_package()
    checkouts: dict[str, Path | None] = {"": None}
    if options.before is not None:
        subprocess.run([sys.executable, "-m", "compileall", "-q",
                        str(options.before / "camfab")], check=True)
        checkouts = {" before": options.before, "": None}
    with tempfile.TemporaryDirectory() as folder:
        commands: dict[str, tuple[list[str], dict[str, str]]] = {
            "floor": ([sys.executable, "-c", FLOOR], _env(None))}
        for label, name, _, _, _ in PARTS:
            design = str(ROOT / "designs" / f"{name}.yaml")
            for suffix, checkout in checkouts.items():
                out = str(Path(folder) / f"{name}{suffix.strip()}")
                build = [sys.executable, "-m", "camfab", "build", design, "-o", out]
                commands[f"{label}{suffix}"] = (build, _env(checkout))
                commands[f"{label} --step{suffix}"] = ([*build, "--step"], _env(checkout))
        times: dict[str, list[float]] = {label: [] for label in commands}
        for command, env in commands.values():
            wall_in(command, env)  # warm the file cache
        for _ in range(options.runs):
            for label, (command, env) in commands.items():
                times[label].append(wall_in(command, env))
    median = {label: statistics.median(t) for label, t in times.items()}
    floor = median["floor"]
    print(f"floor ({FLOOR}): {floor:.3f} s (median of {options.runs}, "
          f"min {min(times['floor']):.3f})")
    ok = True
    for label, name, most_ratio, most_step, most_files in PARTS:
        for suffix, checkout in checkouts.items():
            build, step = median[f"{label}{suffix}"], median[f"{label} --step{suffix}"]
            ratio, added = build / floor, step - build
            inside = _in_process(ROOT / "designs" / f"{name}.yaml", options.runs,
                                 _env(checkout)) if most_files is not None else None
            line = (f"{label}{suffix} ({name}): build {build:.3f} s, {ratio:.2f}× the floor"
                    + (f" (target ≤ {most_ratio}×)" if most_ratio is not None else "")
                    + f"; --step {step:.3f} s, adds {added:.3f} s (target ≤ {most_step} s)")
            if inside is not None:
                line += (f"; in process, files and read-back {inside['files']:.3f} s "
                         f"(target ≤ {most_files} s), manifold3d's solid alone "
                         f"{inside['solid']:.3f} s")
            print(line)
            if suffix:
                continue
            ok = ok and added <= most_step and (most_ratio is None or ratio <= most_ratio)
            ok = ok and (inside is None or most_files is None or inside["files"] <= most_files)
    print(f"targets: {'met' if ok else 'NOT met'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
