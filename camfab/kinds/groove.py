"""The face-groove cam (THEORY §F): a disc cam's pitch curve, the roller held between the
groove's two walls. Its analysis is a plate cam's with the walls and the groove's checks; its
part is the plate cut out (the outer circle and the holes on ``CUT``), the walls on ``POCKET``
and the plate with the groove pocketed into its face as a solid.

Reading back: the DXF's ``POCKET`` walls are read as a reader of the file would and the roller is
run against both of them; the STL is read back and checked closed, outward and of the part's
volume. The inner wall is checked as a disc cam's profile is: the roller (its radius plus half
the clearance, the contact the groove gives it) is pressed onto it from outside at every 0.1°
and its lift compared with the design. The outer wall pulls the roller back and cannot be
pressed onto from outside, so at every 0.1° the exact roller centre's distance from each wall
read back is measured: less the roller's radius and divided by cos φ it is the follower's
displacement that wall would cause (a wall δ off along the normal moves the follower δ/cos φ
along its path).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from camfab.analysis.record import terse
from camfab.analysis.verification import Verification
from camfab.kinds.disc import PlateResult, analyse_plate

if TYPE_CHECKING:
    from camfab.analysis.findings import Finding
    from camfab.analysis.kinematics import MotionUnits, SegmentStats
    from camfab.analysis.record import Analysis
    from camfab.analysis.sizing import Grid, SizeProblem
    from camfab.arrays import Array
    from camfab.curves.follower import FollowerGeometry
    from camfab.curves.profile import Profile
    from camfab.design import Design
    from camfab.export.part import Drawing, Part, Solid
    from camfab.export.serialise import PartFiles
    from camfab.geometry.groove import GrooveWalls
    from camfab.geometry.plate import Contours
    from camfab.kinds.scene3d import Scene3D
    from camfab.motion.program import MotionProgram
    from camfab.speed.contact import Contact


#: A wall-change tick runs this many groove half widths either side of the pitch curve: across
#: both walls and a little beyond.
TICK_REACH = 1.4

#: How far the pocket's cutting body reaches above the face (mm), so the boolean never meets
#: two coplanar faces.
OVERSHOOT_MM = 1.0

#: The roller's end stands this share of the groove's depth off its floor, in the 3-D view.
FLOOR_GAP_SHARE = 0.05


def groove_part(analysis: Analysis) -> Part:
    """The groove cam's part: the plate cut out (its outer circle and holes on ``CUT``), the
    groove's walls on ``POCKET``, the references, marks and notes; the plate with the groove
    pocketed into its face as a solid."""
    from camfab.export.part import Part
    from camfab.geometry.plate import Contours, holes, offset_holes

    design, geom, walls = analysis.design, analysis.geometry, analysis.groove
    assert geom is not None and walls is not None
    part_holes = holes(design)
    kerf = design.manufacturing.kerf
    cut = Contours(part_holes.profiles, (walls.outer_radius, *part_holes.circles))
    if kerf > 0.0:
        beam = offset_holes(part_holes, kerf / 2.0, geom.tolerance)
        cut = Contours(beam.profiles, (walls.outer_radius + kerf / 2.0, *beam.circles))
    drawing = _drawing(analysis, cut, _toolpath(analysis, part_holes), kerf)
    return Part({design.name: drawing},
                {design.name: (cut, Contours((walls.inner, walls.outer)))},
                _solid(analysis, part_holes), made=part_holes)


def _drawing(analysis: Analysis, cut: Contours, toolpath: Contours | None,
             kerf: float) -> Drawing:
    """*cut* (mm) on ``CUT``, the walls on ``POCKET`` (milled, so never kerf-offset), the pitch
    curve on ``PITCH``, base and prime circles, the *toolpath*, marks and notes."""
    from camfab.export.part import Drawing
    from camfab.geometry.plate import fit_chain

    design, geom, walls = analysis.design, analysis.geometry, analysis.groove
    assert geom is not None and walls is not None
    scale = 1.0 / design.mm_per_unit
    drawing = Drawing(design.units)
    drawing.contour(fit_chain(geom.pitch.xy, geom.tolerance), scale, "PITCH")
    drawing.circle(geom.cam.base_radius * scale, "BASE")
    drawing.circle(geom.cam.prime_radius * scale, "PRIME")
    _add_marks(drawing, analysis, scale)
    _add_notes(drawing, analysis, scale, kerf)
    if toolpath is not None:
        drawing.contours(toolpath, scale, "TOOLPATH")
    drawing.contour(walls.inner, scale, "POCKET")
    drawing.contour(walls.outer, scale, "POCKET")
    drawing.contours(cut, scale, "CUT")
    return drawing


def _add_marks(drawing: Drawing, analysis: Analysis, scale: float) -> None:
    """The centre cross, the θ = 0 tick, and a tick across the groove wherever contact passes
    from one wall to the other."""
    from camfab.curves.plane import perp

    geom, walls = analysis.geometry, analysis.groove
    assert geom is not None and walls is not None
    rb = geom.cam.base_radius
    size = 0.15 * rb * scale
    drawing.line((-size, 0.0), (size, 0.0), "MARK")
    drawing.line((0.0, -size), (0.0, size), "MARK")
    drawing.line((0.0, 0.6 * rb * scale), (0.0, 0.9 * rb * scale), "MARK")
    changes = walls.contact.changes
    if changes.size:
        pitch = geom.cam.pitch(changes, analysis.program.evaluate(changes))
        reach = TICK_REACH * walls.radius * perp(pitch.tangent)
        for a, b in zip((pitch.xy - reach) * scale, (pitch.xy + reach) * scale, strict=True):
            drawing.line(tuple(a), tuple(b), "MARK")


def _add_notes(drawing: Drawing, analysis: Analysis, scale: float, kerf: float) -> None:
    design, geom, walls = analysis.design, analysis.geometry, analysis.groove
    assert geom is not None and walls is not None
    unit = design.units

    def length(mm: float) -> str:
        return f"{mm * scale:.6g} {unit}"

    lines = [f"{design.name}: groove cam, {design.cam.rotation}, base radius "
             f"{length(geom.cam.base_radius)} (the inner wall's smallest), plate radius "
             f"{length(walls.outer_radius)}, thickness {length(walls.thickness)}",
             f"POCKET: groove depth {length(walls.depth)} into the front face (floor at "
             f"z = {length(walls.thickness - walls.depth)}), groove width {length(walls.width)} "
             f"(roller radius {length(walls.roller_radius)}, clearance {length(walls.clearance)})",
             f"groove walls of {len(walls.inner.vertices)} and {len(walls.outer.vertices)} lines "
             f"and arcs within {design.manufacturing.tolerance * scale:.3g} {unit}; PITCH: the "
             f"roller centre's path"]
    changes = walls.contact.changes_deg
    if changes:
        lines.append("MARK ticks across the groove: contact changes walls at "
                     + ", ".join(f"{a:.4g}°" for a in changes)
                     + " (the roller reverses its spin)")
    if kerf > 0.0:
        lines.append(f"CUT offset for a kerf of {kerf * scale:.4g} {unit} (POCKET is milled: "
                     "not offset)")
    cutter = design.manufacturing.cutter_radius
    if cutter > 0.0:
        lines.append(f"TOOLPATH: centre of a cutter of radius {cutter * scale:.4g} {unit}")
    height = max(walls.outer_radius * scale * 0.04, 1e-3)
    left = -walls.outer_radius * scale
    low = -(walls.outer_radius + max(cutter, kerf)) * scale - 1.5 * height
    for row, line in enumerate(lines, start=1):
        drawing.text(line, height, (left, low - 1.6 * row * height))


def _solid(analysis: Analysis, holes: Contours) -> Solid:
    """The plate with its *holes* (mm) through, the groove pocketed from the front face
    (z = thickness) down to its floor: the band between the walls extruded from the floor to
    above the face and subtracted once. The walls are the tolerance-sampled chains, the circles
    cut into chords within the same tolerance."""
    from camfab.curves.sampling import arc_points
    from camfab.export.part import Difference, Extrusion
    from camfab.export.stl import hole_points

    geom, walls = analysis.geometry, analysis.groove
    assert geom is not None and walls is not None
    tol = geom.tolerance
    rim = arc_points(np.zeros(2), np.array([walls.outer_radius, 0.0]), 2 * math.pi, tol)[:-1]
    plate = Extrusion((rim, *hole_points(holes, tol)), walls.thickness, None,
                      (walls.outer_radius, *holes.exact))
    pocket = Extrusion((walls.outer_points, walls.inner_points), walls.depth + OVERSHOOT_MM,
                       walls.thickness - walls.depth, (walls.outer, walls.inner))
    return Difference(plate, pocket)


def groove_volume(analysis: Analysis, holes: Contours) -> tuple[float, float]:
    """The part's volume (mm³) from the exact circles and holes and the walls' areas (their arcs
    included), and the allowance for the tolerance along every contour through its height
    (mm³)."""
    from camfab.export.stl import chain_length, hole_points, holes_area

    geom, walls = analysis.geometry, analysis.groove
    assert geom is not None and walls is not None
    t, d = walls.thickness, walls.depth
    hole_area = holes_area(holes)
    groove_area = walls.outer.area - walls.inner.area
    volume = (math.pi * walls.outer_radius**2 - hole_area) * t - groove_area * d
    chains = hole_points(holes, geom.tolerance)
    through = 2 * math.pi * walls.outer_radius + sum(chain_length(c) for c in chains)
    pocket = chain_length(walls.outer_points) + chain_length(walls.inner_points)
    tolerance = analysis.design.manufacturing.tolerance
    return volume, tolerance * (through * t + pocket * d)


def groove_verify(analysis: Analysis, part: Part, files: PartFiles) -> tuple[Analysis,
                                                                            Verification]:
    """The groove cam's files read back: the DXF's ``POCKET`` walls as a reader sees them, the
    roller run against both; the STL (when made) checked against the part's exact volume."""
    from camfab.export.dxf import read_dxf
    from camfab.geometry.groove import wall_lift_check

    design, geom, walls = analysis.design, analysis.geometry, analysis.groove
    assert geom is not None and walls is not None
    stl_check = None
    if files.stl is not None:
        from camfab.export.stl import check_stl

        stl_check = check_stl(files.stl.data, *groove_volume(analysis, part.made))
    kerf = design.manufacturing.kerf
    drawing = read_dxf(files.files["dxf"][f"{design.name}.dxf"], design.mm_per_unit)
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
    source = (f"the POCKET walls read back from {design.name}.dxf: the roller (radius "
              f"{walls.radius:.6g} mm with half the clearance) pressed onto the inner wall, and "
              f"the roller centre's distance from each wall less that radius, over cos φ")
    return analysis, Verification(lift, source, len(inner.vertices) + len(outer.vertices),
                                  deviation, stl_check, exempt=walls.folded)


def _toolpath(analysis: Analysis, part_holes: Contours) -> Contours | None:
    """A milling cutter's centre path (mm): round the plate, inside the holes it fits in, and
    along the groove — on the pitch curve when the cutter is as wide as the groove, else one
    pass along each wall (the pitch curve offset by ± (R − cutter radius)); None without a
    ``cutter_radius``, and no groove pass for a cutter wider than the groove."""
    from camfab.geometry.disc import DiscCam
    from camfab.geometry.disc_geometry import sample_closed, segment_tolerances
    from camfab.geometry.plate import Contours, fit_chain, offset_holes

    design, geom, walls = analysis.design, analysis.geometry, analysis.groove
    assert geom is not None and walls is not None
    cutter = design.manufacturing.cutter_radius
    if cutter <= 0.0:
        return None
    inside = offset_holes(part_holes, cutter, geom.tolerance)
    passes: list[Profile] = []
    if cutter == walls.radius:
        passes.append(fit_chain(geom.pitch.xy, geom.tolerance))
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
            passes.append(fit_chain(xy, geom.tolerance))
    return Contours((*passes, *inside.profiles),
                    (walls.outer_radius + cutter, *inside.circles))


@dataclass(frozen=True)
class GrooveResult(PlateResult):
    """A plate cam's result (its working curve the inner wall) with the groove's walls."""

    groove: GrooveWalls
    refine_for_inspection = False

    def report_geometry(self, analysis: Analysis) -> dict[str, Any]:
        return {**super().report_geometry(analysis), **self.groove.report_geometry()}

    def dynamics_note(self, analysis: Analysis) -> str:
        return ("a groove cam drives its follower both ways without a spring: the forces on its "
                "walls are in geometry (max_inner_wall_force_N, ...)")

    def contact(self, analysis: Analysis) -> Contact:
        """The roller on the inner wall where it is pushed along its motion, on the outer wall
        where it is pulled back; each wall's curvature as its material sees it (the outer
        wall's, −1/(ρ_p + R), concave where the pitch curve is convex), over the groove's
        depth."""
        from camfab.kinds.disc import plate_contact, plate_side

        dense, walls = self.geometry.dense, self.groove
        cam = self.geometry.cam
        sides = (plate_side(cam, dense.working, dense.pressure_angle, None, "the inner wall",
                            always=False),
                 plate_side(cam, walls.outer_dense, dense.pressure_angle, None,
                            "the outer wall", -1, always=False, sign=-1.0))
        return plate_contact(analysis.design, self.geometry, sides)

    def summary(self, analysis: Analysis) -> list[str]:
        walls = self.groove
        changes = walls.contact.changes_deg
        moves = ("contact passes to the other wall (the roller reverses its spin) at "
                 + ", ".join(f"{a:.4g}°" for a in changes) if changes else
                 "the follower never accelerates: no wall carries it")
        return [*super().summary(analysis),
                f"groove: {terse(walls.width)} mm wide (roller {terse(walls.roller_radius)} mm, "
                f"clearance {terse(walls.clearance)} mm), {terse(walls.depth)} mm deep in a plate "
                f"{terse(walls.thickness)} mm thick of radius {terse(walls.outer_radius)} mm; "
                f"{moves}"]

    def pressure_panels(self, analysis: Analysis, top: Any, bottom: Any) -> None:
        from camfab.export.figures import BAD

        super().pressure_panels(analysis, top, bottom)
        # the outer wall folds where a concave ρ_p > −R
        bottom.axhline(-self.geometry.cam.follower.radius, color=BAD, linewidth=0.8,
                       linestyle="--")

    def draw_plate(self, ax: Any, analysis: Analysis) -> None:
        _draw_groove(ax, analysis, self.groove)

    def contact_changes(self, report: dict[str, Any]) -> dict[str, Any]:
        from camfab.export.report_html import num

        return {"title": "Groove walls: where contact changes walls",
                "intro": "The inner wall pushes the follower away from the cam centre where its "
                         "acceleration is positive, the outer wall pulls it back where it is "
                         "negative. At these cam angles the acceleration changes sign: contact "
                         "crosses the clearance to the other wall, and the roller then rolls on "
                         "that wall and reverses its spin.",
                "still": "The follower never accelerates: no wall carries it.",
                "rows": [[num(c["cam_angle_deg"]), f"{c['from']} wall", f"{c['onto']} wall"]
                         for c in report["geometry"]["wall_changes"]]}


def _draw_groove(ax: Any, analysis: Analysis, walls: GrooveWalls) -> None:
    """A groove cam's plate: its outer circle, the groove shaded between its walls, where a
    wall folds, and a tick across the groove wherever contact passes to the other wall."""
    from camfab.curves.plane import perp
    from camfab.export.figures import BAD, CHANGE, CUT, POCKET
    from camfab.geometry.groove import WALL_NAMES

    geom = analysis.geometry
    angle = np.linspace(0, 2 * math.pi, 361)
    rim = walls.outer_radius * np.stack((np.cos(angle), np.sin(angle)), axis=-1)
    ax.fill(rim[:, 0], rim[:, 1], color="#f4d6d2", zorder=0)
    ax.plot(rim[:, 0], rim[:, 1], color=CUT, linewidth=1.2, label="plate outline (cut)")
    outer, inner = (np.vstack((p, p[:1])) for p in (walls.outer_points, walls.inner_points))
    ax.fill(outer[:, 0], outer[:, 1], color="#d9d9d9", zorder=0)
    ax.fill(inner[:, 0], inner[:, 1], color="#f4d6d2", zorder=0)
    ax.plot(outer[:, 0], outer[:, 1], color=POCKET, linewidth=1.0,
            label=f"groove walls ({walls.depth:.4g} mm deep)")
    ax.plot(inner[:, 0], inner[:, 1], color=POCKET, linewidth=1.0)
    if walls.outer_folds.any():
        xy = walls.outer_dense.xy[walls.outer_folds]
        ax.plot(xy[:, 0], xy[:, 1], ".", color=BAD, markersize=2, label="outer wall folds")
    changes = walls.contact.changes
    if not changes.size:
        return
    pitch = geom.cam.pitch(changes, analysis.program.evaluate(changes))
    across = 1.4 * walls.radius * perp(pitch.tangent)
    for k, (centre, step) in enumerate(zip(pitch.xy, across, strict=True)):
        ends = np.array([centre - step, centre + step])
        ax.plot(ends[:, 0], ends[:, 1], color=CHANGE, linewidth=1.6,
                label="contact changes walls" if k == 0 else None)
        label = (f"{walls.contact.changes_deg[k]:.4g}°: onto the "
                 f"{WALL_NAMES[int(walls.contact.onto[k])]} wall")
        tip = centre - 2.0 * step * np.sign(float(np.dot(step, centre)) or 1.0)  # toward the centre
        ax.text(float(tip[0]), float(tip[1]), label, fontsize=8.5, color=CHANGE)



def groove_scene(analysis: Analysis, theta: Array) -> Scene3D:
    """The groove cam's scene (:func:`camfab.kinds.scene3d.plate_scene`): the plate turning, the
    roller on the exact pitch point in the groove, just off its floor, its stem above the
    face."""
    from camfab.kinds.scene3d import first_contact, plate_scene

    walls = analysis.groove
    assert walls is not None
    floor = walls.thickness - walls.depth
    length = analysis.design.follower.roller_length or walls.depth
    low = floor + FLOOR_GAP_SHARE * walls.depth
    contact = first_contact(analysis, theta, (low, low + length))
    return plate_scene(analysis, theta, [contact], walls.outer_radius, walls.thickness,
                       raised=True)


class Groove:
    """The face-groove cam (``cam.type: groove``): a disc cam's pitch curve, the roller held
    between the groove's two walls."""

    drives_both_ways = True
    mounted = "plate"
    inspect_refusal = None  # its drawing's two walls, or a scan, are measured as a scan's

    @staticmethod
    def analyse(design: Design, program: MotionProgram, units: MotionUnits,
                stats: list[SegmentStats], findings: list[Finding]) -> Analysis:
        """A plate cam's analysis with the groove's walls and checks."""
        from camfab.analysis.groove_checks import with_groove

        # the inner wall: the roller plus half the clearance
        clearance = design.follower.groove_clearance / 2
        analysis = analyse_plate(design, program, units, stats, findings, clearance)
        walls, findings = with_groove(analysis)
        plate = analysis.result
        assert isinstance(plate, PlateResult)
        return replace(analysis, findings=findings,
                       result=GrooveResult(plate.geometry, plate.numbers, walls))

    part = staticmethod(groove_part)
    verify = staticmethod(groove_verify)
    scene = staticmethod(groove_scene)

    @staticmethod
    def size_problem(design: Design, follower: FollowerGeometry,
                     grid_pair: tuple[Grid, Grid]) -> SizeProblem:
        """The sizing of the base radius: the inner wall's (the roller plus half the
        clearance), both walls offsets of the pitch curve."""
        from camfab.kinds.plate_sizing import plate_problem

        return plate_problem(design, follower, grid_pair, design.follower.groove_clearance / 2,
                             groove=True)

    @staticmethod
    def check(design: Design) -> None:
        """The plate's ``outer_radius`` must leave a wall of material outside the groove's
        outer wall."""
        from camfab.design.rules import MIN_WALL_MM, fail, mm
        from camfab.geometry.groove import outer_wall_reach

        cam = design.cam
        if cam.outer_radius is None:
            return
        reach = outer_wall_reach(design)
        if cam.outer_radius < reach + MIN_WALL_MM:
            fail(("cam", "outer_radius"), f"must leave at least {MIN_WALL_MM:g} mm of material "
                 f"outside the groove: its outer wall reaches {mm(reach)} from the cam centre "
                 f"(outer_radius at least {mm(reach + MIN_WALL_MM)})")


KIND = Groove()
