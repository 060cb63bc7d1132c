"""The drum (cylindrical) cam: a groove cut round a cylinder drives a translating roller along
the drum's axis (THEORY §C). Its STL is read back and the roller run through the groove between
the wall vertices it finds; the groove developed at the surface (DXF, SVG) is measured against
the exact walls.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from camfab.kinds.readback import Verification, named

if TYPE_CHECKING:
    from camfab.analysis.findings import Finding
    from camfab.analysis.kinematics import MotionUnits, SegmentStats
    from camfab.analysis.record import Analysis
    from camfab.design import Design
    from camfab.motion.program import MotionProgram

#: Cam-angle step at which the roller is run through a drum's groove read back from the STL.
DRUM_VERIFY_STEP = math.radians(0.5)


class Drum:
    """The drum cam (``cam.type: cylindrical``)."""

    drives_both_ways = False

    @staticmethod
    def analyse(design: Design, program: MotionProgram, units: MotionUnits,
                stats: list[SegmentStats], findings: list[Finding]) -> Analysis:
        """The groove's dense walls, the drum's numbers and checks (before *findings*)."""
        from camfab.analysis.drum_checks import drum_findings, drum_numbers
        from camfab.analysis.record import Analysis
        from camfab.geometry.drum import drum, drum_dense

        dense = drum_dense(drum(design), program)
        drum_nums = drum_numbers(dense, len(program.segments))
        findings = [*drum_findings(design, dense, drum_nums), *findings]
        return Analysis(design, program, units, stats, findings, numbers=drum_nums, drum=dense)

    @staticmethod
    def files(analysis: Analysis, requested: tuple[str, ...]) -> tuple[
            Analysis, Verification, dict[str, dict[str, bytes]], dict[str, str]]:
        check, single, withheld = drum_files(analysis)
        return analysis, check, named(analysis.design.name, single), withheld


KIND = Drum()


def drum_files(analysis: Analysis) -> tuple[Verification, dict[str, bytes], dict[str, str]]:
    """The drum's STL (unless its groove folds), developed DXF and SVG, read back: the roller
    run through the groove of the STL between its wall rows, the developed walls measured."""
    from camfab.export.dxf import read_cut_outline, render_development_dxf
    from camfab.export.stl import check_stl, read_stl, render_drum_stl
    from camfab.export.svg import render_svg
    from camfab.geometry.arcfit import fit_arcs
    from camfab.geometry.disc_geometry import LiftCheck
    from camfab.geometry.drum_mesh import development, groove_lift, groove_tube, row_points
    from camfab.geometry.plate import Contours
    from camfab.geometry.sampling import SAMPLING_SHARE
    from camfab.motion.program import cycle_angles

    design, dense = analysis.design, analysis.drum
    assert dense is not None
    d, program = dense.drum, analysis.program
    tolerance = SAMPLING_SHARE * design.manufacturing.tolerance
    files: dict[str, bytes] = {}
    withheld: dict[str, str] = {}
    folded = any(f.id == "groove" and not f.ok for f in analysis.findings)
    if folded:
        # the inner wall folds over itself: no solid a roller could run in. The roller is run
        # between the exact walls as computed, to show how far the fold would throw it.
        tube = groove_tube(d, program, tolerance)
        vertices, faces = tube.vertices, tube.faces
        stl_check = None
        withheld["stl"] = ("the groove folds over itself (see the groove check): there is no "
                           "solid a roller could run in")
        source = "the exact walls (the groove folds: no STL)"
    else:
        # the solid, read back
        stl, volume, area = render_drum_stl(analysis)
        mesh = read_stl(stl)
        stl_check = check_stl(stl, volume, design.manufacturing.tolerance * area, mesh)
        vertices = np.asarray(mesh.vertices, dtype=np.float64)
        faces = np.asarray(mesh.faces)
        files["stl"] = stl
        source = (f"the roller run through the groove of {design.name}.stl read back (between "
                  f"its wall rows)")
    # the roller run between the wall vertices found, and points along the rows' edges between
    # them no further apart than a quarter of the roller's radius
    theta = cycle_angles(DRUM_VERIFY_STEP)
    centre_z = d.start + program.evaluate(theta)[0]
    surface = row_points(d, vertices, faces, d.roller / 4.0, d.axis_angle(theta))
    low, high = groove_lift(d, surface, theta, centre_z)
    found = np.isfinite(low) & np.isfinite(high)  # the roller meets both walls
    error = np.full(theta.size, np.inf)
    error[found] = 0.5 * (low[found] + high[found]) - centre_z[found]
    # the developed groove: the walls at the surface, closed across the seam
    dev = development(d, program, tolerance)
    band = fit_arcs(np.vstack((dev.lower, dev.upper[::-1])), tolerance)
    centre = fit_arcs(dev.centre, tolerance, closed=False)
    dxf = render_development_dxf(analysis, band, centre, (dev.width, dev.height))
    written = read_cut_outline(dxf, design.mm_per_unit)
    exact = development(d, program, tolerance / 64.0)
    deviation = float(written.distance(np.vstack((exact.lower, exact.upper))).max())
    files["dxf"] = dxf
    files["svg"] = render_svg(analysis, Contours((band,)))
    check = Verification(LiftCheck(theta, error, error), source, len(written.vertices),
                         deviation, stl_check, exempt=folded)
    return check, files, withheld
