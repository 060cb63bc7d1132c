"""The disc (plate) cam: a plate turning about its centre, its outline the working curve of the
follower's motion (THEORY §B). Its analysis is shared by the plate cams built on it (shaped,
groove, conjugate and constant-breadth)."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from camfab.analysis.record import TABLE_COLUMNS, Analysis, CamResult, terse

if TYPE_CHECKING:
    from camfab.analysis.cam_checks import CamNumbers
    from camfab.analysis.findings import Finding
    from camfab.analysis.kinematics import MotionUnits, SegmentStats
    from camfab.analysis.sizing import Grid, SizeProblem
    from camfab.analysis.verification import Verification
    from camfab.arrays import Array
    from camfab.curves.follower import FollowerGeometry
    from camfab.curves.plane import CurvePoints
    from camfab.curves.profile import Profile
    from camfab.design import Design
    from camfab.export.part import Drawing, Part, Solid
    from camfab.export.serialise import PartFiles
    from camfab.geometry.disc import DiscCam
    from camfab.geometry.disc_geometry import DiscGeometry, LiftCheck
    from camfab.geometry.plate import Contours, Plate
    from camfab.kinds.scene3d import Scene3D
    from camfab.motion.program import MotionProgram
    from camfab.speed.contact import Contact, ContactSide


@dataclass(frozen=True)
class PlateResult(CamResult):
    """A plate cam's exact curves (mm) and key numbers; what its report, motion table and
    summary show of them."""

    geometry: DiscGeometry
    numbers: CamNumbers
    refine_for_inspection = True

    def report_geometry(self, analysis: Analysis) -> dict[str, Any]:
        from camfab.analysis.cam_checks import offset_side

        design = analysis.design
        geom, numbers = self.geometry, self.numbers
        contact = numbers.face_contact_mm
        required = None if contact is None else contact[1] - contact[0]
        out: dict[str, Any] = {
            "base_radius_mm": design.cam.base_radius,
            "prime_radius_mm": geom.cam.prime_radius,
            "max_radius_mm": numbers.max_radius_mm,
            "pitch_min_radius_of_curvature_mm": numbers.pitch_min_convex.value,
            "pitch_min_radius_of_curvature_at_deg": numbers.pitch_min_convex.at_deg,
            "pitch_min_concave_radius_mm": numbers.pitch_min_concave.value,
            "profile_min_radius_of_curvature_mm": numbers.profile_min_convex.value,
            "profile_min_radius_of_curvature_at_deg": numbers.profile_min_convex.at_deg,
            "profile_min_concave_radius_mm": numbers.profile_min_concave.value,
            "profile_min_concave_radius_at_deg": numbers.profile_min_concave.at_deg,
            "face_width_required_mm": required,
            "face_contact_range_mm": None if contact is None else list(contact),
            "pressure_angle_max_deg": numbers.pressure_angle.value,
            "pressure_angle_max_at_deg": numbers.pressure_angle.at_deg,
            "pressure_angle_limit_deg": math.degrees(design.pressure_angle_limit),
            "offset_side_lowering_rise_pressure_angle": offset_side(design),
            "undercut": geom.undercut,
            "undercut_ranges_deg": [list(r) for r in numbers.undercut_ranges],
            "undercut_fold_ranges_deg": [list(r) for r in numbers.fold_ranges],
            "undercut_cut_ranges_deg": [list(r) for r in numbers.cut_ranges],
            "profile_points": len(geom.profile.vertices),
            "sampling_tolerance_mm": geom.tolerance,
        }
        if design.follower.oscillating:
            out["rest_arm_angle_deg"] = math.degrees(geom.cam.rest)
        return out

    def sampled_lift(self) -> LiftCheck:
        return self.geometry.lift

    def table_columns(self, theta: Array, motion: Array) -> list[tuple[str, Array]]:
        import numpy as np

        cam = self.geometry.cam
        return list(zip(TABLE_COLUMNS, (np.degrees(cam.pressure_angle(theta, motion)),
                                        cam.pitch(theta, motion).radius,
                                        cam.working(theta, motion).radius), strict=True))

    def summary(self, analysis: Analysis) -> list[str]:
        geom, numbers = self.geometry, self.numbers
        count = len(geom.profile.vertices)
        profile = (f"exact profile of {count} arcs and lines" if geom.exact else
                   f"profile of {count} points within {geom.tolerance:.2g} mm")
        return [f"cam: base radius {terse(analysis.design.cam.base_radius)} mm, prime radius "
                f"{terse(geom.cam.prime_radius)} mm, largest radius "
                f"{terse(numbers.max_radius_mm)} mm; pitch curve's smallest convex radius "
                f"{terse(numbers.pitch_min_convex.value)} mm; {profile}; the follower run over "
                f"it strays {geom.lift.max_mm:.2g} mm from the design"]

    def contact(self, analysis: Analysis) -> Contact:
        """The profile under the follower."""
        return plate_contact(analysis.design, self.geometry)

    def pressure_panels(self, analysis: Analysis, top: Any, bottom: Any) -> None:
        from camfab.kinds.plate_figures import plate_pressure_panels

        plate_pressure_panels(self.geometry, top, bottom,
                              analysis.design.pressure_angle_limit)

    def drawing(self, analysis: Analysis) -> str:
        from camfab.kinds.plate_figures import plate_drawing_svg

        return plate_drawing_svg(self, analysis)

    def draw_plate(self, ax: Any, analysis: Analysis) -> None:
        """The plate in the report's drawing: its outline, filled."""
        from camfab.kinds.plate_figures import draw_outline

        draw_outline(ax, self.geometry)

    def draw_other_side(self, ax: Any, analysis: Analysis) -> None:
        """What holds the follower on its other side, in the report's drawing (nothing: a
        spring)."""


def plate_side(cam: DiscCam, working: CurvePoints, pressure_angle: Array,
               face_contact: Array | None, name: str, carries: int = 1, roller: int = 0,
               always: bool = True, sign: float = 1.0) -> ContactSide:
    """A curve of a plate (*working*: its exact points in the cam frame, mm) as a side carrying
    the follower (:class:`ContactSide`): its curvature as the cam's material sees it (*sign*
    over its radius of curvature: −1 for a wall whose material lies on the side the radius
    is measured away from), the normal force per newton along the follower's motion — 1/cos φ
    of the pressure angle *pressure_angle* (rad), or for an oscillating flat face the arm's
    length over the contact's distance along the face from the pivot's foot, *face_contact*
    (mm: the moment about the pivot) — and a roller's rolling speed over it (mm/rad)."""
    import numpy as np

    from camfab.speed.contact import ContactSide

    fol = cam.follower
    if fol.flat and fol.oscillating:
        assert face_contact is not None
        with np.errstate(divide="ignore"):
            normal = fol.arm_length / np.abs(face_contact)
    else:
        normal = 1.0 / np.cos(pressure_angle)
    with np.errstate(divide="ignore"):
        curvature = sign / working.radius
    rolling = working.speed if fol.contact == "roller" else None
    return ContactSide(name, carries, curvature, normal, rolling, roller, always,
                       place=working.xy)


def plate_contact(design: Design, geom: DiscGeometry,
                  sides: tuple[ContactSide, ...] | None = None,
                  rollers: tuple[str, ...] = ("the roller",)) -> Contact:
    """How the follower of a plate cam touches it over the analysis grid: the profile (or
    *sides*), a roller's or a flat face's line over the plate's thickness (a groove's depth), a
    mushroom's point, a knife's none."""
    from camfab.speed.contact import KNIFE_NOTE, Contact, contact_length

    fol, dense = design.follower, geom.dense
    theta = dense.theta
    if fol.type == "knife":
        return Contact(theta, "none", note=KNIFE_NOTE)
    if sides is None:
        sides = (plate_side(geom.cam, dense.working, dense.pressure_angle, dense.face_contact,
                            "the profile"),)
    if fol.type == "mushroom":
        assert fol.face_radius is not None
        return Contact(theta, "point", 1.0 / fol.face_radius, None, sides)
    length, note = contact_length(design)
    radius = fol.roller_radius if fol.type == "roller" else None
    return Contact(theta, "line", 0.0 if radius is None else 1.0 / radius, length, sides,
                   radius, rollers, note)


def analyse_plate(design: Design, program: MotionProgram, units: MotionUnits,
                  stats: list[SegmentStats], findings: list[Finding], clearance: float = 0.0,
                  exact: Profile | None = None) -> Analysis:
    """A plate cam's exact curves, key numbers and geometric checks (before *findings*); the
    follower's radius grown by *clearance* (mm), *exact* the outline of a cam drawn from its
    shape (see :func:`camfab.geometry.disc_geometry.disc_geometry`)."""
    from camfab.analysis.cam_checks import cam_findings, cam_numbers
    from camfab.geometry.disc_geometry import disc_geometry

    geometry = disc_geometry(design, clearance, exact)
    numbers = cam_numbers(geometry, len(program.segments))
    findings = [*cam_findings(design, geometry, numbers), *findings]
    return Analysis(design, program, units, stats, findings, PlateResult(geometry, numbers))


def plate_part(analysis: Analysis, label: str | None = None,
               outline_note: Callable[[Plate], str] | None = None) -> Part:
    """A plate cam's part: its drawing (see :func:`plate_drawing`), its CUT contours, and the
    plate extruded to the design's ``thickness`` (none without one)."""
    from camfab.export.part import Part
    from camfab.geometry.plate import plate

    design, geom = analysis.design, analysis.geometry
    assert geom is not None
    contours = plate(design, geom)
    thickness = design.cam.thickness
    solid = (None if thickness is None else
             plate_stack([geom.outline_points()], contours.holes, geom.tolerance, thickness,
                         [contours.outline]))
    return Part({design.name: plate_drawing(analysis, contours, label, outline_note)},
                {design.name: (contours.cut, None)}, solid, made=contours)


def plate_stack(outlines: list[Array], holes: Contours, tolerance: float,
                thickness: float, exact: list[Profile]) -> Solid:
    """Plates stacked along Z on one bore (mm): plate i is the outline *outlines[i]* (sampling
    the lines and arcs of *exact[i]*) with the *holes*, from z = i·thickness to
    (i + 1)·thickness, the plates joined face to face into one solid (a conjugate pair printed
    as one part; one outline, one plate)."""
    from camfab.export.part import Extrusion, Union
    from camfab.export.stl import hole_points

    bores = hole_points(holes, tolerance)
    return Union(tuple(Extrusion((outline, *bores), thickness, i * thickness,
                                 (contour, *holes.exact))
                       for i, (outline, contour) in enumerate(zip(outlines, exact,
                                                                    strict=True))))


def plate_drawing(analysis: Analysis, plate: Plate, label: str | None = None,
                  outline_note: Callable[[Plate], str] | None = None) -> Drawing:
    """The drawing of *plate*: the pitch curve, base and prime circles, marks and notes, the
    toolpath, and what is cut (on ``CUT``) last, on top where they coincide (a knife's pitch
    curve is its profile); *label* names the cam in the note (by default its type: "disc cam"),
    *outline_note* writes the note's line on the outline."""
    from camfab.export.part import Drawing
    from camfab.geometry.plate import fit_chain

    design, geom = analysis.design, analysis.geometry
    assert geom is not None
    scale = 1.0 / design.mm_per_unit
    drawing = Drawing(design.units)
    drawing.contour(fit_chain(geom.pitch.xy, geom.tolerance), scale, "PITCH")
    drawing.circle(geom.cam.base_radius * scale, "BASE")
    if geom.cam.prime_radius != geom.cam.base_radius:
        drawing.circle(geom.cam.prime_radius * scale, "PRIME")
    _add_marks(drawing, analysis, scale, plate, label, outline_note)
    if plate.toolpath is not None:
        drawing.contours(plate.toolpath, scale, "TOOLPATH")
    drawing.contours(plate.cut, scale, "CUT")
    return drawing


def _add_marks(drawing: Drawing, analysis: Analysis, scale: float, plate: Plate,
               label: str | None,
               outline_note: Callable[[Plate], str] | None) -> None:
    import numpy as np

    geom = analysis.geometry
    assert geom is not None
    rb = geom.cam.base_radius
    size = 0.15 * rb * scale
    drawing.line((-size, 0.0), (size, 0.0), "MARK")
    drawing.line((0.0, -size), (0.0, size), "MARK")
    # θ = 0: a tick on +Y just inside the base circle, where the follower sits
    drawing.line((0.0, 0.6 * rb * scale), (0.0, 0.9 * rb * scale), "MARK")
    design = analysis.design
    unit = design.units
    kind = label or f"{design.cam.type} cam"
    lines = [f"{design.name}: {kind}, {design.cam.rotation}, base radius {rb * scale:.6g} "
             f"{unit}",
             outline_note(plate) if outline_note is not None else
             f"outline of {len(plate.cut.profiles[0].vertices)} lines and arcs within "
             f"{design.manufacturing.tolerance * scale:.3g} {unit}"]
    if plate.kerf > 0.0:
        lines.append(f"CUT offset for a kerf of {plate.kerf * scale:.4g} {unit}")
    cutter = design.manufacturing.cutter_radius
    if cutter > 0.0:
        lines.append(f"TOOLPATH: centre of a cutter of radius {cutter * scale:.4g} {unit}")
    height = max(rb * scale * 0.06, 1e-3)
    # below everything drawn: the profile, the pitch curve and the toolpath around them
    drawn = np.vstack((geom.outline_points(), geom.pitch.xy))
    margin = max(cutter, plate.kerf)
    left = (float(np.min(drawn[:, 0])) - margin) * scale
    low = (float(np.min(drawn[:, 1])) - margin) * scale - 1.5 * height
    for row, line in enumerate(lines, start=1):
        drawing.text(line, height, (left, low - 1.6 * row * height))


def plate_verify(analysis: Analysis, part: Part, files: PartFiles) -> tuple[Analysis,
                                                                           Verification]:
    """The plate's files read back: the follower run over the CUT outline of its DXF, the STL
    checked (see :func:`camfab.kinds.readback.verify_plate`)."""
    from camfab.kinds.readback import verify_plate

    check, _ = verify_plate(analysis, part.made, files)
    return analysis, check


def disc_scene(analysis: Analysis, theta: Array) -> Scene3D:
    """A plate cam's scene (:func:`camfab.kinds.scene3d.plate_scene`): the plate turning, its
    follower on the exact trace point over the plate's thickness."""
    from camfab.kinds.scene3d import first_contact, plate_scene, plate_thickness, roller_span

    thickness = plate_thickness(analysis)
    contact = first_contact(analysis, theta, roller_span(analysis, 0.0, thickness))
    return plate_scene(analysis, theta, [contact], analysis.numbers.max_radius_mm, thickness)


def no_checks(design: Design) -> None:
    """A kind whose design-file rules need none of its geometry."""


class Disc:
    """The disc cam (``cam.type: disc``)."""

    drives_both_ways = False
    mounted = "plate"
    inspect_refusal = None
    check = staticmethod(no_checks)
    verify = staticmethod(plate_verify)
    scene = staticmethod(disc_scene)

    @staticmethod
    def analyse(design: Design, program: MotionProgram, units: MotionUnits,
                stats: list[SegmentStats], findings: list[Finding]) -> Analysis:
        return analyse_plate(design, program, units, stats, findings)

    @staticmethod
    def part(analysis: Analysis) -> Part:
        return plate_part(analysis)

    @staticmethod
    def size_problem(design: Design, follower: FollowerGeometry,
                     grid_pair: tuple[Grid, Grid]) -> SizeProblem:
        """The sizing of the base radius (:mod:`camfab.kinds.plate_sizing`)."""
        from camfab.kinds.plate_sizing import plate_problem

        return plate_problem(design, follower, grid_pair)


KIND = Disc()
