"""A groove cam's files, made and read back: the DXF's ``POCKET`` walls are read as a reader of
the file would and the roller is run against both of them; the STL is read back and checked
closed, outward and of the part's volume.

The inner wall is checked as a disc cam's profile is: the roller (its radius plus half the
clearance, the contact the groove gives it) is pressed onto it from outside at every 0.1° and its
lift compared with the design. The outer wall pulls the roller back and cannot be pressed onto
from outside, so at every 0.1° the exact roller centre's distance from each wall read back is
measured: less the roller's radius and divided by cos φ it is the follower's displacement that
wall would cause (a wall δ off along the normal moves the follower δ/cos φ along its path).
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from camfab.kinds.readback import Verification, named

if TYPE_CHECKING:
    from camfab.analysis.findings import Finding
    from camfab.analysis.kinematics import MotionUnits, SegmentStats
    from camfab.analysis.record import Analysis
    from camfab.design import Design
    from camfab.geometry.plate import Contours
    from camfab.geometry.profile import Profile
    from camfab.motion.program import MotionProgram


def verify_groove(analysis: Analysis, requested: tuple[str, ...]) -> tuple[
        Verification, dict[str, dict[str, bytes]]]:
    """Make the groove cam's files (DXF always: the verification reads it; STL and SVG when
    *requested*), read them back and run the roller against both walls."""
    from camfab.export.groove_dxf import read_groove_dxf, render_groove_dxf
    from camfab.geometry.groove import wall_lift_check
    from camfab.geometry.plate import Contours, holes, offset_holes

    design, geom, walls = analysis.design, analysis.geometry, analysis.groove
    assert geom is not None and walls is not None
    part_holes = holes(design)
    kerf = design.manufacturing.kerf
    cut = Contours(part_holes.profiles, (walls.outer_radius, *part_holes.circles))
    if kerf > 0.0:
        beam = offset_holes(part_holes, kerf / 2.0, geom.tolerance)
        cut = Contours(beam.profiles, (walls.outer_radius + kerf / 2.0, *beam.circles))
    files: dict[str, bytes] = {}
    stl_check = None
    if "stl" in requested:
        from camfab.export.groove_stl import groove_volume, render_groove_stl
        from camfab.export.stl import check_stl

        stl = render_groove_stl(analysis, part_holes)
        files["stl"] = stl
        stl_check = check_stl(stl, *groove_volume(analysis, part_holes))
    dxf = render_groove_dxf(analysis, cut, _toolpath(analysis, part_holes), kerf)
    files["dxf"] = dxf
    drawing = read_groove_dxf(dxf, design.mm_per_unit)
    if len(drawing.pocket) < 2:
        raise ValueError(f"{design.name}.dxf: the POCKET layer holds {len(drawing.pocket)} "
                         "closed contours, not the groove's two walls")
    outer, inner = drawing.pocket[0], drawing.pocket[1]
    lift = wall_lift_check(geom.cam, analysis.program, walls.radius, inner, outer)
    deviation = None
    if not walls.folded:
        circle = drawing.cut_circles[0] if drawing.cut_circles else np.inf
        deviation = float(max(inner.distance(geom.dense.working.xy).max(),
                              outer.distance(walls.outer_dense.xy).max(),
                              abs(circle - (walls.outer_radius + kerf / 2.0))))
    if "svg" in requested:
        from camfab.export.svg import render_svg

        files["svg"] = render_svg(analysis, cut, Contours((walls.inner, walls.outer)))
    source = (f"the POCKET walls read back from {design.name}.dxf: the roller (radius "
              f"{walls.radius:.6g} mm with half the clearance) pressed onto the inner wall, and "
              f"the roller centre's distance from each wall less that radius, over cos φ")
    check = Verification(lift, source, len(inner.vertices) + len(outer.vertices), deviation,
                         stl_check, exempt=walls.folded)
    return check, named(design.name, files)


def _toolpath(analysis: Analysis, part_holes: Contours) -> Contours | None:
    """A milling cutter's centre path (mm): round the plate, inside the holes it fits in, and
    along the groove — on the pitch curve when the cutter is as wide as the groove, else one
    pass along each wall (the pitch curve offset by ± (R − cutter radius)); None without a
    ``cutter_radius``, and no groove pass for a cutter wider than the groove."""
    from camfab.geometry.arcfit import fit_arcs
    from camfab.geometry.disc import DiscCam
    from camfab.geometry.disc_geometry import sample_closed, segment_tolerances
    from camfab.geometry.plate import Contours, offset_holes

    design, geom, walls = analysis.design, analysis.geometry, analysis.groove
    assert geom is not None and walls is not None
    cutter = design.manufacturing.cutter_radius
    if cutter <= 0.0:
        return None
    inside = offset_holes(part_holes, cutter, geom.tolerance)
    passes: list[Profile] = []
    if cutter == walls.radius:
        passes.append(fit_arcs(geom.pitch.xy, geom.tolerance))
    elif cutter < walls.radius:
        # a cam of the same pitch curve whose follower radius is R − cutter: its working and
        # outer curves are the cutter centre's passes
        cam = geom.cam
        fol = replace(cam.follower, radius=walls.radius - cutter)
        tool = DiscCam(fol, cam.base_radius + cutter, cam.sigma)
        program = analysis.program
        tolerances = segment_tolerances(cam, geom.dense, design.manufacturing.tolerance,
                                        len(program.segments))
        for curve in ("working", "outer"):
            xy = sample_closed(tool, program, curve, tolerances).xy
            passes.append(fit_arcs(xy, geom.tolerance))
    return Contours((*passes, *inside.profiles),
                    (walls.outer_radius + cutter, *inside.circles))


class Groove:
    """The face-groove cam (``cam.type: groove``): a disc cam's pitch curve, the roller held
    between the groove's two walls."""

    drives_both_ways = True

    @staticmethod
    def analyse(design: Design, program: MotionProgram, units: MotionUnits,
                stats: list[SegmentStats], findings: list[Finding]) -> Analysis:
        """A plate cam's analysis with the groove's walls and checks."""
        from camfab.analysis.groove_checks import with_groove
        from camfab.kinds.disc import analyse_plate

        return with_groove(analyse_plate(design, program, units, stats, findings))

    @staticmethod
    def files(analysis: Analysis, requested: tuple[str, ...]) -> tuple[
            Analysis, Verification, dict[str, dict[str, bytes]], dict[str, str]]:
        check, files = verify_groove(analysis, requested)
        return analysis, check, files, {}


KIND = Groove()
