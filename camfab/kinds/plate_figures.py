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
    FOLLOWER,
    PITCH,
    REFERENCE,
    clip_radii,
    mark_failures,
    thin,
)

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.geometry.disc_geometry import DiscGeometry
    from camfab.kinds.disc import PlateResult


def plate_pressure_panels(geom: DiscGeometry, top: Axes, bottom: Axes) -> None:
    """The pressure angle on *top*; the pitch curve's and the profile's radii of curvature
    against the follower's radius on *bottom*."""
    theta, phi, pitch, profile = thin(np.degrees(geom.dense.theta),
                                      np.degrees(geom.dense.pressure_angle),
                                      geom.dense.pitch.radius, geom.dense.working.radius)
    top.plot(theta, phi, color=PITCH, linewidth=1.0, label="pressure angle φ")
    bottom.plot(theta, clip_radii(pitch), color=PITCH, linewidth=1.0, label="pitch curve ρ")
    bottom.plot(theta, clip_radii(profile), color=CUT, linewidth=1.0, label="profile ρ")
    radius = geom.cam.follower.radius
    if radius > 0:
        bottom.axhline(radius, color=BAD, linewidth=0.8, linestyle="--",
                       label=f"follower radius {radius:.4g} mm")


def plate_drawing_svg(result: PlateResult, analysis: Analysis) -> str:
    """The plate at θ = 0: its outline (or a groove's walls), the pitch curve, the base and
    prime circles, where the checks fail, the follower and what holds it on its other side."""
    geom = result.geometry
    fol = geom.cam.follower
    fig = Figure(6.4, 6.4, "drawing", left=0.12, bottom=0.08)
    [ax] = fig.subplots()
    ax.set_aspect("equal")
    result.draw_plate(ax, analysis)
    pitch = np.vstack((geom.pitch.xy, geom.pitch.xy[:1]))
    if fol.radius > 0:
        ax.plot(pitch[:, 0], pitch[:, 1], color=PITCH, linewidth=0.8, linestyle="--",
                label="pitch curve")
    angle = np.linspace(0, 2 * math.pi, 361)
    for radius, style, name in ((geom.cam.base_radius, ":", "base circle"),
                                (geom.cam.prime_radius, "-.", "prime circle")):
        ax.plot(radius * np.cos(angle), radius * np.sin(angle), color=REFERENCE,
                linewidth=0.7, linestyle=style, label=name)
    # where the checks fail, on the profile
    mark_failures(ax, analysis, geom)
    draw_follower(ax, analysis, geom)
    result.draw_other_side(ax, analysis)
    ax.plot([0], [0], "+", color="black", markersize=10)
    ax.legend(fontsize=7, loc="lower left")
    ax.set_title(f"{analysis.design.name} at θ = 0 ({analysis.design.cam.rotation})",
                 fontsize=9)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    return fig.svg()


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
