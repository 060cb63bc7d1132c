"""A linear cam's files, made and read back: the DXF's CUT outline is read as a reader of the
file would (the kerf taken back off), the follower run over it along the whole stroke and its
height compared with base_height + s; the outline's distance from the exact working curve is
measured; the STL is read back and checked closed, outward and of the plate's volume.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from camfab.kinds.readback import Verification, against_cut, named, read_part

if TYPE_CHECKING:
    from camfab.analysis.findings import Finding
    from camfab.analysis.kinematics import MotionUnits, SegmentStats
    from camfab.analysis.record import Analysis
    from camfab.design import Design
    from camfab.export.stl import StlCheck
    from camfab.geometry.linear import LinearGeometry
    from camfab.geometry.profile import Profile
    from camfab.motion.program import MotionProgram


def linear_contours(analysis: Analysis) -> tuple[Profile, Profile, Profile | None]:
    """What the DXF draws (mm): the CUT contour (the plate, or a laser beam's path kerf/2 outside
    it), the pitch curve as an open chain of lines and arcs, and a milling cutter's centre path
    (None without ``cutter_radius``)."""
    from camfab.geometry.linear import fit_open, offset_plate

    design, geom = analysis.design, analysis.linear
    assert geom is not None
    tolerance = geom.tolerance
    kerf = design.manufacturing.kerf
    cut = geom.outline if kerf <= 0.0 else offset_plate(geom.chain, kerf / 2.0, tolerance)
    cutter = design.manufacturing.cutter_radius
    toolpath = None if cutter <= 0.0 else offset_plate(geom.chain, cutter, tolerance)
    pitch = fit_open(geom.pitch.xy, geom.pitch_corners, tolerance)
    return cut, pitch, toolpath


def exact_working(geom: LinearGeometry, distance: float = 0.0) -> np.ndarray:
    """The exact working curve over the stroke (mm) on the analysis grid, moved *distance* (mm)
    out of the plate along its normal (a laser beam's path for kerf/2); the raw envelope's
    folds left out."""
    working = geom.dense.working
    xy = working.xy[~geom.folds]
    if distance == 0.0:
        return xy
    normal = np.stack((-working.tangent[:, 1], working.tangent[:, 0]), axis=-1)[~geom.folds]
    return xy + distance * normal


def verify_linear(analysis: Analysis,
                  requested: tuple[str, ...]) -> tuple[Verification, dict[str, dict[str, bytes]]]:
    """Make the DXF (always: it is what is verified), and the SVG and STL when *requested*, read
    them back and run the follower over the CUT outline."""
    from camfab.export.linear_files import render_linear_dxf, render_linear_stl
    from camfab.geometry.linear import lift_check
    from camfab.geometry.plate import Contours

    design, geom = analysis.design, analysis.linear
    assert geom is not None
    cut, pitch, toolpath = linear_contours(analysis)
    files: dict[str, bytes] = {}
    stl_check: StlCheck | None = None
    if "stl" in requested:
        from camfab.export.stl import check_stl

        made = render_linear_stl(analysis)
        if made is not None:
            files["stl"], volume, allowance = made
            stl_check = check_stl(files["stl"], volume, allowance)
    dxf = render_linear_dxf(analysis, cut, pitch, toolpath)
    files["dxf"] = dxf
    kerf = design.manufacturing.kerf
    written, part, source = read_part(dxf, design.mm_per_unit, kerf, geom.tolerance,
                                      f"{design.name}.dxf")
    lift = lift_check(geom.cam, analysis.program, part)
    deviation = None
    if not geom.undercut:
        deviation = float(written.distance(exact_working(geom, kerf / 2.0)).max())
    if "svg" in requested:
        from camfab.export.svg import render_svg

        files["svg"] = render_svg(analysis, Contours((cut,)))
    cut_error = (against_cut(lift, geom.lift, design.manufacturing.tolerance)
                 if geom.undercut else None)
    check = Verification(lift, source, len(written.vertices), deviation, stl_check,
                         exempt=geom.undercut, cut_error=cut_error)
    return check, named(design.name, files)


class Linear:
    """The linear (translating, wedge) cam (``cam.type: linear``)."""

    drives_both_ways = False

    @staticmethod
    def analyse(design: Design, program: MotionProgram, units: MotionUnits,
                stats: list[SegmentStats], findings: list[Finding]) -> Analysis:
        """The plate's exact curves, numbers and checks (before *findings*)."""
        from camfab.analysis.linear_checks import analyse_linear

        return analyse_linear(design, program, units, stats, findings)

    @staticmethod
    def files(analysis: Analysis, requested: tuple[str, ...]) -> tuple[
            Analysis, Verification, dict[str, dict[str, bytes]], dict[str, str]]:
        check, files = verify_linear(analysis, requested)
        return analysis, check, files, {}


KIND = Linear()
