"""The globoidal cam: a groove round a globoid blank (hourglass or barrel) drives a roller on
an oscillating arm whose pivot axis crosses the cam axis square, apart from it (THEORY §H).

Its STL is the blank revolved less the groove swept as one closed tube; the DXF is the blank's
half-section for the lathe, with the groove's centre path developed on the pitch globoid. Both
are read back: the roller is put at its pose in the groove of the STL at every half degree,
and the section of the DXF is measured against the exact one.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import cache
from typing import TYPE_CHECKING, Any

import numpy as np

from camfab.analysis.record import TABLE_COLUMNS, Analysis, CamResult, terse
from camfab.analysis.verification import Verification

if TYPE_CHECKING:
    from camfab.analysis.findings import Finding
    from camfab.analysis.globoid_checks import GloboidDense, GloboidNumbers
    from camfab.analysis.kinematics import MotionUnits, SegmentStats
    from camfab.arrays import Array
    from camfab.curves.profile import Profile
    from camfab.design import Design
    from camfab.export.part import Drawing, Part
    from camfab.export.serialise import PartFiles
    from camfab.geometry.globoid import Globoid
    from camfab.geometry.globoid_cam import GloboidCam
    from camfab.kinds.scene3d import Scene3D, Shape
    from camfab.motion.program import MotionProgram
    from camfab.speed.contact import Contact


#: The share of the sampling tolerance within which the boolean of the blank and the groove's
#: tube merges what it meets (:attr:`~camfab.export.part.Difference.tolerance`): the tube
#: crosses the blank's surface along a curve where the two tessellations' edges fall
#: arbitrarily near each other, and would leave slivers there.
MERGE_SHARE = 0.2


@dataclass(frozen=True)
class GloboidResult(CamResult):
    """A globoidal cam's groove on the analysis grid and its key numbers (mm, deg)."""

    globoid: GloboidDense
    numbers: GloboidNumbers
    drawing_title = "The cam in section through its axis, the arm swinging"

    def kind_name(self, design: Design) -> str:
        return f"globoidal cam ({design.cam.globoid})"

    def report_geometry(self, analysis: Analysis) -> dict[str, Any]:
        design = analysis.design
        blank, numbers = self.globoid.blank, self.numbers
        g = blank.follower
        return {
            "globoid": design.cam.globoid,
            "pivot_distance_mm": g.centre, "arm_length_mm": g.arm,
            "roller_radius_mm": design.follower.roller_radius,
            "roller_length_mm": g.length,
            "rest_angle_deg": math.degrees(g.rest),
            "swing_deg": math.degrees(analysis.program.max_lift),
            "outer_radius_mm": blank.outer_radius, "width_mm": blank.width,
            "groove_depth_mm": blank.depth,
            "surface_from_pivot_mm": blank.surface, "floor_from_pivot_mm": blank.floor,
            "groove_width_mm": 2 * g.radius,
            "bore_radius_mm": blank.bore or None,
            "floor_min_radius_mm": numbers.floor_radius,
            "groove_reach_z_mm": numbers.reach_z,
            "end_wall_mm": numbers.end_wall,
            "pressure_angle_max_deg": numbers.pressure.value,
            "pressure_angle_max_at_deg": numbers.pressure.at_deg,
            "pressure_angle_max_from_pivot_mm": numbers.pressure_at_mm,
            "pressure_angle_limit_deg": math.degrees(design.pressure_angle_limit),
            "undercut_roller_radius_mm": (numbers.undercut_radius
                                          if math.isfinite(numbers.undercut_radius) else None),
        }

    def table_columns(self, theta: Array, motion: Array) -> list[tuple[str, Array]]:
        """The largest pressure angle along the roller's contact line, and the largest roller
        radius the flanks take there without folding (``undercut_roller_radius_mm``, the
        diagrams' undercut limit; empty where no roller folds them). No radius of curvature:
        the flanks are surfaces, not curves of the cam (their limit is this one, the undercut
        check's); the pitch radius column SPEC §5 gives every table stays, empty, and the
        report's readout leaves it out."""
        from camfab.speed.model import sample_at

        dense = self.globoid
        g = dense.blank.follower
        ells = dense.blank.contact()[:, None]
        phi = np.degrees(g.pressure_angle(ells, g.rest + motion[0][None, :],
                                          motion[1][None, :])).max(axis=0)
        limit = sample_at(dense.theta, dense.undercut_radius, theta)
        return [(TABLE_COLUMNS[0], phi), (TABLE_COLUMNS[1], np.full(theta.size, np.nan)),
                ("undercut_roller_radius_mm", np.where(np.isfinite(limit), limit, np.nan))]

    def dynamics_note(self, analysis: Analysis) -> str:
        return ("a globoidal cam drives its follower both ways without a spring: the forces on "
                "its flanks are the cam at its speed's (contact_stress_..., roller_life_h)")

    def contact(self, analysis: Analysis) -> Contact:
        """The roller on the flank behind it where it is pushed along its swing, on the other
        where it is held back, in line contact along the roller inside the groove. Each
        flank's curvature across the contact is the sum of its principal curvatures, from the
        regularity of the flanks (:func:`~camfab.geometry.globoid.flank_curvature`); the
        normal force balances the arm's moment, F·L = F_n·mean(ℓ cos α) with the load spread
        evenly along the line (:func:`mean_lever`, converged); the roller rolls over the
        groove as its middle moves against the cam."""
        from camfab.analysis.globoid_checks import UNDERCUT_STEP
        from camfab.geometry.globoid import flank_coefficients, flank_curvature
        from camfab.speed.contact import Contact, ContactSide

        dense, design, program = self.globoid, analysis.design, analysis.program
        g = dense.blank.follower
        theta, motion, ells = dense.theta, dense.motion, dense.ells
        h = UNDERCUT_STEP
        coefficients = flank_coefficients(g, theta[None, :], ells[:, None], motion[:, None, :],
                                          program.evaluate(theta + h)[:, None, :],
                                          program.evaluate(theta - h)[:, None, :], h)
        psi = g.rest + motion[0]
        reach = g.centre - ells[:, None] * np.cos(psi)[None, :]  # D = C − ℓ cos ψ
        behind = -np.sign(g.sigma * reach)  # the side s with s·n against the swing
        lever = mean_lever(g, ells[0], ells[-1], psi, motion[1])
        normal = g.arm / lever
        middle = 0.5 * (ells[0] + ells[-1])
        rolling = np.hypot(g.centre - middle * np.cos(psi), motion[1] * middle)
        sides = tuple(ContactSide(name, carries, flank_curvature(*coefficients, carries * behind,
                                                                 g.radius),
                                  normal, rolling, always=False, rows=ells,
                                  rows_from="from the pivot")
                      for name, carries in (("the flank behind the roller", 1),
                                            ("the flank ahead of it", -1)))
        radius = design.follower.roller_radius or 0.0
        return Contact(theta, "line", 1.0 / radius, abs(float(ells[-1] - ells[0])), sides,
                       radius)

    def summary(self, analysis: Analysis) -> list[str]:
        blank, numbers = self.globoid.blank, self.numbers
        shape = "waist" if blank.inward > 0 else "crown"
        return [f"globoid ({analysis.design.cam.globoid}): {terse(blank.outer_radius)} mm at "
                f"its {shape}, {terse(blank.width)} mm wide, groove {terse(blank.depth)} mm "
                f"deep; pressure angle up to {terse(numbers.pressure.value)}° along the "
                f"roller; flanks fold at a roller of {terse(numbers.undercut_radius)} mm"]

    def pressure_panels(self, analysis: Analysis, top: Any, bottom: Any) -> None:
        """The pressure angle at the roller's two ends in the groove (and the largest along
        it); the largest roller the flanks take without folding, against the roller's."""
        from camfab.export.figures import BAD, LEGEND_FONT, PITCH, bands, clip_radii, thin

        dense = self.globoid
        phi = np.degrees(np.abs(dense.pressure_angle))
        theta, outer, inner, limit = thin(np.degrees(dense.theta), phi[0], phi[-1],
                                          dense.undercut_radius)
        top.plot(theta, inner, color=PITCH, linewidth=1.0,
                 label=f"α, roller's inner end ({dense.ells[-1]:.4g} mm)")
        top.plot(theta, outer, linewidth=1.0, linestyle="--",
                 label=f"α, blank's surface ({dense.ells[0]:.4g} mm)")
        bands(top, dense.theta, phi.max(axis=0) > math.degrees(
            analysis.design.pressure_angle_limit), "over the limit")
        bottom.plot(theta, clip_radii(limit), color=PITCH, linewidth=1.0,
                    label="largest roller radius\nthe flanks take")
        wall = dense.blank.follower.radius
        bottom.axhline(wall, color=BAD, linewidth=0.8, linestyle="--",
                       label=f"roller {wall:.4g} mm")
        bands(bottom, dense.theta, dense.undercut_radius <= wall, "undercut")
        bottom.set_ylabel("undercut\nlimit (mm)", fontsize=LEGEND_FONT)

    def drawing(self, analysis: Analysis) -> str:
        return _drawing_svg(analysis, self.globoid.blank)


def _drawing_svg(analysis: Analysis, blank: GloboidCam) -> str:
    """The cam cut through its axis and the pivot (the plane of the arm): the blank's section
    both sides of the axis, the groove's reach over the swing, the pivot, the pitch circle,
    and the arm with its roller (group ``follower``), which carries the animation's frames:
    it swings about the pivot as the motion table says."""
    from camfab.export.chart import Figure
    from camfab.export.figures import (
        CUT,
        FIGURE_WIDTH,
        FOLLOWER,
        LEGEND_FONT,
        PITCH,
        REFERENCE,
        frame_angles,
        group_points,
        rotations,
        scale_bar,
        side_margins,
        turned,
    )

    design, program = analysis.design, analysis.program
    g = blank.follower
    section = blank.section().points(max(1e-4, 2e-4 * blank.width))
    # as high as the section and the swinging roller need at the panel's width
    swing = np.abs(np.sin(g.rest + np.array([0.0, program.max_lift])))
    tall = max(0.6 * blank.width, float(np.max(swing)) * (g.arm + g.length / 2.0) + g.radius)
    across = float(np.max(section[:, 0])) + g.centre
    left, right = side_margins()
    height = min(9.0, max(3.0, (right - left) * FIGURE_WIDTH * 2.0 * tall / across + 1.2))
    fig = Figure(FIGURE_WIDTH, height, "drawing", left=left, right=right,
                 bottom=0.7 / height, top=1.0 - 0.45 / height)
    [ax] = fig.subplots()
    ax.set_aspect("equal")
    for sign, label in ((1.0, "the blank in section"), (-1.0, None)):
        loop = np.vstack((section, section[:1]))
        ax.plot(sign * loop[:, 0], loop[:, 1], color=CUT, linewidth=1.2, label=label)
    reach = max(float(np.max(section[:, 0])), g.centre, 1e-9)
    ax.plot([0.0, 0.0], [-0.6 * blank.width, 0.6 * blank.width], color="#555555",
            linewidth=0.8, linestyle="-.", label="cam axis")
    # the groove's reach over the swing: between the surface and the floor about the pivot
    psi = g.rest + np.linspace(0.0, program.max_lift, 61)
    band = np.concatenate((blank.surface * np.column_stack((-np.cos(psi), np.sin(psi))),
                           blank.floor * np.column_stack((-np.cos(psi), np.sin(psi)))[::-1]))
    band = np.vstack((band, band[:1])) + np.array([g.centre, 0.0])
    ax.plot(band[:, 0], band[:, 1], color=REFERENCE, linewidth=0.8,
            label="the groove over the swing")
    arc = g.rest + np.linspace(-0.15, program.max_lift + 0.15, 61)
    ax.plot(g.centre - g.arm * np.cos(arc), g.arm * np.sin(arc), color=PITCH, linewidth=0.8,
            linestyle="--", label="pitch circle")
    ax.plot([g.centre], [0.0], "+", color="black", markersize=10)
    with ax.group("follower"):
        a = np.array([-math.cos(g.rest), math.sin(g.rest)])
        side = np.array([a[1], -a[0]])
        pivot = np.array([g.centre, 0.0])
        outer, inner = pivot + blank.roller_outer * a, pivot + blank.roller_inner * a
        r = design.follower.roller_radius or 0.0
        corners = np.array([outer + r * side, inner + r * side, inner - r * side,
                            outer - r * side, outer + r * side])
        # a convex globoid's arm reaches past the cam: its yoke goes round the blank
        ax.plot([pivot[0], outer[0]], [pivot[1], outer[1]], color=FOLLOWER, linewidth=2.0,
                linestyle="-" if blank.inward > 0 else "--",
                label="arm" if blank.inward > 0 else "arm's line (its yoke\nround the blank)")
        ax.plot(corners[:, 0], corners[:, 1], color=FOLLOWER, linewidth=1.5, label="roller")
        ax.plot([pivot[0]], [pivot[1]], "o", color=FOLLOWER, markersize=4)
    theta = frame_angles(design.table_step)
    s = program.evaluate(theta)[0]
    move = -(s - s[0])  # ψ grows clockwise in this view (toward +z from the line of centres)
    moving = group_points(ax, "follower")
    ends = move[[int(np.argmin(move)), int(np.argmax(move))]]
    ax.include(*turned(moving, pivot, ends).T)
    ax.include([-reach, reach], [0.0, 0.0])
    scale_bar(ax, 2.0 * reach, design.units, 1.0 / design.mm_per_unit)
    ox, oy, kx, ky = ax.to_frame()
    ax.animate("follower", rotations(move, (ox + kx * pivot[0], oy - ky * pivot[1])))
    ax.set_title(f"{design.name} at θ = {{θ}}°: globoidal cam ({design.cam.globoid}) cut "
                 "through its axis and the pivot", fontsize=10)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("z, the cam axis (mm)")
    ax.legend(fontsize=LEGEND_FONT, outside_right=True)
    return fig.svg()


#: In the 3-D view: the arm's width and height as a share of the roller's diameter, and how far
#: a convex globoid's yoke passes outside the blank, as a share of its largest radius.
ARM_SHARE = 0.6
YOKE_CLEARANCE_SHARE = 0.1


def globoid_scene(analysis: Analysis, theta: Array) -> Scene3D:
    """The globoid's scene: the blank (its STL about Z, from z = −width/2 to width/2) turning by
    σθ about Z, the arm turning about the pivot axis (parallel to Y through (C, 0, 0)) to
    ψ = ψ₀ + s, the roller on it along the arm from ``arm − length/2`` to ``arm + length/2``
    from the pivot (:meth:`~camfab.geometry.globoid.Globoid.axis_point`): the follower's frame
    is the pivot's, its X axis along the arm toward the roller and its Y axis the pivot's."""
    from camfab.kinds.scene3d import (
        Scene3D,
        Shape,
        along_x,
        along_y,
        box_extent,
        rigid,
        turning,
    )

    dense = analysis.globoid
    assert dense is not None
    blank = dense.blank
    g = blank.follower
    psi = g.rest + analysis.program.evaluate(theta)[0]
    arm = g.axis_direction(psi)
    across = np.cross(arm, np.array([0.0, 1.0, 0.0]))
    turn = np.stack((arm, np.broadcast_to([0.0, 1.0, 0.0], arm.shape), across), axis=-1)
    follower = rigid(turn, np.array([g.centre, 0.0, 0.0]))
    radius = analysis.design.follower.roller_radius or g.radius
    roller = Shape("cylinder", "roller", (radius, g.length),
                   rigid(along_x(), np.array([g.arm, 0.0, 0.0])))
    size = ARM_SHARE * 2.0 * radius
    hub = Shape("cylinder", "pivot", (size, 2.0 * size), rigid(along_y(), np.zeros(3)))
    reach = max(blank.outer_radius, blank.ends_radius())
    shapes = (roller, *_arm(blank.roller_outer, blank.inward < 0,
                            reach * (1.0 + YOKE_CLEARANCE_SHARE) + size, size), hub)
    half = blank.width / 2.0
    return Scene3D(theta, turning(g.sigma * theta)[None], shapes, follower,
                   box_extent([-reach, -reach, -half], [reach, reach, half]),
                   np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 1.0]]))


def _arm(end: float, yoke: bool, offset: float, size: float) -> tuple[Shape, ...]:
    """The arm from the pivot to the roller's outer *end* (mm along the arm), or where it
    would pass through the blank (a convex globoid: *yoke*) a yoke round it, *offset* (mm) to
    the side along the pivot's axis; *size* (mm) wide and high."""
    from camfab.kinds.scene3d import bar

    pivot, tip = np.zeros(3), np.array([end, 0.0, 0.0])
    if not yoke:
        return (bar("arm", pivot, tip, size, size),)
    side = np.array([0.0, offset, 0.0])
    return (bar("arm", pivot, pivot + side, size, size),
            bar("arm", pivot + side, tip + side, size, size),
            bar("arm", tip + side, tip, size, size))


class Globoidal:
    """The globoidal cam (``cam.type: globoidal``)."""

    drives_both_ways = True
    mounted = "globoid"
    inspect_refusal = ("is a globoidal cam: its groove is inspected from a 3-D scan or CMM "
                       "points (CSV of x, y, z, PLY or STL), not from a drawing")

    @staticmethod
    def check(design: Design) -> None:
        """The groove in the blank: the floor past the roller's end (and the reach of its end
        face), the roller's outer end outside the blank, the floor short of the cam axis and
        the bore, the blank's ends past the groove; and its tube no larger than camfab
        builds."""
        from camfab.geometry.globoid_cam import globoid_cam

        blank = globoid_cam(design)
        check_blank(design, blank)
        check_tube_size(design, blank)

    @staticmethod
    def analyse(design: Design, program: MotionProgram, units: MotionUnits,
                stats: list[SegmentStats], findings: list[Finding]) -> Analysis:
        """The groove's pressure angle, undercut and fit (before *findings*)."""
        from camfab.analysis.globoid_checks import (
            globoid_dense,
            globoid_findings,
            globoid_numbers,
        )
        from camfab.geometry.globoid_cam import globoid_cam

        dense = globoid_dense(globoid_cam(design), program)
        numbers = globoid_numbers(dense, program)
        findings = [*globoid_findings(design, dense, numbers), *findings]
        return Analysis(design, program, units, stats, findings, GloboidResult(dense, numbers))

    scene = staticmethod(globoid_scene)

    @staticmethod
    def part(analysis: Analysis) -> Part:
        return globoid_part(analysis)

    @staticmethod
    def verify(analysis: Analysis, part: Part, files: PartFiles) -> tuple[Analysis,
                                                                          Verification]:
        return analysis, globoid_verify(analysis, part, files)


KIND = Globoidal()


def check_blank(design: Design, blank: GloboidCam) -> None:
    """The rules of a globoidal design that need its groove's geometry (raising
    :class:`~camfab.design.rules.RuleViolation`)."""
    from camfab.design.rules import MIN_WALL_MM, fail, mm, wall_need
    from camfab.geometry.globoid_cam import FLOOR_GAP_MM, end_reach, groove_extent

    cam = design.cam
    g = blank.follower
    given = ("cam", "outer_radius") if cam.outer_radius is not None else ("cam", "groove_depth")
    if blank.inward * (blank.surface - blank.roller_outer) <= 0.0:
        fail(given, f"puts the blank's surface {mm(blank.surface)} from the pivot, beyond the "
             f"roller's outer end ({mm(blank.roller_outer)}): the arm would run in the groove")
    if cam.outer_radius is not None:
        reach = end_reach(g, blank.roller_inner, design.program)
        past = blank.inward * (blank.floor - blank.roller_inner)
        if past < reach + FLOOR_GAP_MM:
            need = blank.depth + reach + FLOOR_GAP_MM - past
            fail(("cam", "groove_depth"), f"puts the groove's floor {mm(past)} past the "
                 f"roller's inner end, whose end face sweeps {mm(reach)} past it as the arm "
                 f"tilts: with {FLOOR_GAP_MM:g} mm of clearance the groove must be at least "
                 f"{mm(need)} deep at this outer_radius")
    if blank.inward < 0 and blank.outer_radius + MIN_WALL_MM > g.centre:
        fail(given, f"gives a crown of radius {mm(blank.outer_radius)}: the barrel must stay "
             f"{MIN_WALL_MM:g} mm inside the pivot axis, {mm(g.centre)} from the cam axis")
    if cam.width is not None and blank.inward > 0 and cam.width / 2.0 >= blank.surface:
        fail(("cam", "width"), f"must be less than {mm(2 * blank.surface)}: the hourglass "
             "closes beyond it")
    if blank.ends_radius() <= 0.0:
        fail(("cam", "width"), "is wider than the barrel: its ends would pass the cam axis")
    floor_r, corner_r, reach_z = groove_extent(blank, design.program)
    least = min(floor_r, corner_r)
    if least < wall_need():  # the blank's size puts the floor at the axis, whatever the bore
        fail(given, f"takes the groove's floor to within {mm(least)} of the cam axis; it must "
             f"stay {MIN_WALL_MM:g} mm clear of it")
    if least < wall_need(cam.bore or 0.0):
        fail(("cam", "bore"), f"reaches the groove's floor (it comes within {mm(least)} of the "
             f"cam axis; the bore must leave {MIN_WALL_MM:g} mm under it)")
    if cam.width is not None and reach_z + MIN_WALL_MM > cam.width / 2.0:
        fail(("cam", "width"), f"the groove reaches z = ±{mm(reach_z)}: the blank must be at "
             f"least {mm(2 * (reach_z + MIN_WALL_MM))} wide to leave {MIN_WALL_MM:g} mm walls")


def check_tube_size(design: Design, blank: GloboidCam) -> None:
    """The groove's tube no larger than camfab builds
    (:func:`camfab.geometry.tube_budget.check_tube`): the tube :func:`globoid_part` would make,
    its facets' diagonals held to the tolerance unless a flank folds (which only a tube too
    large that way asks)."""
    from camfab.curves.sampling import SAMPLING_SHARE
    from camfab.geometry.globoid_cam import tube_plan
    from camfab.geometry.tube_budget import COUNTED, MAX_TUBE_FACETS, check_tube

    program, tolerance = design.program, design.manufacturing.tolerance

    def facets(twist: bool) -> Callable[[float, int], int]:
        @cache  # (the count at the design's tolerance is asked twice: here and to refuse)
        def count(tol: float, most: int) -> int:
            return tube_plan(blank, program, SAMPLING_SHARE * tol, twist, most).facets

        return count

    facets_at = facets(True)
    if facets_at(tolerance, COUNTED * MAX_TUBE_FACETS) > MAX_TUBE_FACETS and _folds(blank,
                                                                                  program):
        facets_at = facets(False)
    check_tube(facets_at, tolerance, "a globoid's groove", len(program.segments))


def _folds(blank: GloboidCam, program: MotionProgram) -> bool:
    """Whether a flank of the groove folds (the undercut check fails: see
    :func:`camfab.analysis.globoid_checks.undercut_finding`)."""
    from camfab.analysis.globoid_checks import globoid_dense

    dense = globoid_dense(blank, program)
    return bool(np.any(dense.undercut_radius <= blank.follower.radius))


def _undercut(analysis: Analysis) -> bool:
    return any(f.id == "undercut" and not f.ok for f in analysis.findings)


def globoid_part(analysis: Analysis) -> Part:
    """The globoid's part: the blank's half-section revolved less the groove's tube (withheld
    when a flank folds); the half-section and the developed centre path as the drawing, the
    half-section as the view."""
    from camfab.curves.sampling import SAMPLING_SHARE
    from camfab.export.part import Difference, Mesh, Part, Revolution
    from camfab.export.stl import circle_segments
    from camfab.geometry.globoid_cam import tube, tube_surfaces
    from camfab.geometry.plate import Contours

    design, dense = analysis.design, analysis.globoid
    assert dense is not None
    blank, program = dense.blank, analysis.program
    tolerance = SAMPLING_SHARE * design.manufacturing.tolerance
    section = blank.section()
    folded = _undercut(analysis)
    groove = tube(blank, program, tolerance, twist=not folded)
    withheld: dict[str, str] = {}
    solid = None
    if folded:
        withheld["stl"] = ("a flank of the groove folds over itself (see the undercut check): "
                           "there is no solid the roller could run in")
    else:
        points = section.points(tolerance)
        radius = float(np.max(points[:, 0]))
        body = Revolution(points, circle_segments(radius, tolerance), section)
        grids, probes = tube_surfaces(blank, program, groove)
        solid = Difference(body, Mesh(groove.vertices, groove.faces, grids, probes),
                           cut_first=True, tolerance=MERGE_SHARE * tolerance)
    drawing = _section_drawing(analysis, blank, section, tolerance)
    return Part({design.name: drawing}, {design.name: (Contours((section,)), None)}, solid,
                needs=("dxf", "stl"), withheld=withheld, made=groove)


def _section_drawing(analysis: Analysis, blank: GloboidCam, section: Profile,
                     tolerance: float) -> Drawing:
    """The blank's half-section (*section*) for the lathe on ``CUT`` (r across, the cam axis
    up, the axis on ``MARK``), and below it the groove's centre path developed on the pitch
    globoid on ``PITCH`` in its frame on ``MARK``, with notes."""
    from camfab.export.part import Drawing
    from camfab.geometry.arcfit import fit_arcs
    from camfab.geometry.globoid_cam import development

    design, program = analysis.design, analysis.program
    g = blank.follower
    scale = 1.0 / design.mm_per_unit
    drawing = Drawing(design.units)
    half = blank.width / 2.0
    drawing.line((0.0, (-half - 5.0) * scale), (0.0, (half + 5.0) * scale), "MARK")
    dev = development(blank, program, math.radians(0.25))
    gap = 10.0 + 0.2 * blank.width
    shift = np.array([0.0, -half - gap - (dev.high - dev.low)]) - np.array([0.0, dev.low])
    frame = np.array([[0.0, dev.low], [dev.width, dev.low], [dev.width, dev.high],
                      [0.0, dev.high]]) + shift
    for a, b in zip(frame, np.roll(frame, -1, axis=0), strict=True):
        drawing.line(tuple(a * scale), tuple(b * scale), "MARK")
    centre = fit_arcs(dev.centre + shift, tolerance, closed=False)
    drawing.contour(centre, scale, "PITCH", closed=False)
    unit = design.units
    text = [f"{design.name}: globoidal cam ({design.cam.globoid}), {design.cam.rotation}: the "
            f"blank's half-section (r across, the cam axis up), {blank.outer_radius * scale:.6g} "
            f"{unit} at its {'waist' if blank.inward > 0 else 'crown'}, "
            f"{blank.width * scale:.6g} {unit} wide; the surface an arc of radius "
            f"{blank.surface * scale:.6g} {unit} about the pivot",
            f"below: the groove's centre path developed on the pitch globoid (around: the cam "
            f"angle × {abs(g.centre - g.arm) * scale:.6g} {unit}; up: the arc of radius "
            f"{g.arm * scale:.6g} {unit} about the pivot), reference only: the groove is cut "
            "from the STL"]
    height = max(blank.width * scale * 0.03, 1e-3)
    low = float(frame[:, 1].min())
    for row, line in enumerate(text, start=1):
        drawing.text(line, height, (0.0, (low - 1.6 * row * height / scale) * scale))
    drawing.contour(section, scale, "CUT")
    return drawing


def globoid_verify(analysis: Analysis, part: Part, files: PartFiles) -> Verification:
    """The roller put at its pose in the groove of the STL read back at every
    :data:`~camfab.geometry.globoid_cam.VERIFY_STEP` (or, with a flank folded, in the tube
    as computed): each flank must stand within the tolerance of the roller's wall radius and
    never inside it; the STL checked closed, outward and of the solid's volume; the DXF's
    half-section measured against the exact one."""
    from camfab.export.dxf import read_cut_outline
    from camfab.geometry.disc_geometry import LiftCheck
    from camfab.geometry.globoid_cam import VERIFY_STEP
    from camfab.geometry.globoid_run import mesh_edges, near_roller, roller_run
    from camfab.kinds.readback import groove_mesh
    from camfab.motion.program import cycle_angles

    design, dense = analysis.design, analysis.globoid
    assert dense is not None
    blank, program = dense.blank, analysis.program
    tolerance = design.manufacturing.tolerance
    folded = _undercut(analysis)
    vertices, _, stl_check, pairs = groove_mesh(part, files, tolerance, folded)
    source = ("the groove's tube as computed (a flank folds: no STL)" if stl_check is None
              else f"the roller put in the groove of {design.name}.stl read back")
    theta = cycle_angles(VERIFY_STEP * (4 if folded else 1))  # (a fold: what it would do)
    edges = mesh_edges(vertices, pairs, near_roller(blank, vertices))
    run = roller_run(blank, edges, theta, program.evaluate(theta), tolerance)
    # each flank's distance from the roller's wall radius: off it (> 0) or into it (< 0)
    error = np.maximum(np.abs(run.gap_plus_mm), np.abs(run.gap_minus_mm))
    error = np.maximum(error, run.cut_mm)
    written = read_cut_outline(files.files["dxf"][f"{design.name}.dxf"], design.mm_per_unit)
    exact = blank.section().points(tolerance / 64.0)
    deviation = float(written.distance(exact).max())
    return Verification(LiftCheck(theta, error, error), source, len(written.vertices),
                        deviation, stl_check, exempt=folded,
                        exempt_because="a flank of the groove folds over itself",
                        exempt_check="undercut")


#: Gauss–Legendre nodes of the mean lever along a globoid's roller: ℓ cos α(ℓ) is smooth along
#: it, and 8 nodes already give its mean to 1e-15 on the demos.
LEVER_NODES = 16


def mean_lever(g: Globoid, inner: float, outer: float, psi: Array, dpsi: Array) -> Array:
    """mean over ℓ from *inner* to *outer* (mm from the pivot) of ℓ cos α(ℓ), α the pressure
    angle along the roller of the globoid's follower *g* at the swing *psi* (rad) and its rate
    *dpsi* (rad/rad), by Gauss–Legendre quadrature of :data:`LEVER_NODES` nodes (mm)."""
    nodes, weights = np.polynomial.legendre.leggauss(LEVER_NODES)
    ells = 0.5 * (inner + outer) + 0.5 * (outer - inner) * nodes
    alpha = g.pressure_angle(ells[:, None], psi[None, :], dpsi[None, :])
    return 0.5 * np.sum(weights[:, None] * ells[:, None] * np.cos(alpha), axis=0)

