"""The cams that hold their follower on both sides (THEORY §F): the conjugate pair and the
constant-breadth cam, two kinds built on the disc cam, with the second contact and the ``hold``
check in their analysis.

A conjugate pair gets a DXF and an SVG per plate (``NAME-a``, ``NAME-b``: cam b drawn as it is
made, half a turn from the frame it is computed in) and one STL of both plates stacked on the
bore, keyway aligned, in their phase relation. Each plate's CUT outline is read back and its own
roller run over it; then both rollers are run over the two outlines together to measure whether
the pair holds the follower. A constant-breadth cam's files are a disc cam's; its outline read
back is run under both faces (or rollers) of the yoke.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from camfab.analysis.verification import Verification
from camfab.geometry.conjugate import (
    half_turned,
    hold,
    made_geometry,
    mirrored,
    to_made_frame,
)
from camfab.geometry.disc_geometry import VERIFY_STEP, LiftCheck
from camfab.kinds.disc import PlateResult, analyse_plate, no_checks
from camfab.kinds.readback import BEAM_DEPARTS, against_cut, beam_cut, read_back, verify_plate
from camfab.motion.program import cycle_angles

if TYPE_CHECKING:
    from camfab.analysis.findings import Finding
    from camfab.analysis.kinematics import MotionUnits, SegmentStats
    from camfab.analysis.partner_checks import Partner
    from camfab.analysis.record import Analysis
    from camfab.analysis.sizing import Grid, SizeProblem
    from camfab.arrays import Array
    from camfab.curves.follower import FollowerGeometry
    from camfab.design import Design
    from camfab.export.part import Part
    from camfab.export.serialise import PartFiles
    from camfab.kinds.scene3d import Scene3D
    from camfab.motion.program import MotionProgram
    from camfab.speed.contact import Contact


def pair_part(analysis: Analysis) -> Part:
    """A conjugate pair's part: a drawing and a view per plate (``NAME-a``, ``NAME-b``: cam b
    drawn as it is made, half a turn or mirrored from the frame it is computed in) and one
    solid of both plates stacked on the bore."""
    from camfab.export.part import Part
    from camfab.geometry.plate import plate
    from camfab.kinds.disc import plate_drawing, plate_stack

    design, partner, geom_a = analysis.design, analysis.partner, analysis.geometry
    assert partner is not None and geom_a is not None and partner.geometry is not None
    name = design.name
    made_b = made_geometry(partner.geometry, partner.mirror)
    analysis_b = replace(analysis, result=replace(analysis.result, geometry=made_b))
    plates = {"a": plate(design, geom_a), "b": plate(design, made_b)}
    where = ("arm a, above the line of centres", "arm b, below it") if partner.mirror else (
        "roller a, above the shaft", "roller b, below the shaft")
    drawings = {f"{name}-a": plate_drawing(analysis, plates["a"], f"conjugate cam a ({where[0]})"),
                f"{name}-b": plate_drawing(analysis_b, plates["b"],
                                           f"conjugate cam b ({where[1]}; same keyway)")}
    views = {f"{name}-{k}": (plates[k].cut, None) for k in ("a", "b")}
    thickness = design.cam.thickness
    solid = (None if thickness is None else
             plate_stack([geom_a.outline_points(), made_b.outline_points()], plates["a"].holes,
                         geom_a.tolerance, thickness, [plates["a"].outline, plates["b"].outline]))
    return Part(drawings, views, solid, made=(plates, made_b))


def conjugate_scene(analysis: Analysis, theta: Array) -> Scene3D:
    """A conjugate pair's scene (:func:`camfab.kinds.scene3d.plate_scene`): both plates turning
    as the one solid they are written as, roller a on cam a's exact trace point over plate a,
    roller b on cam b's (moved into the frame it is made in) over plate b."""
    from camfab.kinds.scene3d import (
        PlateContact,
        first_contact,
        plate_scene,
        plate_thickness,
        roller_span,
    )

    partner = analysis.partner
    assert partner is not None and partner.geometry is not None
    assert partner.program is not None and partner.numbers is not None
    thickness = plate_thickness(analysis)
    first = first_contact(analysis, theta, roller_span(analysis, 0.0, thickness))
    move = mirrored if partner.mirror else half_turned
    trace, _, _, rise = partner.geometry.cam.trace(partner.program.evaluate(theta))
    second = PlateContact(move(trace), move(rise),
                          roller_span(analysis, thickness, 2.0 * thickness))
    radius = max(analysis.numbers.max_radius_mm, partner.numbers.max_radius_mm)
    return plate_scene(analysis, theta, [first, second], radius, 2.0 * thickness)


def breadth_scene(analysis: Analysis, theta: Array) -> Scene3D:
    """A constant-breadth cam's scene (:func:`camfab.kinds.scene3d.plate_scene`): the plate
    turning, the yoke's first face (or roller) on the exact trace point, its other one where
    the outline half a turn on puts it."""
    from camfab.kinds.scene3d import (
        PlateContact,
        face_line,
        first_contact,
        plate_scene,
        plate_thickness,
        roller_span,
    )

    cam = analysis.geometry.cam
    thickness = plate_thickness(analysis)
    first = first_contact(analysis, theta, roller_span(analysis, 0.0, thickness))
    turned = theta + math.pi
    motion = analysis.program.evaluate(turned)
    trace, _, _, rise = cam.trace(motion)
    face = face_line(cam, turned, motion, half_turn=True) if cam.follower.flat else None
    second = PlateContact(half_turned(trace), half_turned(rise), first.z, face)
    return plate_scene(analysis, theta, [first, second], analysis.numbers.max_radius_mm,
                       thickness)


def _held(analysis: Analysis, check: Verification) -> Analysis:
    """*analysis* with the hold of the cams as written in place of that of the cams as
    sampled."""
    from camfab.analysis.partner_checks import read_back_hold

    assert check.hold is not None and analysis.partner is not None
    findings = [read_back_hold(analysis, check.hold) if f.id == "hold" else f
                for f in analysis.findings]
    return replace(analysis, findings=findings,
                   result=replace(analysis.result,
                                  partner=replace(analysis.partner, hold=check.hold)))


def _verify_pair(analysis: Analysis, part: Part, files: PartFiles) -> Verification:
    from camfab.kinds.readback import expected_volume

    design, partner, geom_a = analysis.design, analysis.partner, analysis.geometry
    assert partner is not None and geom_a is not None
    geom_b, program_b = partner.geometry, partner.program
    assert geom_b is not None and program_b is not None
    name = design.name
    plates, made_b = part.made
    dxf = files.files["dxf"]
    kerf = plates["a"].kerf
    back_a = read_back(design, geom_a, analysis.program, dxf[f"{name}-a.dxf"], kerf,
                       f"{name}-a.dxf", holes=plates["a"].holes)
    back_b = read_back(design, geom_b, program_b, dxf[f"{name}-b.dxf"], kerf, f"{name}-b.dxf",
                       lambda profile: to_made_frame(profile, partner.mirror),
                       holes=plates["b"].holes)
    stl_check = None
    if files.stl is not None:
        from camfab.export.stl import check_stl

        volumes = [expected_volume(analysis, plates["a"]),
                   expected_volume(replace(analysis, result=replace(analysis.result,
                                                                             geometry=made_b)),
                                   plates["b"])]
        stl_check = check_stl(files.stl.data, sum(v[0] for v in volumes),
                              sum(v[1] for v in volumes))
    held = hold(back_a.lift.theta, partner.spacing, (back_a.part, geom_a.cam),
                (back_b.part, geom_b.cam))
    worse = back_a.lift if back_a.lift.max_mm >= back_b.lift.max_mm else back_b.lift
    source = (f"{back_a.source} ({back_a.lift.max_mm:.3g} mm) and {back_b.source} "
              f"({back_b.lift.max_mm:.3g} mm), each under its own roller")
    deviation = max(back_a.deviation, back_b.deviation)
    lift = LiftCheck(worse.theta, worse.error, worse.error_mm)
    cut_error = None
    tolerance = analysis.design.manufacturing.tolerance
    beams = (beam_cut(design, geom_a, analysis.program, kerf),
             beam_cut(design, geom_b, program_b, kerf))
    words = BEAM_DEPARTS if any(b is not None for b in beams) else {}
    if geom_a.undercut or geom_b.undercut or words:  # each cam's files held to the cam made
        cut_error = max((against_cut(back_a.lift, beams[0] or geom_a.lift, tolerance),
                         against_cut(back_b.lift, beams[1] or geom_b.lift, tolerance)),
                        key=lambda c: c.max_mm)
    return Verification(lift, source, back_a.entities + back_b.entities, deviation, stl_check,
                        exempt=cut_error is not None, hold=held, cut_error=cut_error, **words)


@dataclass(frozen=True)
class PairResult(PlateResult):
    """A plate cam's result with what holds its follower on the other side: a conjugate pair's
    cam b, or a constant-breadth cam's own outline half a turn on."""

    partner: Partner
    refine_for_inspection = False

    def report_geometry(self, analysis: Analysis) -> dict[str, Any]:
        return {**super().report_geometry(analysis), **self.partner.report_geometry()}

    def contact(self, analysis: Analysis) -> Contact:
        """Each side on its own cam: a conjugate pair's cam a and cam b, each under its own
        roller; a constant-breadth cam's outline under the yoke's one face (or roller) and,
        half a turn on, under the other. Each roller rides its cam loaded or not."""
        import numpy as np

        from camfab.kinds.disc import plate_contact, plate_side

        geom, partner = self.geometry, self.partner
        dense, holder = geom.dense, partner.holder
        if partner.geometry is not None:
            names, rollers = ("cam a", "cam b"), ("roller a", "roller b")
        else:
            names = (f"the profile under the {holder.outward}",
                     f"the profile under the {holder.inward}")
            rollers = (f"the {holder.outward}", f"the {holder.inward}")
        first = plate_side(geom.cam, dense.working, dense.pressure_angle, dense.face_contact,
                           names[0])
        if partner.geometry is not None:  # cam b
            other = partner.geometry.dense
            second = plate_side(partner.geometry.cam, other.working, other.pressure_angle,
                                other.face_contact, names[1], -1, roller=1)
        else:  # the same outline half a turn on
            cam = geom.cam
            theta = dense.theta + np.pi
            motion = analysis.program.evaluate(theta)
            lines = cam.face_lines(theta, motion) if cam.follower.flat else None
            second = plate_side(cam, cam.working(theta, motion, lines),
                                cam.pressure_angle(theta, motion, lines),
                                None if lines is None else cam.face_contact(theta, motion,
                                                                             lines),
                                names[1], -1, roller=1)
        return plate_contact(analysis.design, geom, (first, second), rollers)

    def dynamics_note(self, analysis: Analysis) -> str:
        return (f"a {analysis.design.cam.type} cam drives its follower both ways without a "
                "spring: the forces on either side are in geometry (load_changes, "
                "max_..._force_N)")

    def summary(self, analysis: Analysis) -> list[str]:
        lines = super().summary(analysis)
        partner = self.partner
        if partner.contact is not None:
            sides = partner.sides
            held = partner.hold
            passes = ", ".join(f"{math.degrees(float(a)):.4g}° (onto {sides[int(to)]})"
                               for a, to in zip(partner.contact.changes, partner.contact.onto,
                                                strict=True)) or "nowhere"
            lines.append(f"held on both sides: gap up to {held.max_gap:.2g} mm, interference "
                         f"up to {held.max_interference:.2g} mm; the load passes sides at "
                         f"{passes}")
        return lines

    def draw_other_side(self, ax: Any, analysis: Analysis) -> None:
        """The yoke's other face or roller, at θ = 0."""
        trace = _trace(analysis)
        _draw_second(ax, analysis, trace - np.array([0.0, self.partner.spacing]), trace)

    def contact_changes(self, report: dict[str, Any]) -> dict[str, Any] | None:
        from camfab.export.report_html import num

        geometry = report["geometry"]
        if "load_changes" not in geometry:
            return None
        return {"title": "Where the load passes from one side to the other",
                "intro": "The follower is pushed away from the cam centre where its acceleration "
                         "is positive and pulled back where it is negative; at these cam angles "
                         "the other side takes the load (any play between the two shows here).",
                "still": "The follower never accelerates: neither side carries it.",
                "rows": [[num(c["cam_angle_deg"]), c["from"], c["onto"]]
                         for c in geometry["load_changes"]]}


@dataclass(frozen=True)
class ConjugateResult(PairResult):
    """A conjugate pair's result: cam a's, with cam b (its geometry, motion and numbers) in
    ``partner``."""

    def table_columns(self, theta: Array, motion: Array) -> list[tuple[str, Array]]:
        """Cam a's columns, then cam b's (``..._b_...``)."""
        partner = self.partner
        assert partner.geometry is not None and partner.program is not None
        cam_b, s_b = partner.geometry.cam, partner.program.evaluate(theta)
        return [*super().table_columns(theta, motion),
                ("pressure_angle_b_deg", np.degrees(cam_b.pressure_angle(theta, s_b))),
                ("pitch_b_radius_of_curvature_mm", cam_b.pitch(theta, s_b).radius),
                ("profile_b_radius_of_curvature_mm", cam_b.working(theta, s_b).radius)]

    def draw_other_side(self, ax: Any, analysis: Analysis) -> None:
        """Cam b (turned into the frame it is made in) with its roller, at θ = 0."""
        from camfab.export.figures import CUT
        from camfab.geometry.conjugate import half_turned, mirrored

        partner = self.partner
        assert partner.geometry is not None and partner.program is not None
        cam_b = partner.geometry.cam
        move = mirrored if partner.mirror else half_turned
        other = move(cam_b.trace(partner.program.evaluate(np.zeros(1)))[0][0])
        ring = move(partner.geometry.outline_points())
        ring = np.vstack((ring, ring[:1]))
        with ax.group("cam"):  # on the same shaft: it turns with cam a
            ax.plot(ring[:, 0], ring[:, 1], color=CUT, linewidth=1.0, linestyle="--",
                    label="cam b (behind cam a)")
        _draw_second(ax, analysis, other, _trace(analysis))


def _trace(analysis: Analysis) -> Array:
    """The follower's trace point at θ = 0 (mm)."""
    cam = analysis.result.geometry.cam
    return cam.trace(analysis.program.evaluate(np.zeros(1)))[0][0]


def _draw_second(ax: Any, analysis: Analysis, other: Array, trace: Array) -> None:
    """What holds the follower on the other side at θ = 0, its trace point at *other*: a yoke's
    other face, or the second roller tied to the pivot or to the first roller's *trace*."""
    from camfab.export.figures import FOLLOWER

    cam = analysis.result.geometry.cam
    fol = cam.follower
    if fol.flat:
        half = 0.6 * cam.base_radius
        ax.plot([other[0] - half, other[0] + half], [other[1], other[1]], color=FOLLOWER,
                linewidth=2.0, label="the yoke's other face")
        return
    angle = np.linspace(0, 2 * math.pi, 181)
    ax.plot(other[0] + fol.radius * np.cos(angle), other[1] + fol.radius * np.sin(angle),
            color=FOLLOWER, linewidth=1.5, linestyle="--", label="second roller")
    joint = cam.pivot if fol.oscillating else trace
    ax.plot([other[0], joint[0]], [other[1], joint[1]], color=FOLLOWER, linewidth=0.8,
            linestyle=":")


def _with_partner(analysis: Analysis,
                  partner_of: Callable[[Analysis], tuple[Partner, list[Finding]]],
                  result: type[PairResult]) -> Analysis:
    plate = analysis.result
    assert isinstance(plate, PlateResult)
    partner, findings = partner_of(analysis)
    return replace(analysis, findings=findings,
                   result=result(plate.geometry, plate.numbers, partner))


class ConstantBreadth:
    """The constant-breadth (constant-diameter) cam (``cam.type: constant-breadth``): one disc
    cam between the two faces or rollers of a yoke, its outline half a turn on holding the
    other side. Its files are a disc cam's."""

    drives_both_ways = True
    mounted = "plate"
    inspect_refusal = None
    check = staticmethod(no_checks)
    scene = staticmethod(breadth_scene)

    @staticmethod
    def analyse(design: Design, program: MotionProgram, units: MotionUnits,
                stats: list[SegmentStats], findings: list[Finding]) -> Analysis:
        """A plate cam's analysis with the second contact and the ``hold`` check."""
        from camfab.analysis.partner_checks import breadth_partner

        return _with_partner(analyse_plate(design, program, units, stats, findings),
                             breadth_partner, PairResult)

    @staticmethod
    def part(analysis: Analysis) -> Part:
        from camfab.kinds.disc import plate_part

        return plate_part(analysis)

    @staticmethod
    def verify(analysis: Analysis, part: Part, files: PartFiles) -> tuple[Analysis,
                                                                          Verification]:
        """The outline read back, run under both sides of the yoke."""
        partner, geom = analysis.partner, analysis.geometry
        assert partner is not None and geom is not None
        check, back = verify_plate(analysis, part.made, files)
        held = hold(cycle_angles(VERIFY_STEP), partner.spacing, (back.part, geom.cam),
                    (back.part, geom.cam), math.pi)
        check = replace(check, hold=held)
        return _held(analysis, check), check


class Conjugate:
    """The conjugate pair (``cam.type: conjugate``): two plates on one shaft, each driving one
    roller of the follower, together holding it both ways."""

    drives_both_ways = True
    mounted = "plate"
    inspect_refusal = None
    part = staticmethod(pair_part)
    scene = staticmethod(conjugate_scene)

    @staticmethod
    def check(design: Design) -> None:
        """Cam b must have a base circle around the bore, and an oscillating pair's arm b must
        stay short of 180° from the line of centres with the pivot outside both cams."""
        from camfab.design.rules import fail, mm, wall_need
        from camfab.geometry.conjugate import partner_base_radius
        from camfab.geometry.disc_geometry import disc_cam

        program = design.program
        cam_a = disc_cam(design)
        need = wall_need(design.cam.bore or 0.0)
        base_b = partner_base_radius(design, cam_a)
        if design.follower.oscillating:
            if base_b < need:
                fail(("follower", "arm_angle"), "leaves cam b no base circle around the bore (cam "
                     f"b's base radius would be {mm(base_b)}, at least {mm(need)} is needed): "
                     "open the angle between the arms")
            swing = math.degrees(cam_a.rest + program.max_lift)
            if math.degrees(design.follower.arm_angle or 0.0) - math.degrees(cam_a.rest) >= 180.0:
                fail(("follower", "arm_angle"), f"arm b would pass 180° from the line of centres "
                     f"(arm a turns from {math.degrees(cam_a.rest):.4g}° to {swing:.4g}°)")
            fol = cam_a.follower
            top = (design.follower.arm_angle or 0.0) - cam_a.rest
            reach = math.sqrt(fol.pivot_distance**2 + fol.arm_length**2 - 2 * fol.pivot_distance
                              * fol.arm_length * math.cos(top)) - fol.radius
            if reach >= fol.pivot_distance:
                fail(("follower", "arm_angle"), f"cam b would reach {mm(reach)} from its centre, "
                     "past the pivot: the pivot must lie outside both cams")
            return
        if base_b < need:
            reach = need + cam_a.follower.radius
            least = (cam_a.rest + program.max_lift
                     + math.sqrt(max(reach * reach - cam_a.follower.offset ** 2, 0.0)))
            fail(("follower", "roller_spacing"), "leaves cam b no base circle around the bore "
                 f"(cam b's base radius would be {mm(base_b)}, at least {mm(need)} is needed): "
                 f"the rollers must be at least {mm(least)} apart")

    @staticmethod
    def analyse(design: Design, program: MotionProgram, units: MotionUnits,
                stats: list[SegmentStats], findings: list[Finding]) -> Analysis:
        """A plate cam's analysis with cam b, each cam's checks and the ``hold`` check."""
        from camfab.analysis.partner_checks import conjugate_partner

        return _with_partner(analyse_plate(design, program, units, stats, findings),
                             conjugate_partner, ConjugateResult)

    @staticmethod
    def verify(analysis: Analysis, part: Part, files: PartFiles) -> tuple[Analysis,
                                                                          Verification]:
        """Each plate's CUT outline read back and its own roller run over it; then both
        rollers run over the outlines together, to measure whether they hold the follower."""
        check = _verify_pair(analysis, part, files)
        return _held(analysis, check), check

    @staticmethod
    def size_problem(design: Design, follower: FollowerGeometry,
                     grid_pair: tuple[Grid, Grid]) -> SizeProblem:
        """The sizing of cam a's base radius, cam b's limits with it."""
        from camfab.kinds.plate_sizing import plate_problem

        return plate_problem(design, follower, grid_pair, partner=True)


CONSTANT_BREADTH = ConstantBreadth()
CONJUGATE = Conjugate()
