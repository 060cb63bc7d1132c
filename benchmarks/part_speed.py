"""3-D parts against plates: ``camfab build`` of a disc, a drum and the two globoids, with and
without ``--step``, in fresh processes beside the import floor; and in process, each part's
files and their read-back, and its STEP; and beside each, the share of it no change of
camfab's that keeps every byte can cut.

    python benchmarks/part_speed.py [--runs N] [--before CHECKOUT]

The floor is a bare ``python -c "import numpy, ezdxf, manifold3d"``, timed in the same rounds
as the builds (the machine is shared: only ratios from one run mean anything). Each build
writes every output (DXF, SVG, STL, report, motion CSV) and reads them back; with ``--step``
it writes and checks the STEP too (the ``step`` extra). In process (``part_inside.py``), the
libraries loaded and the part made, the files are written and read back (``serialise`` and the
kind's ``verify``), and the STEP written and checked.

The share no byte-keeping change can cut is the libraries' (:mod:`library_calls`): importing
every module of another package the build imports (a fresh process importing just those, timed
in the same rounds), and the calls that make the bytes (manifold3d's and ezdxf's within the
files, OpenCASCADE's and LAPACK's within the STEP). A target below its share is out of reach
while the outputs stay byte for byte the same.

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
from typing import Any

from timing import ROOT, compile_package, modules_of_build, wall_in

FLOOR = "import numpy, ezdxf, manifold3d"
#: (label, design, largest build ratio to the floor or None, most seconds --step may add,
#: most seconds in process for the files and their read-back or None)
PARTS = (("disc", "seed-10-4", None, 1.0, None),
         ("drum", "demo-cylindrical", 2.4, 2.0, 0.12),
         ("globoid concave", "demo-globoidal-concave", 3.5, 2.0, 0.4),
         ("globoid convex", "demo-globoidal-convex", 3.5, 2.0, 0.4))

HERE = Path(__file__).resolve().parent

#: The imports of a list of modules, each skipped should it not import on its own; the process
#: ends as ``camfab`` ends, its objects out of the garbage collector's reach.
_IMPORTS = """
import atexit, gc, importlib, sys
atexit.register(gc.freeze)
for name in sys.argv[1:]:
    try:
        importlib.import_module(name)
    except Exception:
        pass
"""


def _env(checkout: Path | None) -> dict[str, str]:
    """The environment that runs *checkout*'s camfab (None: this one's)."""
    return {**os.environ, "PYTHONPATH": str((checkout or ROOT).resolve())}


def _in_process(design: Path, runs: int, env: dict[str, str]) -> dict[str, Any]:
    """The files and read-back of *design*, and its STEP, in process (``part_inside.py``)."""
    out = subprocess.run([sys.executable, str(HERE / "part_inside.py"), str(design), str(runs)],
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
        compile_package(options.before)
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
            for step in ("", " --step"):  # the libraries' imports of this checkout's build
                modules = [module for module in modules_of_build(Path(design), *step.split())
                           if module.split(".")[0] != "camfab"
                           and not any(part.startswith("_") for part in module.split("."))]
                commands[f"{label}{step} imports"] = (
                    [sys.executable, "-c", _IMPORTS, *modules], _env(None))
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
        imports, step_imports = median[f"{label} imports"], median[f"{label} --step imports"]
        for suffix, checkout in checkouts.items():
            build, step = median[f"{label}{suffix}"], median[f"{label} --step{suffix}"]
            ratio, added = build / floor, step - build
            inside = _in_process(ROOT / "designs" / f"{name}.yaml", options.runs,
                                 _env(checkout))
            calls, step_calls = inside["files_libraries"], inside["step_libraries"]
            least = imports + sum(calls.values())
            least_added = step_imports - imports + sum(step_calls.values())
            least_files = sum(calls.values())
            print(f"{label}{suffix} ({name})")
            print(f"  build {build:.3f} s, {ratio:.2f}× the floor"
                  + (f" (target ≤ {most_ratio}×)" if most_ratio is not None else "")
                  + f"; the libraries: imports {imports:.3f} s, manifold3d's and ezdxf's calls "
                  f"{least_files:.3f} s: {least / floor:.2f}× the floor"
                  + _reach(least / floor, most_ratio))
            print(f"  --step adds {added:.3f} s (target ≤ {most_step} s); the libraries: "
                  f"imports {step_imports - imports:.3f} s, OpenCASCADE's calls "
                  f"{step_calls['OpenCASCADE']:.3f} s, LAPACK's {step_calls['LAPACK']:.3f} s: "
                  f"{least_added:.3f} s" + _reach(least_added, most_step)
                  + f"; in process, the STEP written and checked {inside['step']:.3f} s")
            print(f"  in process, files and read-back {inside['files']:.3f} s"
                  + (f" (target ≤ {most_files} s)" if most_files is not None else "")
                  + f"; manifold3d's calls {calls['manifold3d']:.3f} s, ezdxf's "
                  f"{calls['ezdxf']:.3f} s: {least_files:.3f} s" + _reach(least_files, most_files)
                  + f"; manifold3d's solid alone {inside['solid']:.3f} s")
            if suffix:
                continue
            ok = ok and added <= most_step and (most_ratio is None or ratio <= most_ratio)
            ok = ok and (most_files is None or inside["files"] <= most_files)
    print(f"targets: {'met' if ok else 'NOT met'}")
    return 0 if ok else 1


def _reach(least: float, target: float | None) -> str:
    """Whether a *target* stays within reach of the *least* the libraries take."""
    if target is None:
        return ""
    return " (out of reach with every byte kept)" if least > target else " (within reach)"


if __name__ == "__main__":
    sys.exit(main())
