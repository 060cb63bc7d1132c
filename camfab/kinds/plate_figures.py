"""The report's figures of a plate cam (disc, shaped, groove, conjugate, constant-breadth): the
cam at θ = 0 with its follower, and its pressure angle and radii of curvature over the cycle
(inline SVG through :mod:`camfab.export.chart`). Lengths are millimetres, angles degrees."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from camfab.export.chart import Axes, Figure
from camfab.export.figures import (
    BAD,
    CUT,
    FIGURE_WIDTH,
    FOLLOWER,
    LEGEND_FONT,
    PITCH,
    REFERENCE,
    bands,
    clip_radii,
    frame_angles,
    group_points,
    mark_failures,
    rotations,
    scale_bar,
    side_margins,
    thin,
    translations,
    turned,
)

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.geometry.disc_geometry import DiscGeometry
    from camfab.kinds.disc import PlateResult


def plate_pressure_panels(geom: DiscGeometry, top: Axes, bottom: Axes, limit: float) -> None:
    """The pressure angle on *top* (bands where it is over the *limit*, rad); the pitch
    curve's and the profile's radii of curvature against the follower's radius on *bottom*
    (bands where the envelope is undercut). A flat face's pitch point follows no curve of the
    cam: its radius is not drawn."""
    theta, phi, pitch, profile = thin(np.degrees(geom.dense.theta),
                                      np.degrees(geom.dense.pressure_angle),
                                      geom.dense.pitch.radius, geom.dense.working.radius)
    fol = geom.cam.follower
    if fol.flat and not fol.oscillating:
        top.text(180.0, 0.5, "a flat face square to its motion: no pressure angle (φ = 0)",
                 fontsize=LEGEND_FONT, color="#555555", y_in_axes=True)
        top.set_ylim(-45.0, 45.0)
    else:
        top.plot(theta, phi, color=PITCH, linewidth=1.0, label="pressure angle φ")
    if not fol.flat:  # a flat face's pitch point is no curve its contact follows
        bottom.plot(theta, clip_radii(pitch), color=PITCH, linewidth=1.0, label="pitch curve ρ")
    bottom.plot(theta, clip_radii(profile, bottom), color=CUT, linewidth=1.0,
                label="profile ρ")
    dense = geom.dense
    bands(bottom, dense.theta, geom.folds, "undercut")
    steep = np.abs(dense.pressure_angle) > limit
    if fol.oscillating or not fol.flat:
        bands(top, dense.theta, steep, "over the limit")
    radius = geom.cam.follower.radius
    if radius > 0:
        bottom.axhline(radius, color=BAD, linewidth=0.8, linestyle="--",
                       label=f"follower radius {radius:.4g} mm")


def plate_drawing_svg(result: PlateResult, analysis: Analysis) -> str:
    """The plate at θ = 0: its outline (or a groove's walls) with the bore and keyway, the
    pitch curve, the base and prime circles, where the checks fail, the follower and what holds
    it on its other side, a scale bar; the plate (group ``cam``) and the follower (group
    ``follower``) carry the animation's frames: the plate turning about its centre, the
    follower moving as the motion table says."""
    geom = result.geometry
    cam = geom.cam
    fol = cam.follower
    design = analysis.design
    left, right = side_margins()
    fig = Figure(FIGURE_WIDTH, 7.6, "drawing", left=left, right=right, bottom=0.07, top=0.95)
    [ax] = fig.subplots()
    ax.set_aspect("equal")
    with ax.group("cam"):
        result.draw_plate(ax, analysis)
        draw_holes(ax, analysis)
        pitch = np.vstack((geom.pitch.xy, geom.pitch.xy[:1]))
        if fol.radius > 0:
            ax.plot(pitch[:, 0], pitch[:, 1], color=PITCH, linewidth=0.8, linestyle="--",
                    label="pitch curve")
        # where the checks fail, on the profile
        mark_failures(ax, analysis, geom)
        ax.plot([0.0, 0.0], [0.0, 0.35 * cam.base_radius], color="#555555", linewidth=0.8,
                label="θ = 0 mark")
    angle = np.linspace(0, 2 * math.pi, 361)
    for radius, style, name in ((cam.base_radius, ":", "base circle"),
                                (cam.prime_radius, "-.", "prime circle")):
        ax.plot(radius * np.cos(angle), radius * np.sin(angle), color=REFERENCE,
                linewidth=0.7, linestyle=style, label=name)
    with ax.group("follower"):
        draw_follower(ax, analysis, geom)
        result.draw_other_side(ax, analysis)
    ax.plot([0], [0], "+", color="black", markersize=10)
    # the animation: the plate turns about the centre, the follower moves with the motion
    theta = frame_angles(design.table_step)
    trace = cam.trace(analysis.program.evaluate(theta))[0]
    plate = group_points(ax, "cam")
    reach = float(np.max(np.hypot(plate[:, 0], plate[:, 1]))) if plate.size else 1.0
    ax.include(reach * np.cos(angle), reach * np.sin(angle))
    moving = group_points(ax, "follower")
    pivot = cam.pivot
    # the follower's move from θ = 0: the arm's turn (rad), or the rise (mm)
    move = _arm_angles(trace, pivot) if fol.oscillating else trace[:, 1] - trace[0, 1]
    ends = move[[int(np.argmin(move)), int(np.argmax(move))]]
    if fol.oscillating:
        ax.include(*turned(moving, pivot, ends).T)
    else:
        for shift in ends:
            ax.include(moving[:, 0], moving[:, 1] + shift)
    scale_bar(ax, 2.0 * reach, design.units, 1.0 / design.mm_per_unit)
    ox, oy, kx, ky = ax.to_frame()
    ax.animate("cam", rotations(cam.sigma * theta, (ox, oy)))
    ax.animate("follower", rotations(move, (ox + kx * pivot[0], oy - ky * pivot[1]))
               if fol.oscillating else translations(np.zeros(theta.size), -ky * move))
    ax.legend(fontsize=LEGEND_FONT, outside_right=True)
    ax.set_title(f"{design.name} at θ = {{θ}}° ({design.cam.rotation})", fontsize=10)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    return fig.svg()


def _arm_angles(trace: np.ndarray, pivot: np.ndarray) -> np.ndarray:
    """How far the arm from *pivot* to each *trace* point has turned from the first (rad,
    counter-clockwise)."""
    arm = np.arctan2(trace[:, 1] - pivot[1], trace[:, 0] - pivot[0])
    return np.unwrap(arm - arm[0])


def draw_holes(ax: Axes, analysis: Analysis) -> None:
    """The bore and keyway, as cut."""
    from camfab.export.stl import hole_points
    from camfab.geometry.plate import holes

    tolerance = analysis.design.manufacturing.tolerance
    for k, chain in enumerate(hole_points(holes(analysis.design), max(tolerance, 0.01))):
        ring = np.vstack((chain, chain[:1]))
        ax.fill(ring[:, 0], ring[:, 1], color="#ffffff", zorder=0.5)
        ax.plot(ring[:, 0], ring[:, 1], color=CUT, linewidth=1.0,
                label="bore and keyway" if k == 0 else None)


def draw_outline(ax: Axes, geom: DiscGeometry) -> None:
    """The cam's outline, filled."""
    outline = geom.outline_points()
    ring = np.vstack((outline, outline[:1]))
    ax.fill(ring[:, 0], ring[:, 1], color="#f4d6d2", zorder=0)
    ax.plot(ring[:, 0], ring[:, 1], color=CUT, linewidth=1.2, label="cam profile")


def draw_follower(ax: Axes, analysis: Analysis, geom: DiscGeometry) -> None:
    """The follower at θ = 0 (the cam frame and the fixed frame coincide there)."""
    cam = geom.cam
    fol = cam.follower
    m = analysis.program.evaluate(np.zeros(1))
    trace = cam.trace(m)[0][0]
    angle = np.linspace(0, 2 * math.pi, 181)
    if fol.flat:
        lines = cam.face_lines(np.zeros(1), m)
        normal = lines.normal[0]
        foot = normal * lines.h[0]
        along = np.array([-normal[1], normal[0]])
        half = 0.6 * geom.cam.base_radius
        ends = np.array([foot - half * along, foot + half * along])
        ax.plot(ends[:, 0], ends[:, 1], color=FOLLOWER, linewidth=2.0, label="follower face")
    elif fol.radius > 0:
        ax.plot(trace[0] + fol.radius * np.cos(angle), trace[1] + fol.radius * np.sin(angle),
                color=FOLLOWER, linewidth=1.5, label="follower")
    if fol.oscillating:
        pivot = cam.pivot
        ax.plot([pivot[0], trace[0]], [pivot[1], trace[1]], color=FOLLOWER, linewidth=1.0)
        ax.plot([pivot[0]], [pivot[1]], "o", color=FOLLOWER, markersize=4)
    elif not fol.flat:
        ax.plot([trace[0], trace[0]], [trace[1], trace[1] + 1.5 * geom.cam.base_radius * 0.5],
                color=FOLLOWER, linewidth=1.5)
    ax.plot([trace[0]], [trace[1]], ".", color=FOLLOWER)
