"""The drum (cylindrical) cam: a groove cut round a cylinder drives a translating roller along
the drum's axis (THEORY §C). Its STL is read back and the roller run through the groove between
the wall vertices it finds; the groove developed at the surface (DXF, SVG) is measured against
the exact walls.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from camfab.analysis.record import TABLE_COLUMNS, Analysis, CamResult, terse
from camfab.analysis.verification import Verification

if TYPE_CHECKING:
    from camfab.analysis.drum_checks import DrumNumbers
    from camfab.analysis.findings import Finding
    from camfab.analysis.kinematics import MotionUnits, SegmentStats
    from camfab.analysis.sizing import Grid, SizeProblem
    from camfab.arrays import Array
    from camfab.curves.follower import FollowerGeometry
    from camfab.curves.profile import Profile
    from camfab.design import Design
    from camfab.export.part import Drawing, Part, Solid
    from camfab.export.serialise import PartFiles
    from camfab.geometry.drum import Drum as DrumGeometry
    from camfab.geometry.drum import DrumDense
    from camfab.kinds.scene3d import Scene3D
    from camfab.motion.program import MotionProgram
    from camfab.speed.contact import Contact

#: Cam-angle step at which the roller is run through a drum's groove read back from the STL.
DRUM_VERIFY_STEP = math.radians(0.5)

#: The share of ``manufacturing.tolerance`` the groove developed at the surface is sampled to:
#: its arcs hold the chords between those points within twice this
#: (:data:`camfab.geometry.plate.ARC_FACTOR`), so within three times it of the groove as
#: computed, the rest left to the reading back and the rounding of the files.
DEVELOPED_SHARE = 0.25

#: In the 3-D view, the roller's end stands this share of the groove's depth off its floor; its
#: stem reaches this share of the drum's radius beyond it and is this share of the roller's
#: diameter wide.
FLOOR_GAP_SHARE = 0.05
STEM_SHARE = 0.4
STEM_WIDTH_SHARE = 0.6


@dataclass(frozen=True)
class DrumResult(CamResult):
    """A drum cam's groove walls over its depth (mm, dense in cam angle) and key numbers."""

    drum: DrumDense
    numbers: DrumNumbers
    drawing_title = "The groove developed, the roller running in it"

    def kind_name(self, design: Design) -> str:
        return "drum cam"

    def report_geometry(self, analysis: Analysis) -> dict[str, Any]:
        cam, fol = analysis.design.cam, analysis.design.follower
        d, numbers = self.drum.drum, self.numbers
        return {
            "radius_mm": cam.radius, "length_mm": cam.length,
            "groove_depth_mm": cam.groove_depth, "roller_radius_mm": fol.roller_radius,
            "root_radius_mm": d.root,
            "pitch_radius_mm": d.pitch,
            "groove_width_mm": 2 * d.roller,
            "groove_start_mm": d.start,
            "bore_radius_mm": d.bore or None,
            "root_pressure_angle_max_deg": numbers.root_pressure.value,
            "root_pressure_angle_max_at_deg": numbers.root_pressure.at_deg,
            "pitch_pressure_angle_max_deg": numbers.pitch_pressure.value,
            "pitch_pressure_angle_max_at_deg": numbers.pitch_pressure.at_deg,
            "outer_pressure_angle_max_deg": numbers.outer_pressure.value,
            "outer_pressure_angle_max_at_deg": numbers.outer_pressure.at_deg,
            "pressure_angle_limit_deg": math.degrees(analysis.design.pressure_angle_limit),
            "developed_min_radius_of_curvature_mm": numbers.min_developed_radius.value,
            "developed_min_radius_of_curvature_at_deg": numbers.min_developed_radius.at_deg,
            "developed_min_radius_of_curvature_at_radius_mm":
                numbers.min_developed_radius_at_mm,
        }

    def table_columns(self, theta: Array, motion: Array) -> list[tuple[str, Array]]:
        """At the groove's floor, and the groove developed at its pitch radius."""
        d = self.drum.drum
        return list(zip(TABLE_COLUMNS, (np.degrees(d.pressure_angle(motion[1], d.root)),
                                        d.developed_radius(motion[1], motion[2], d.pitch),
                                        np.full(theta.size, np.nan)), strict=True))

    def summary(self, analysis: Analysis) -> list[str]:
        d, numbers = self.drum.drum, self.numbers
        return [f"drum: radius {terse(d.radius)} mm, groove floor at {terse(d.root)} mm, "
                f"{terse(2 * d.roller)} mm wide, roller centre at z = {terse(d.start)} mm at zero "
                f"lift; pressure angle up to {terse(numbers.root_pressure.value)}° at the floor; "
                f"developed groove's smallest radius of curvature "
                f"{terse(numbers.min_developed_radius.value)} mm"]

    def contact(self, analysis: Analysis) -> Contact:
        """The roller on the groove's lower flank where it is pushed along its motion (+Z), on
        the upper flank where it is pulled back, in line contact from the floor to the
        surface, each flank's curvature across the contact exact
        (:meth:`~camfab.geometry.drum.Drum.flank_curvature`) at the radii of the analysis;
        the normal force is the force along the motion over the mean of cos φ along the line
        (:func:`mean_cosine`, exact), and the roller rolls along the groove at its pitch
        radius."""
        from camfab.speed.contact import Contact, ContactSide, contact_length

        dense, design = self.drum, analysis.design
        d = dense.drum
        radii = dense.radii[:, None]
        lower, upper = (d.flank_curvature(dense.motion[1], dense.motion[2], radii, side)
                        for side in (True, False))
        normal = 1.0 / mean_cosine(d.root, d.radius, dense.motion[1])
        rolling = np.hypot(d.pitch, dense.motion[1])
        sides = tuple(ContactSide(name, carries, curvature, normal, rolling, always=False,
                                  rows=dense.radii, rows_from="from the drum's axis")
                      for name, carries, curvature in (("the lower flank", 1, lower),
                                                       ("the upper flank", -1, upper)))
        length, note = contact_length(design)
        radius = design.follower.roller_radius or 0.0
        return Contact(dense.theta, "line", 1.0 / radius, length, sides, radius, note=note)

    def pressure_panels(self, analysis: Analysis, top: Any, bottom: Any) -> None:
        """The pressure angle and the developed radius of curvature at the groove's floor and
        at the surface, against the roller's radius."""
        from camfab.export.figures import BAD, clip_radii, thin

        dense = self.drum
        theta, phi, rho = thin(np.degrees(dense.theta), np.degrees(dense.pressure_angle),
                               dense.developed_radius)
        for row, name in ((0, "floor"), (-1, "surface")):
            top.plot(theta, phi[row], linewidth=1.0,
                     label=f"φ at the {name} (r = {dense.radii[row]:.4g} mm)")
            bottom.plot(theta, clip_radii(rho[row]), linewidth=1.0,
                        label=f"developed ρ at the {name}")
        bottom.axhline(dense.drum.roller, color=BAD, linewidth=0.8, linestyle="--",
                       label=f"roller {dense.drum.roller:.4g} mm")
        bottom.axhline(-dense.drum.roller, color=BAD, linewidth=0.8, linestyle="--")

    def drawing(self, analysis: Analysis) -> str:
        return _drawing_svg(analysis, self.drum)


def mean_cosine(inner: float, outer: float, ds: Array) -> Array:
    """The mean of cos φ = r/√(r² + s′²) over the contact line from radius *inner* to *outer*
    (mm) at the lift's rate *ds* (mm/rad), exact: the integral of r/√(r² + s′²) is
    √(r² + s′²), so the mean is (r₁ + r₀)/(√(r₁² + s′²) + √(r₀² + s′²)) (written without the
    difference of the roots, which cancels)."""
    ds = np.asarray(ds, dtype=np.float64)
    return (outer + inner) / (np.hypot(outer, ds) + np.hypot(inner, ds))


def _drawing_svg(analysis: Analysis, dense: DrumDense) -> str:
    """The groove developed at the drum's surface, seen from outside, with the roller in it and
    a scale bar; the roller (group ``follower``) carries the animation's frames: it runs along
    the groove as the drum turns and the follower moves."""
    from camfab.export.chart import Figure
    from camfab.export.figures import (
        CUT,
        FIGURE_WIDTH,
        FOLLOWER,
        LEGEND_FONT,
        PITCH,
        REFERENCE,
        frame_angles,
        scale_bar,
        side_margins,
        translations,
    )
    from camfab.geometry.drum_mesh import development

    d = dense.drum
    design = analysis.design
    dev = development(d, analysis.program, 0.01)
    # as high as the developed surface needs at the panel's width, plus margins
    left, right = side_margins()
    panel = (right - left) * FIGURE_WIDTH * 1.1 * dev.height / max(dev.width, 1e-9)
    height = min(9.0, max(2.8, panel + 1.0))
    fig = Figure(FIGURE_WIDTH, height, "drawing", left=left, right=right,
                 bottom=0.55 / height, top=1.0 - 0.4 / height)
    [ax] = fig.subplots()
    ax.set_aspect("equal")
    ax.plot([0, dev.width, dev.width, 0, 0], [0, 0, dev.height, dev.height, 0],
            color=REFERENCE, linewidth=0.7, label="the drum's surface")
    ax.plot(dev.lower[:, 0], dev.lower[:, 1], color=CUT, linewidth=1.2, label="groove walls")
    ax.plot(dev.upper[:, 0], dev.upper[:, 1], color=CUT, linewidth=1.2)
    ax.plot(dev.centre[:, 0], dev.centre[:, 1], color=PITCH, linewidth=0.8, linestyle="--",
            label="roller axis")
    start = dev.centre[0]
    angle = np.linspace(0, 2 * math.pi, 181)
    radius = design.follower.roller_radius or 0.0
    with ax.group("follower"):
        ax.plot(start[0] + radius * np.cos(angle), start[1] + radius * np.sin(angle),
                color=FOLLOWER, linewidth=1.5, label="roller")
        ax.plot([start[0]], [start[1]], ".", color=FOLLOWER)
    scale_bar(ax, dev.width, design.units, 1.0 / design.mm_per_unit)
    theta = frame_angles(design.table_step)
    s = analysis.program.evaluate(theta)[0]
    _, _, kx, ky = ax.to_frame()
    ax.animate("follower", translations(kx * d.radius * (-d.sigma * theta),
                                        -ky * (s - s[0])))
    ax.set_title(f"{design.name} at θ = {{θ}}°: groove developed at the surface (r = "
                 f"{d.radius:.4g} mm), seen from outside", fontsize=10)
    ax.set_xlabel("around the drum (mm)")
    ax.set_ylabel("z (mm)")
    ax.legend(fontsize=LEGEND_FONT, outside_right=True)
    return fig.svg()


def drum_scene(analysis: Analysis, theta: Array) -> Scene3D:
    """The drum's scene: the drum (its STL along Z from 0 to its length) turning so that the
    roller's axis, at polar angle α = −σθ on the drum (:meth:`~camfab.geometry.drum.Drum.
    axis_angle`), stays on +Y; the roller on that radial axis, at the height ``start + s`` of
    its centre, from just off the groove's floor outward, and its stem beyond the drum."""
    from camfab.kinds.scene3d import Scene3D, Shape, along_y, bar, box_extent, rigid, turning

    dense = analysis.drum
    assert dense is not None
    d, fol = dense.drum, analysis.design.follower
    height = d.start + analysis.program.evaluate(theta)[0]
    radius = fol.roller_radius or d.roller
    length = fol.roller_length or d.depth
    low = d.root + FLOOR_GAP_SHARE * d.depth
    roller = Shape("cylinder", "roller", (radius, length),
                   rigid(along_y(), np.array([0.0, low + length / 2.0, 0.0])))
    stem = bar("stem", np.array([0.0, low + length, 0.0]),
               np.array([0.0, low + length + STEM_SHARE * d.radius, 0.0]),
               STEM_WIDTH_SHARE * 2.0 * radius, STEM_WIDTH_SHARE * 2.0 * radius)
    follower = rigid(np.eye(3), np.column_stack((np.zeros((theta.size, 2)), height)))
    return Scene3D(theta, turning(-d.axis_angle(theta))[None], (roller, stem), follower,
                   box_extent([-d.radius, -d.radius, 0.0], [d.radius, d.radius, d.length]),
                   np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 1.0]]))


class Drum:
    """The drum cam (``cam.type: cylindrical``)."""

    drives_both_ways = False
    mounted = "drum"
    inspect_refusal = ("is a drum (cylindrical) cam: its groove is inspected from a 3-D scan or "
                       "CMM points (CSV of x, y, z, PLY or STL), not from a drawing")

    @staticmethod
    def check(design: Design) -> None:
        """The groove's tube no larger than camfab builds
        (:func:`camfab.geometry.tube_budget.check_tube`)."""
        from camfab.curves.sampling import SAMPLING_SHARE
        from camfab.geometry.drum import drum
        from camfab.geometry.drum_mesh import tube_facets
        from camfab.geometry.tube_budget import check_tube

        d, program = drum(design), design.program
        check_tube(lambda tolerance, most: tube_facets(d, program, SAMPLING_SHARE * tolerance,
                                                       most),
                   design.manufacturing.tolerance, "a drum's groove", len(program.segments))

    @staticmethod
    def analyse(design: Design, program: MotionProgram, units: MotionUnits,
                stats: list[SegmentStats], findings: list[Finding]) -> Analysis:
        """The groove's dense walls, the drum's numbers and checks (before *findings*)."""
        from camfab.analysis.drum_checks import drum_findings, drum_numbers
        from camfab.geometry.drum import drum, drum_dense

        dense = drum_dense(drum(design), program)
        drum_nums = drum_numbers(dense, len(program.segments))
        findings = [*drum_findings(design, dense, drum_nums), *findings]
        return Analysis(design, program, units, stats, findings, DrumResult(dense, drum_nums))

    scene = staticmethod(drum_scene)

    @staticmethod
    def part(analysis: Analysis) -> Part:
        return drum_part(analysis)

    @staticmethod
    def verify(analysis: Analysis, part: Part, files: PartFiles) -> tuple[Analysis,
                                                                          Verification]:
        return analysis, drum_verify(analysis, part, files)


    @staticmethod
    def size_problem(design: Design, follower: FollowerGeometry,
                     grid_pair: tuple[Grid, Grid]) -> SizeProblem:
        """The sizing of the drum's radius (:func:`camfab.kinds.drum_sizing.drum_problem`)."""
        from camfab.kinds.drum_sizing import drum_problem

        return drum_problem(design, grid_pair)


KIND = Drum()


def drum_part(analysis: Analysis) -> Part:
    """The drum's part: the drum along Z from 0 to its length, the bore through and the groove
    subtracted once as one closed tube (withheld when the groove folds over itself); the groove
    developed at the surface as a drawing and a view (see :func:`_development_drawing`),
    sampled within :data:`DEVELOPED_SHARE` of the tolerance."""
    from camfab.curves.sampling import SAMPLING_SHARE
    from camfab.export.part import Difference, Mesh, Part
    from camfab.geometry.arcfit import fit_arcs
    from camfab.geometry.drum_mesh import (
        development,
        groove_tube,
        tube_surfaces,
        velocity_steps,
    )
    from camfab.geometry.plate import ARC_FACTOR, Contours, fit_chain

    design, dense = analysis.design, analysis.drum
    assert dense is not None
    d, program = dense.drum, analysis.program
    tolerance = SAMPLING_SHARE * design.manufacturing.tolerance
    tube = groove_tube(d, program, tolerance)
    withheld: dict[str, str] = {}
    solid = None
    if _folded(analysis):
        withheld["stl"] = ("the groove folds over itself (see the groove check): there is no "
                           "solid a roller could run in")
    else:
        body = _body(d, tolerance)
        if velocity_steps(program):
            withheld["step"] = ("the groove has a corner at each velocity step (see the corner "
                                "check), and camfab's exact solids are of smooth grooves: the "
                                "STL holds the roller's positions there")
            cut = Mesh(tube.vertices, tube.faces)
        else:
            cut = Mesh(tube.vertices, tube.faces, *tube_surfaces(d, program, tube))
        solid = Difference(body, cut, cut_first=True)
    # the developed groove: the walls at the surface, closed across the seam, as arcs that
    # hold the chords between its points
    share = DEVELOPED_SHARE * design.manufacturing.tolerance
    dev = development(d, program, share)
    band = fit_chain(np.vstack((dev.lower, dev.upper[::-1])), share)
    centre = fit_arcs(dev.centre, ARC_FACTOR * share, closed=False, chords=True)
    drawing = _development_drawing(analysis, band, centre, (dev.width, dev.height))
    return Part({design.name: drawing}, {design.name: (Contours((band,)), None)}, solid,
                needs=("dxf", "stl"), withheld=withheld, made=tube)


def _body(d: DrumGeometry, tolerance: float) -> Solid:
    """The drum before its groove is cut: a cylinder (mm) along Z from 0 to its length, its
    circle's chords within *tolerance* (mm); with a bore, the ring between the bore and the
    surface revolved, both circles cut into the same number of chords at the same angles.

    (A cylinder less a bore cylinder has end faces that manifold3d triangulates afresh, and a
    corner of the surface's polygon that falls within a few micrometres of the line through a
    chord of the bore's makes a needle facet of the two, thinner than an STL can hold; the ring
    revolved has its end faces in quads between the circles, each as wide as its chord.)"""
    from camfab.curves.profile import Profile
    from camfab.export.part import Cylinder, Revolution
    from camfab.export.stl import circle_segments

    segments = circle_segments(d.radius, tolerance)
    if d.bore <= 0.0:
        return Cylinder(d.length, d.radius, segments)
    ring = np.array([[d.bore, 0.0], [d.radius, 0.0], [d.radius, d.length], [d.bore, d.length]])
    return Revolution(ring, segments, Profile.from_points(ring))


def _folded(analysis: Analysis) -> bool:
    return any(f.id == "groove" and not f.ok for f in analysis.findings)


def _development_drawing(analysis: Analysis, band: Profile, centre: Profile,
                         size: tuple[float, float]) -> Drawing:
    """The groove developed at the drum's surface: the groove between its walls as one closed
    contour on ``CUT`` (cut open at the seam), the roller axis's track on ``PITCH`` (an open
    chain), the developed surface's rectangle (*size*, mm) on ``MARK``, and a note."""
    from camfab.export.part import Drawing

    design = analysis.design
    scale = 1.0 / design.mm_per_unit
    drawing = Drawing(design.units)
    width, height = size[0] * scale, size[1] * scale
    corners = [(0.0, 0.0), (width, 0.0), (width, height), (0.0, height)]
    for a, b in zip(corners, corners[1:] + corners[:1], strict=True):
        drawing.line(a, b, "MARK")
    drawing.contour(centre, scale, "PITCH", closed=False)
    unit = design.units
    text = [f"{design.name}: drum cam, {design.cam.rotation}, groove developed at the surface "
            f"(radius {(design.cam.radius or 0.0) * scale:.6g} {unit}), seen from outside",
            f"groove of {len(band.vertices)} lines and arcs within "
            f"{design.manufacturing.tolerance * scale:.3g} {unit}"]
    text_height = max(height * 0.03, 1e-3)
    for row, line in enumerate(text, start=1):
        drawing.text(line, text_height, (0.0, -1.6 * row * text_height))
    drawing.contour(band, scale, "CUT")
    return drawing


def drum_verify(analysis: Analysis, part: Part, files: PartFiles) -> Verification:
    """The roller run through the groove of the STL read back, between its wall rows (or, when
    the groove folds, between the exact walls, to show how far the fold would throw it); the
    STL checked closed, outward and of the solid's volume; the groove developed in the DXF
    measured against the groove as computed (the tube's walls at the surface, sampled anew
    within :data:`~camfab.kinds.readback.REFERENCE_SHARE` of the tolerance), each way."""
    from camfab.arrays import edge_groups
    from camfab.export.dxf import read_cut_outline
    from camfab.geometry.disc_geometry import LiftCheck
    from camfab.geometry.drum_mesh import (
        corner_play,
        development,
        groove_lift,
        velocity_steps,
    )
    from camfab.kinds.readback import (
        REFERENCE_SHARE,
        against_cut,
        groove_mesh,
        outline_deviation,
    )
    from camfab.motion.program import cycle_angles

    design, dense = analysis.design, analysis.drum
    assert dense is not None
    d, program = dense.drum, analysis.program
    tolerance = design.manufacturing.tolerance
    folded = _folded(analysis)
    vertices, _, stl_check, edges = groove_mesh(part, files, tolerance, folded)
    source = ("the exact walls (the groove folds: no STL)" if stl_check is None else
              f"the roller run through the groove of {design.name}.stl read back (between its "
              "wall rows)")
    # the roller run between the wall rows' edges found, each met exactly
    theta = cycle_angles(DRUM_VERIFY_STEP)
    centre_z = d.start + program.evaluate(theta)[0]
    low, high = groove_lift(d, vertices, edges, theta, centre_z)
    found = np.isfinite(low) & np.isfinite(high)  # the roller meets both walls
    error = np.full(theta.size, np.inf)
    error[found] = 0.5 * (low[found] + high[found]) - centre_z[found]
    written = read_cut_outline(files.files["dxf"][f"{design.name}.dxf"], design.mm_per_unit)
    exact = development(d, program, REFERENCE_SHARE * tolerance)
    deviation = outline_deviation(written, np.vstack((exact.lower, exact.upper[::-1])), 0.0,
                                  tolerance)
    lift = LiftCheck(theta, error, error)
    if folded or not velocity_steps(program):
        return Verification(lift, source, len(written.vertices), deviation, stl_check,
                            exempt=folded)
    # a velocity step: the groove's corners leave the roller room (the corner check), so the
    # files are held to the groove as computed wherever its motion departs from the design,
    # and no further off the design than the exact groove's corners take it
    tube = part.made
    low, high = groove_lift(d, tube.vertices, edge_groups(tube.faces, len(tube.vertices))[0],
                            theta, centre_z)
    corner = max(play for _, play in corner_play(d, program)) / 2.0
    computed = np.clip(0.5 * (low + high) - centre_z, -corner, corner)
    return Verification(lift, source, len(written.vertices), deviation, stl_check, exempt=True,
                        cut_error=against_cut(lift, LiftCheck(theta, computed, computed),
                                              tolerance),
                        departs_because="the groove has a corner at each velocity step",
                        departs_check="corner", departs_cam="the groove",
                        departs_by="its corners leave it")
