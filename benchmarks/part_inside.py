"""One 3-D part's files and their read-back in process, and its STEP, with the time spent in the
libraries that make their bytes (:mod:`library_calls`); run by ``part_speed.py`` with the
checkout to time first on ``PYTHONPATH``.

    python benchmarks/part_inside.py DESIGN RUNS

Prints one line of JSON: the medians (s) of *RUNS* after one that warms every import:
``files`` (``serialise`` and the kind's ``verify``), ``files_libraries`` (manifold3d's and
ezdxf's calls within them), ``solid`` (manifold3d building the solid alone and handing over its
mesh), ``step`` (the STEP written and checked) and ``step_libraries`` (OpenCASCADE's and
LAPACK's calls within it).
"""

from __future__ import annotations

import json
import statistics
import sys
import time
from pathlib import Path

from library_calls import tallied


def main() -> None:
    from camfab.export.ezdxf_import import load_ezdxf
    from camfab.export.serialise import serialise
    from camfab.export.step import check_step, render_step
    from camfab.export.stl import build
    from camfab.kinds import kind_of
    from camfab.pipeline import ALL_OUTPUTS, analyse, load_design

    load_ezdxf()  # as camfab imports it, before its calls are timed
    design = load_design(Path(sys.argv[1]))
    kind = kind_of(design.cam.type)
    analysis = analyse(design)
    part = kind.part(analysis)
    tolerance = design.manufacturing.tolerance
    times: dict[str, list[float]] = {"files": [], "solid": [], "step": []}
    libraries: dict[str, list[float]] = {}
    for _ in range(int(sys.argv[2]) + 1):  # the first warms every import
        with tallied("manifold3d", "ezdxf") as inside:
            start = time.perf_counter()
            files = serialise(design, part, ALL_OUTPUTS)
            kind.verify(analysis, part, files)
            times["files"].append(time.perf_counter() - start)
        start = time.perf_counter()
        build(part.solid, []).to_mesh64()
        times["solid"].append(time.perf_counter() - start)
        assert files.stl is not None
        measured = (files.stl.volume_mm3, tolerance * files.stl.area_mm2)
        with tallied("OpenCASCADE", "LAPACK") as step_inside:
            start = time.perf_counter()
            check_step(render_step(part.solid, design.name), part.solid, tolerance, measured)
            times["step"].append(time.perf_counter() - start)
        for library, seconds in (*inside.items(), *step_inside.items()):
            libraries.setdefault(library, []).append(seconds)
    median = {name: statistics.median(values[1:]) for name, values in times.items()}
    spent = {name: statistics.median(values[1:]) for name, values in libraries.items()}
    print(json.dumps({**median,
                      "files_libraries": {k: spent[k] for k in ("manifold3d", "ezdxf")},
                      "step_libraries": {k: spent[k] for k in ("OpenCASCADE", "LAPACK")}}))


if __name__ == "__main__":
    main()
