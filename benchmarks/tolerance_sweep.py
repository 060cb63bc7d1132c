"""Profile computation against the export tolerance, for disc cams (in process).

    python benchmarks/tolerance_sweep.py [DESIGN...] [--runs N] [--tolerances T...]

For each design (by default ``seed-10-4``, an offset roller with a harmonic rise and a
uniform-acceleration return, and ``seed-poly-345``) the design is rebuilt with
``manufacturing.tolerance`` set to each value (``design_from_mapping`` of the YAML with that one
key changed) and measured:

- ``geometry ms``: ``disc_geometry(design)``, median of N runs: the dense exact evaluation, the
  pitch and working curves sampled within the tolerance, and the follower run over the profile;
- ``points``: vertices of the sampled profile (the working curve, loops trimmed) and of the
  sampled pitch curve;
- ``entities``: the lines and arcs of the DXF CUT outline read back (the profile fitted with arcs
  within the tolerance), and ``dxf ms``, median of N runs of ``verify_exports(analysis,
  ("dxf",))`` (writing the DXF, reading it back, the follower run over it);
- ``lift err``: ``geometry.lift.max_mm``, the follower run over the sampled profile, and the
  verification's, the follower run over the CUT outline read back from the DXF (what the report
  calls ``max_lift_error_mm``), both against the design's s(θ) every 0.1°, in mm; and the
  outline's largest distance from the exact working curve (``deviation``).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import yaml
from timing import ROOT, median_seconds, use_checkout

DEFAULT_DESIGNS = (ROOT / "designs" / "seed-10-4.yaml", ROOT / "designs" / "seed-poly-345.yaml")
DEFAULT_TOLERANCES = (0.1, 0.01, 0.001, 0.0001)

HEADER = ("tolerance mm", "geometry ms", "profile pts", "pitch pts", "entities", "dxf ms",
          "lift err mm", "DXF lift err mm", "deviation mm")


def with_tolerance(data: dict[str, Any], tolerance: float) -> dict[str, Any]:
    """The design mapping *data* with ``manufacturing.tolerance`` set to *tolerance*."""
    manufacturing = {**(data.get("manufacturing") or {}), "tolerance": tolerance}
    return {**data, "manufacturing": manufacturing}


def sweep(path: Path, tolerances: tuple[float, ...], runs: int) -> list[tuple[Any, ...]]:
    """One row of :data:`HEADER` per tolerance for the design in *path*."""
    from camfab.geometry.disc_geometry import disc_geometry
    from camfab.pipeline import analyse, design_from_mapping, verify_exports

    data = yaml.safe_load(path.read_text())
    verify_exports(analyse(design_from_mapping(data, file=path.name)), ("dxf",))  # warm up
    rows = []
    for tolerance in tolerances:
        design = design_from_mapping(with_tolerance(data, tolerance), file=path.name)
        seconds = median_seconds(lambda d=design: disc_geometry(d), runs)
        analysis = analyse(design)
        geom = analysis.geometry
        assert geom is not None, f"{path.name} is not a disc cam"
        dxf_s = median_seconds(lambda a=analysis: verify_exports(a, ("dxf",)), runs)
        verified, _ = verify_exports(analysis, ("dxf",))
        check = verified.verification
        assert check is not None
        deviation = float("nan") if check.deviation_mm is None else check.deviation_mm
        rows.append((tolerance, 1e3 * seconds, len(geom.profile.vertices),
                     len(geom.pitch.xy), check.entities, 1e3 * dxf_s, geom.lift.max_mm,
                     check.lift.max_mm, deviation))
    return rows


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("designs", nargs="*", type=Path, default=list(DEFAULT_DESIGNS))
    parser.add_argument("--runs", type=int, default=7, help="runs per median (default 7)")
    parser.add_argument("--tolerances", type=float, nargs="+", default=list(DEFAULT_TOLERANCES))
    parser.add_argument("--markdown", action="store_true", help="print Markdown tables")
    options = parser.parse_args()
    use_checkout()
    for path in options.designs:
        rows = sweep(path, tuple(options.tolerances), options.runs)
        print(f"\n{path.stem} (median of {options.runs} runs)\n")
        if options.markdown:
            print("| " + " | ".join(HEADER) + " |")
            print("|" + "---:|" * len(HEADER))
        else:
            print("  ".join(f"{h:>12s}" for h in HEADER))
        for row in rows:
            cells = (f"{row[0]:g}", f"{row[1]:.1f}", str(row[2]), str(row[3]), str(row[4]),
                     f"{row[5]:.1f}", f"{row[6]:.2e}", f"{row[7]:.2e}", f"{row[8]:.2e}")
            if options.markdown:
                print("| " + " | ".join(cells) + " |")
            else:
                print("  ".join(f"{c:>12s}" for c in cells), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
