"""The report's figures of a linear cam: the plate at travel 0 with its follower, and the pressure
angle and radii of curvature over the cycle (inline SVG through :mod:`camfab.export.chart`).

Lengths are millimetres; the cycle angle is degrees (360° is one stroke).
"""

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
)

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis


def linear_drawing(analysis: Analysis) -> str:
    """The plate at travel 0 with its follower over x = 0, the pitch curve, the zero-lift lines,
    and where the checks fail marked on the profile."""
    geom = analysis.linear
    assert geom is not None
    cam = geom.cam
    outline = geom.outline_points()
    width = geom.plate_length
    height = float(outline[:, 1].max()) + 2.5 * cam.radius + 0.25 * cam.base_height
    size = min(10.0, max(6.0, 0.04 * width))
    fig = Figure(size, max(2.6, size * (height + 0.3 * cam.base_height) / width * 1.15),
                 "drawing", left=0.07, right=0.98, bottom=0.2, top=0.88)
    [ax] = fig.subplots()
    ax.set_aspect("equal")
    ring = np.vstack((outline, outline[:1]))
    ax.fill(ring[:, 0], ring[:, 1], color="#f4d6d2", zorder=0)
    ax.plot(ring[:, 0], ring[:, 1], color=CUT, linewidth=1.2, label="plate outline")
    if cam.radius > 0.0:
        ax.plot(geom.pitch.xy[:, 0], geom.pitch.xy[:, 1], color=PITCH, linewidth=0.8,
                linestyle="--", label="pitch curve")
    left, right = -cam.overhang, cam.stroke + cam.overhang
    ax.plot([left, right], [cam.base_height] * 2, color=REFERENCE, linewidth=0.7,
            linestyle="-.", label="trace point at zero lift")
    mark_failures(ax, analysis, geom)
    trace = cam.base_height + float(analysis.program.evaluate(np.zeros(1))[0, 0])
    if cam.radius > 0.0:
        angle = np.linspace(0.0, 2.0 * math.pi, 181)
        ax.plot(cam.radius * np.cos(angle), trace + cam.radius * np.sin(angle), color=FOLLOWER,
                linewidth=1.5, label="follower at travel 0")
    stem = trace + cam.radius + 0.6 * cam.base_height
    ax.plot([0.0, 0.0], [trace, stem], color=FOLLOWER, linewidth=1.5,
            label=None if cam.radius > 0.0 else "knife at travel 0")
    ax.plot([0.0], [trace], ".", color=FOLLOWER)
    ax.arrow((0.4 * width - cam.overhang, -0.12 * cam.base_height),
             (0.2 * width - cam.overhang, -0.12 * cam.base_height), color=REFERENCE)
    ax.text(0.3 * width - cam.overhang, -0.2 * cam.base_height, "the plate moves toward −X",
            ha="center", va="top", fontsize=7, color="#555555")
    ax.set_ylim(-0.45 * cam.base_height, height)
    ax.legend(fontsize=7, loc="upper right", ncol=2)
    ax.set_title(f"{analysis.design.name} at travel 0 (stroke {cam.stroke:.4g} mm)", fontsize=9)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    return fig.svg()


def linear_pressure_panels(analysis: Analysis, top: Axes, bottom: Axes) -> None:
    """The signed pressure angle, and the pitch and profile radii of curvature, over the cycle."""
    geom = analysis.linear
    assert geom is not None
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
