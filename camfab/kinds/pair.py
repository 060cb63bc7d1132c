"""The files of the cams that hold their follower on both sides, read back.

A conjugate pair gets a DXF and an SVG per plate (``NAME-a``, ``NAME-b``: cam b drawn as it is
made, half a turn from the frame it is computed in) and one STL of both plates stacked on the
bore, keyway aligned, in their phase relation. Each plate's CUT outline is read back and its own
roller run over it; then both rollers are run over the two outlines together to measure whether
the pair holds the follower. A constant-breadth cam's files are a disc cam's; its outline read
back is run under both faces (or rollers) of the yoke.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING

from camfab.geometry.conjugate import hold, made_geometry, to_made_frame
from camfab.geometry.disc_geometry import VERIFY_STEP, LiftCheck
from camfab.kinds.readback import Verification, against_cut, read_back, verify_plate
from camfab.motion.program import cycle_angles

if TYPE_CHECKING:
    from camfab.analysis.findings import Finding
    from camfab.analysis.kinematics import MotionUnits, SegmentStats
    from camfab.analysis.record import Analysis
    from camfab.design import Design
    from camfab.motion.program import MotionProgram


def verify_partner(analysis: Analysis, requested: tuple[str, ...]) -> tuple[
        Verification, dict[str, dict[str, bytes]]]:
    """The files of a conjugate or constant-breadth cam by output name and file name, and what
    reading them back found (with the hold of the outlines as written)."""
    partner, geom = analysis.partner, analysis.geometry
    assert partner is not None and geom is not None
    name = analysis.design.name
    theta = cycle_angles(VERIFY_STEP)
    if partner.geometry is None:  # constant breadth: one cam, both sides of the yoke
        check, single, back = verify_plate(analysis, requested)
        held = hold(theta, partner.spacing, (back.part, geom.cam), (back.part, geom.cam),
                    math.pi)
        files = {output: {f"{name}.{output}": data} for output, data in single.items()}
        return replace(check, hold=held), files
    return _verify_pair(analysis, requested)


def _verify_pair(analysis: Analysis, requested: tuple[str, ...]) -> tuple[
        Verification, dict[str, dict[str, bytes]]]:
    from camfab.export.dxf import render_dxf
    from camfab.geometry.plate import plate

    design, partner, geom_a = analysis.design, analysis.partner, analysis.geometry
    assert partner is not None and geom_a is not None
    geom_b, program_b = partner.geometry, partner.program
    assert geom_b is not None and program_b is not None
    name = design.name
    # cam b as it is made: half a turn (or mirrored) from the frame it was computed in
    mirror = partner.mirror
    made_b = made_geometry(geom_b, mirror)
    analysis_b = replace(analysis, geometry=made_b)
    plates = {"a": plate(design, geom_a), "b": plate(design, made_b)}
    where = ("arm a, above the line of centres", "arm b, below it") if mirror else (
        "roller a, above the shaft", "roller b, below the shaft")
    dxf = {"a": render_dxf(analysis, plates["a"], f"conjugate cam a ({where[0]})"),
           "b": render_dxf(analysis_b, plates["b"],
                           f"conjugate cam b ({where[1]}; same keyway)")}
    kerf = plates["a"].kerf
    back_a = read_back(design, geom_a, analysis.program, dxf["a"], kerf, f"{name}-a.dxf")
    back_b = read_back(design, geom_b, program_b, dxf["b"], kerf, f"{name}-b.dxf",
                       lambda profile: to_made_frame(profile, mirror))
    files: dict[str, dict[str, bytes]] = {"dxf": {f"{name}-{k}.dxf": v for k, v in dxf.items()}}
    if "svg" in requested:
        from camfab.export.svg import render_svg

        files["svg"] = {f"{name}-a.svg": render_svg(analysis, plates["a"].cut),
                        f"{name}-b.svg": render_svg(analysis_b, plates["b"].cut)}
    stl_check = None
    thickness = design.cam.thickness
    if "stl" in requested and thickness is not None:
        from camfab.export.stl import check_stl, expected_volume, render_stack_stl

        stl = render_stack_stl([geom_a.outline_points(), made_b.outline_points()],
                               plates["a"].holes, geom_a.tolerance, thickness)
        files["stl"] = {f"{name}.stl": stl}
        volumes = [expected_volume(analysis, plates["a"]),
                   expected_volume(analysis_b, plates["b"])]
        stl_check = check_stl(stl, sum(v[0] for v in volumes), sum(v[1] for v in volumes))
    held = hold(back_a.lift.theta, partner.spacing, (back_a.part, geom_a.cam),
                (back_b.part, geom_b.cam))
    worse = back_a.lift if back_a.lift.max_mm >= back_b.lift.max_mm else back_b.lift
    source = (f"{back_a.source} ({back_a.lift.max_mm:.3g} mm) and {back_b.source} "
              f"({back_b.lift.max_mm:.3g} mm), each under its own roller")
    deviation = (None if back_a.deviation is None or back_b.deviation is None
                 else max(back_a.deviation, back_b.deviation))
    lift = LiftCheck(worse.theta, worse.error, worse.error_mm)
    cut_error = None
    if geom_a.undercut or geom_b.undercut:  # each cam's files held to the cam as computed
        tolerance = analysis.design.manufacturing.tolerance
        cut_error = max((against_cut(back_a.lift, geom_a.lift, tolerance),
                         against_cut(back_b.lift, geom_b.lift, tolerance)),
                        key=lambda c: c.max_mm)
    return Verification(lift, source, back_a.entities + back_b.entities, deviation, stl_check,
                        exempt=geom_a.undercut or geom_b.undercut, hold=held,
                        cut_error=cut_error), files


class Pair:
    """The cams that hold their follower on both sides: the conjugate pair and the
    constant-breadth cam (``cam.type: conjugate``, ``constant-breadth``)."""

    drives_both_ways = True

    @staticmethod
    def analyse(design: Design, program: MotionProgram, units: MotionUnits,
                stats: list[SegmentStats], findings: list[Finding]) -> Analysis:
        """A plate cam's analysis with the second contact, the second cam's checks and the
        ``hold`` check."""
        from camfab.analysis.partner_checks import with_partner
        from camfab.kinds.disc import analyse_plate

        return with_partner(analyse_plate(design, program, units, stats, findings))

    @staticmethod
    def files(analysis: Analysis, requested: tuple[str, ...]) -> tuple[
            Analysis, Verification, dict[str, dict[str, bytes]], dict[str, str]]:
        """The files, read back; the hold of the cams as written replaces that of the cams as
        sampled."""
        from camfab.analysis.partner_checks import read_back_hold

        check, files = verify_partner(analysis, requested)
        if check.hold is not None and analysis.partner is not None:
            findings = [read_back_hold(analysis, check.hold) if f.id == "hold" else f
                        for f in analysis.findings]
            analysis = replace(analysis, findings=findings,
                               partner=replace(analysis.partner, hold=check.hold))
        return analysis, check, files, {}


KIND = Pair()
