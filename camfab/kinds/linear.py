"""The linear (translating, wedge) cam: a plate sliding along X drives the follower across it.
Its analysis is the plate's exact curves, numbers and checks over one stroke; its part is the
plate's drawing (the CUT outline: the working curve fitted with lines and arcs, the two
square ends and the base line; the pitch curve, the zero-lift lines, marks and notes) and the
plate extruded to its thickness; its report draws the plate at travel 0 with its follower.

Reading back: the DXF's CUT outline is read as a reader of the file would (the kerf taken back
off), the follower run over it along the whole stroke and its height compared with
base_height + s; the outline's distance from the exact working curve is measured; the STL is
read back and checked closed, outward and of the plate's volume.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from camfab.analysis.record import TABLE_COLUMNS, Analysis, CamResult, terse
from camfab.analysis.verification import Verification
from camfab.kinds.disc import no_checks
from camfab.kinds.readback import BEAM_DEPARTS, against_cut, beam_cut, read_part

if TYPE_CHECKING:
    from camfab.analysis.findings import Finding
    from camfab.analysis.kinematics import MotionUnits, SegmentStats
    from camfab.analysis.linear_checks import LinearNumbers
    from camfab.analysis.verification import StlCheck
    from camfab.arrays import Array
    from camfab.curves.profile import Profile
    from camfab.design import Design
    from camfab.export.part import Drawing, Part
    from camfab.export.serialise import PartFiles
    from camfab.geometry.linear import LinearGeometry
    from camfab.kinds.scene3d import Scene3D
    from camfab.motion.program import MotionProgram
    from camfab.speed.contact import Contact


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


def beam_path(geom: LinearGeometry, radius: float) -> Array:
    """The points of :func:`exact_working` moved *radius* (mm) out of the plate that lie on the
    path of a beam (or a cutter) of that radius running round it: in a hollow sharper than the
    beam the paths from either side cross, and the points beyond the crossing, nearer the plate
    than *radius* (by over a quarter of the tolerance, the chain's sampling share), are not."""
    moved = exact_working(geom, radius)
    if radius == 0.0:
        return moved
    import shapely

    near = shapely.distance(shapely.Polygon(geom.chain), shapely.points(moved))
    return moved[near >= radius - 0.25 * geom.tolerance]


def linear_part(analysis: Analysis) -> Part:
    """The linear cam's part: its drawing (see :func:`_drawing`), its CUT contour, and the plate
    extruded from z = 0 to the design's ``thickness`` (none without one)."""
    from camfab.export.part import Extrusion, Part
    from camfab.geometry.plate import Contours

    design, geom = analysis.design, analysis.linear
    assert geom is not None
    cut, pitch, toolpath = linear_contours(analysis)
    thickness = design.cam.thickness
    solid = (None if thickness is None else
             Extrusion((geom.outline_points(),), thickness, None, (geom.outline,)))
    return Part({design.name: _drawing(analysis, cut, pitch, toolpath)},
                {design.name: (Contours((cut,)), None)}, solid)


def _drawing(analysis: Analysis, cut: Profile, pitch: Profile,
             toolpath: Profile | None) -> Drawing:
    """*cut* on ``CUT`` (mm, kerf-compensated: the working curve, the two square ends and the
    base line), the open *pitch* chain on ``PITCH``, the *toolpath* (or None) on ``TOOLPATH``;
    ``PRIME``: the trace point's height at zero lift (y = base_height); ``BASE``: the
    profile's (y = base_height − roller radius, for a roller); ``MARK``: the base line y = 0
    and ticks at travel 0 (the taller) and at the end of the stroke; ``NOTE``."""
    from camfab.export.part import Drawing

    design, geom = analysis.design, analysis.linear
    assert geom is not None
    scale = 1.0 / design.mm_per_unit
    cam = geom.cam
    drawing = Drawing(design.units)
    left, right = -cam.overhang * scale, (cam.stroke + cam.overhang) * scale
    # references first, what is cut last: drawn on top where they coincide (the base line)
    drawing.contour(pitch, scale, "PITCH", closed=False)
    drawing.line((left, cam.base_height * scale), (right, cam.base_height * scale), "PRIME")
    if cam.radius > 0.0:
        low = (cam.base_height - cam.radius) * scale
        drawing.line((left, low), (right, low), "BASE")
    drawing.line((left, 0.0), (right, 0.0), "MARK")
    tick = 0.5 * (cam.base_height - cam.radius) * scale
    drawing.line((0.0, 0.0), (0.0, tick), "MARK")  # travel 0
    drawing.line((cam.stroke * scale, 0.0), (cam.stroke * scale, 0.5 * tick), "MARK")
    unit = design.units
    lines = [f"{design.name}: linear cam, stroke {cam.stroke * scale:.6g} {unit}, base height "
             f"{cam.base_height * scale:.6g} {unit}; moves toward -X, travel 0 at x = 0",
             f"outline of {len(cut.vertices)} lines and arcs within "
             f"{design.manufacturing.tolerance * scale:.3g} {unit}"]
    kerf = design.manufacturing.kerf
    if kerf > 0.0:
        lines.append(f"CUT offset for a kerf of {kerf * scale:.4g} {unit}")
    cutter = design.manufacturing.cutter_radius
    if toolpath is not None:
        drawing.contour(toolpath, scale, "TOOLPATH")
        lines.append(f"TOOLPATH: centre of a cutter of radius {cutter * scale:.4g} {unit}")
    height = max(0.008 * geom.plate_length * scale, 1e-3)
    below = -(max(cutter, kerf / 2.0) * scale + 1.5 * height)
    for row, line in enumerate(lines):
        drawing.text(line, height, (left, below - 1.6 * row * height))
    drawing.contour(cut, scale, "CUT")
    return drawing


def linear_verify(analysis: Analysis, part: Part, files: PartFiles) -> tuple[Analysis,
                                                                            Verification]:
    """The DXF's CUT outline read back (the kerf taken off) and the follower run over it along
    the whole stroke; the STL (when made) checked against the plate's exact volume: its area ×
    thickness, within the tolerance along the outline through the thickness."""
    from camfab.geometry.linear import lift_check

    design, geom = analysis.design, analysis.linear
    assert geom is not None
    stl_check: StlCheck | None = None
    if files.stl is not None and design.cam.thickness is not None:
        from camfab.export.stl import chain_length, check_stl

        thickness = design.cam.thickness
        allowance = (design.manufacturing.tolerance * chain_length(geom.outline_points())
                     * thickness)
        stl_check = check_stl(files.stl.data, geom.outline.area * thickness, allowance)
    kerf = design.manufacturing.kerf
    written, part_read, source = read_part(files.files["dxf"][f"{design.name}.dxf"],
                                           design.mm_per_unit, kerf, geom.tolerance,
                                           f"{design.name}.dxf")
    lift = lift_check(geom.cam, analysis.program, part_read)
    deviation = None
    if not geom.undercut:
        deviation = float(written.distance(beam_path(geom, kerf / 2.0)).max())
    tolerance = design.manufacturing.tolerance
    beam = beam_cut(design, geom, analysis.program, kerf)
    if beam is not None:
        return analysis, Verification(lift, source, len(written.vertices), deviation, stl_check,
                                      exempt=True, cut_error=against_cut(lift, beam, tolerance),
                                      **BEAM_DEPARTS)
    cut_error = against_cut(lift, geom.lift, tolerance) if geom.undercut else None
    return analysis, Verification(lift, source, len(written.vertices), deviation, stl_check,
                                  exempt=geom.undercut, cut_error=cut_error)


@dataclass(frozen=True)
class LinearResult(CamResult):
    """A linear cam's exact curves (mm, over one stroke) and key numbers."""

    linear: LinearGeometry
    numbers: LinearNumbers
    drawing_title = "The plate sliding under its follower"

    def motion_words(self, design: Design) -> str:
        return "moving toward −X"

    def report_geometry(self, analysis: Analysis) -> dict[str, Any]:
        from camfab.analysis.linear_checks import linear_report_geometry

        return linear_report_geometry(analysis.design, self.linear, self.numbers)

    def table_leading(self, theta: Array) -> list[tuple[str, Array]]:
        """The travel of the plate (a stroke is 360°)."""
        return [("cam_travel_mm", self.linear.cam.travel(theta))]

    def table_columns(self, theta: Array, motion: Array) -> list[tuple[str, Array]]:
        cam = self.linear.cam
        x = cam.travel(theta)
        return list(zip(TABLE_COLUMNS, (np.degrees(cam.pressure_angle(motion)),
                                        cam.pitch(x, motion).radius,
                                        cam.working(x, motion).radius), strict=True))

    def summary(self, analysis: Analysis) -> list[str]:
        linear, lin, rpm = self.linear, self.linear.cam, analysis.design.cam.speed_rpm
        pace = "" if rpm is None else f", traversing at {terse(lin.stroke * rpm / 60.0)} mm/s"
        return [f"plate: stroke {terse(lin.stroke)} mm{pace}, base height "
                f"{terse(lin.base_height)} mm, {terse(linear.plate_length)} mm long; pitch "
                f"curve's smallest convex radius {terse(self.numbers.pitch_min_convex.value)} mm; "
                f"outline of {len(linear.outline.vertices)} lines and arcs; the follower run over "
                f"it strays {linear.lift.max_mm:.2g} mm from the design"]

    def contact(self, analysis: Analysis) -> Contact:
        """The plate's edge under the follower: a roller's line over the plate's thickness, a
        knife's none."""
        from camfab.speed.contact import KNIFE_NOTE, Contact, ContactSide, contact_length

        design, dense = analysis.design, self.linear.dense
        if design.follower.type == "knife":
            return Contact(dense.theta, "none", note=KNIFE_NOTE)
        working = dense.working
        with np.errstate(divide="ignore"):
            curvature = 1.0 / working.radius
        side = ContactSide("the plate's edge", 1, curvature, 1.0 / np.cos(dense.pressure_angle),
                           working.speed, place=working.xy, frame="the plate's frame")
        length, note = contact_length(design)
        radius = design.follower.roller_radius or 0.0
        return Contact(dense.theta, "line", 1.0 / radius, length, (side,), radius, note=note)

    def pressure_panels(self, analysis: Analysis, top: Any, bottom: Any) -> None:
        _pressure_panels(self.linear, top, bottom)

    def drawing(self, analysis: Analysis) -> str:
        return _drawing_svg(analysis, self.linear)


def _drawing_svg(analysis: Analysis, geom: LinearGeometry) -> str:
    """The plate at travel 0 with its follower over x = 0, the pitch curve, the zero-lift lines,
    where the checks fail marked on the profile, and a scale bar; the plate (group ``cam``) and
    the follower (group ``follower``) carry the animation's frames: the plate slides toward −X
    by its travel, the follower rises and falls as the motion table says."""
    from camfab.export.chart import Figure
    from camfab.export.figures import (
        CUT,
        FIGURE_WIDTH,
        FOLLOWER,
        LEGEND_FONT,
        PITCH,
        REFERENCE,
        frame_angles,
        mark_failures,
        scale_bar,
        side_margins,
        translations,
    )

    cam = geom.cam
    design = analysis.design
    outline = geom.outline_points()
    width = geom.plate_length
    height = float(outline[:, 1].max()) + 2.5 * cam.radius + 0.25 * cam.base_height
    size = FIGURE_WIDTH
    left, right = side_margins()
    fig = Figure(size, max(3.0, 0.7 * size * (height + 0.3 * cam.base_height) / width * 1.15),
                 "drawing", left=left, right=right, bottom=0.2, top=0.88)
    [ax] = fig.subplots()
    ax.set_aspect("equal")
    with ax.group("cam"):
        ring = np.vstack((outline, outline[:1]))
        ax.fill(ring[:, 0], ring[:, 1], color="#f4d6d2", zorder=0)
        ax.plot(ring[:, 0], ring[:, 1], color=CUT, linewidth=1.2, label="plate outline")
        if cam.radius > 0.0:
            ax.plot(geom.pitch.xy[:, 0], geom.pitch.xy[:, 1], color=PITCH, linewidth=0.8,
                    linestyle="--", label="pitch curve")
        mark_failures(ax, analysis, geom)
    left, right = -cam.overhang, cam.stroke + cam.overhang
    ax.plot([left, right], [cam.base_height] * 2, color=REFERENCE, linewidth=0.7,
            linestyle="-.", label="trace point at zero lift")
    trace = cam.base_height + float(analysis.program.evaluate(np.zeros(1))[0, 0])
    stem = trace + cam.radius + 0.6 * cam.base_height
    with ax.group("follower"):
        if cam.radius > 0.0:
            angle = np.linspace(0.0, 2.0 * np.pi, 181)
            ax.plot(cam.radius * np.cos(angle), trace + cam.radius * np.sin(angle),
                    color=FOLLOWER, linewidth=1.5, label="follower")
        ax.plot([0.0, 0.0], [trace, stem], color=FOLLOWER, linewidth=1.5,
                label=None if cam.radius > 0.0 else "knife")
        ax.plot([0.0], [trace], ".", color=FOLLOWER)
    ax.arrow((0.4 * width - cam.overhang, -0.12 * cam.base_height),
             (0.2 * width - cam.overhang, -0.12 * cam.base_height), color=REFERENCE)
    ax.text(0.3 * width - cam.overhang, -0.2 * cam.base_height, "the plate moves toward −X",
            ha="center", va="top", fontsize=LEGEND_FONT, color="#555555")
    theta = frame_angles(design.table_step)
    s = analysis.program.evaluate(theta)[0]
    ax.include([0.0, 0.0], [stem + float(s.max() - s[0]), trace])
    ax.set_ylim(-0.45 * cam.base_height, max(height, stem + float(s.max() - s[0]) + 1.0))
    scale_bar(ax, width, design.units, 1.0 / design.mm_per_unit, right=True)
    _, _, kx, ky = ax.to_frame()
    travel = cam.stroke * theta / (2.0 * np.pi)
    ax.animate("cam", translations(-kx * travel, np.zeros(theta.size)))
    ax.animate("follower", translations(np.zeros(theta.size), -ky * (s - s[0])))
    ax.legend(fontsize=LEGEND_FONT, outside_right=True)
    # the travel at the frame's cam angle: a stroke is 360° of it
    ax.set_title(f"{design.name} at travel {{θ×{cam.stroke / 360.0:.12g}}} mm, θ = {{θ}}° "
                 f"(stroke {cam.stroke:.4g} mm)", fontsize=10)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    return fig.svg()


def _pressure_panels(geom: LinearGeometry, top: Any, bottom: Any) -> None:
    """The signed pressure angle, and the pitch and profile radii of curvature, over the cycle."""
    from camfab.export.figures import BAD, CUT, PITCH, clip_radii

    dense = geom.dense
    theta = np.degrees(dense.theta)[::10]
    top.plot(theta, np.degrees(dense.pressure_angle)[::10], color=PITCH, linewidth=1.0,
             label="pressure angle φ = atan(ds/dx)")
    bottom.plot(theta, clip_radii(dense.pitch.radius[::10]), color=PITCH, linewidth=1.0,
                label="pitch curve ρ")
    bottom.plot(theta, clip_radii(dense.working.radius[::10]), color=CUT, linewidth=1.0,
                label="profile ρ")
    if geom.cam.radius > 0.0:
        bottom.axhline(geom.cam.radius, color=BAD, linewidth=0.8, linestyle="--",
                       label=f"roller radius {geom.cam.radius:.4g} mm")


def linear_scene(analysis: Analysis, theta: Array) -> Scene3D:
    """The linear cam's scene: the plate (its STL in its own frame) sliding toward −X by its
    travel, the follower over x = 0 on the exact pitch point (:meth:`~camfab.geometry.linear.
    LinearCam.pitch`), a roller over the plate's thickness (or a knife's wedge) and its stem
    along +Y."""
    from camfab.kinds.scene3d import (
        KNIFE_HEIGHT_SHARE,
        KNIFE_WIDTH_SHARE,
        NO_THICKNESS_SHARE,
        STEM_LENGTH_SHARE,
        Scene3D,
        Shape,
        bar,
        box_extent,
        rigid,
    )

    design, geom = analysis.design, analysis.linear
    assert geom is not None
    cam = geom.cam
    travel = cam.travel(theta)
    pitch = cam.pitch(travel, analysis.program.evaluate(theta)).xy
    zeros = np.zeros(theta.size)
    slide = rigid(np.eye(3), np.column_stack((-travel, zeros, zeros)))
    follower = rigid(np.eye(3), np.column_stack((pitch[:, 0] - travel, pitch[:, 1], zeros)))
    thickness = design.cam.thickness or NO_THICKNESS_SHARE * cam.base_height
    length = design.follower.roller_length or thickness
    middle = thickness / 2.0
    size = cam.base_height
    if cam.radius > 0.0:
        tip = Shape("cylinder", "roller", (cam.radius, length),
                    rigid(np.eye(3), np.array([0.0, 0.0, middle])))
        start, width = cam.radius, cam.radius
    else:
        start, width = KNIFE_HEIGHT_SHARE * size, KNIFE_WIDTH_SHARE * size
        tip = Shape("wedge", "knife", (width, start, length),
                    rigid(np.eye(3), np.array([0.0, 0.0, middle])))
    stem = bar("stem", np.array([0.0, start, middle]),
               np.array([0.0, start + STEM_LENGTH_SHARE * size, middle]), width, length)
    outline = geom.outline_points()
    extent = box_extent([*outline.min(axis=0), 0.0], [*outline.max(axis=0), thickness])
    return Scene3D(theta, slide[None], (tip, stem), follower, extent,
                   np.array([[0.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]), slides=True)


class Linear:
    """The linear (translating, wedge) cam (``cam.type: linear``)."""

    drives_both_ways = False
    mounted = None
    check = staticmethod(no_checks)
    inspect_refusal = ("is a linear cam: its plate is inspected from a 3-D scan or CMM points "
                       "(CSV of x, y, z, PLY or STL), not from a drawing")

    @staticmethod
    def analyse(design: Design, program: MotionProgram, units: MotionUnits,
                stats: list[SegmentStats], findings: list[Finding]) -> Analysis:
        """The plate's exact curves, numbers and checks (before *findings*)."""
        from camfab.analysis.linear_checks import linear_findings, linear_numbers
        from camfab.geometry.linear import linear_geometry

        geom = linear_geometry(design)
        numbers = linear_numbers(geom, len(program.segments))
        return Analysis(design, program, units, stats,
                        [*linear_findings(design, geom, numbers), *findings],
                        LinearResult(geom, numbers))

    part = staticmethod(linear_part)
    verify = staticmethod(linear_verify)
    scene = staticmethod(linear_scene)


KIND = Linear()
