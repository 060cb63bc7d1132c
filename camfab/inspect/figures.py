"""The inspection report's figures as inline SVG, drawn like the build report's
(:mod:`camfab.export.figures`, through :mod:`camfab.export.chart`), lengths in mm, angles in
degrees.
"""

from __future__ import annotations

import math

import numpy as np

from camfab.export.chart import Axes, Figure
from camfab.export.figures import (
    BAD,
    CUT,
    FOLLOWER,
    PITCH,
    REFERENCE,
    WARN,
    angle_axis,
    clip_radii,
    panel_stack,
)
from camfab.inspect.record import Inspection

#: Colour of the magnified deviation drawn along the outline.
MAGNIFIED = "#8e44ad"

#: Every how many grid angles (0.1° apart) the smooth curves are drawn: 0.5°, as in the build
#: report. The deviation is drawn at every angle: a bump on the part may be narrower.
_THIN = 5


def outline_drawing(ins: Inspection, title: str) -> str:
    """The outline as inspected (centred, turned into phase when aligned) at θ = 0 with the
    design's cam over it, the follower, and where the deviation exceeds the tolerance."""
    fig = Figure(9.0, 6.4, "outline", left=0.09, right=0.68, bottom=0.08)
    [ax] = fig.subplots()
    ax.set_aspect("equal")
    ring = _ring(ins.profile.points(0.01, split_lines=False))
    ax.fill(ring[:, 0], ring[:, 1], color="#f4d6d2", zorder=0)
    ax.plot(ring[:, 0], ring[:, 1], color=CUT, linewidth=1.2, label="outline inspected")
    if ins.reference is not None:
        design = _ring(ins.reference.profile.points(0.01, split_lines=False))
        ax.plot(design[:, 0], design[:, 1], color=PITCH, linewidth=0.8, linestyle="--",
                label=f"design ({ins.reference.name})")
    angle = np.linspace(0, 2 * math.pi, 361)
    rb = ins.base_radius
    ax.plot(rb * np.cos(angle), rb * np.sin(angle), color=REFERENCE, linewidth=0.7,
            linestyle=":", label=f"base circle {rb:.4g} mm")
    tolerance = ins.setup.tolerance
    if ins.deviation_mm is not None and tolerance is not None:
        over = np.abs(ins.deviation_mm) > tolerance
        if over.any():
            xy = ins.contact[over]
            ax.plot(xy[:, 0], xy[:, 1], ".", color=BAD, markersize=3,
                    label="contact where |deviation| > tolerance")
        _magnified(ax, ins)
        k = int(np.argmax(np.abs(ins.deviation_mm)))
        ax.plot([ins.contact[k, 0]], [ins.contact[k, 1]], "o", markerfacecolor="none",
                markeredgecolor="black", markersize=9,
                label=f"largest deviation (θ = {math.degrees(ins.theta[k]):.4g}°)")
    _draw_follower(ax, ins)
    ax.plot([0], [0], "+", color="black", markersize=10)
    ax.legend(fontsize=7, outside_right=True)
    ax.set_title(title, fontsize=9)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    return fig.svg()


def _magnified(ax: Axes, ins: Inspection) -> None:
    """The deviation drawn at the contact points, magnified radially by a round factor so its
    largest value shows as about a tenth of the cam's size."""
    assert ins.deviation_mm is not None
    largest = float(np.max(np.abs(ins.deviation_mm)))
    if largest <= 0.0:
        return
    wanted = 0.1 * float(np.max(ins.profile.radii())) / largest
    decade = 10.0 ** math.floor(math.log10(wanted))
    factor = max(f * decade for f in (1.0, 2.0, 5.0) if f * decade <= wanted)
    radial = ins.contact / np.hypot(ins.contact[:, 0], ins.contact[:, 1])[:, None]
    shown = _ring(ins.contact + (factor * ins.deviation_mm)[:, None] * radial)
    ax.plot(shown[:, 0], shown[:, 1], color=MAGNIFIED, linewidth=0.9,
            label=f"contact + deviation × {factor:g} (radial)")


def _ring(points: np.ndarray) -> np.ndarray:
    return np.vstack((points, points[:1]))


def _draw_follower(ax: Axes, ins: Inspection) -> None:
    """The follower at θ = 0, where the outline as drawn meets it."""
    fol = ins.setup.follower
    height = float(ins.position[0])
    length = 0.75 * ins.base_radius
    if fol.oscillating:
        p = fol.pivot_sign
        pivot = np.array([p * fol.pivot_distance, 0.0])
        trace = np.array([p * (fol.pivot_distance - fol.arm_length * math.cos(height)),
                          fol.arm_length * math.sin(height)])
        ax.plot([pivot[0], trace[0]], [pivot[1], trace[1]], color=FOLLOWER, linewidth=1.0)
        ax.plot([pivot[0]], [pivot[1]], "o", color=FOLLOWER, markersize=4)
    else:
        trace = np.array([fol.offset, height])
        if not fol.flat:
            ax.plot([trace[0], trace[0]], [trace[1], trace[1] + length], color=FOLLOWER,
                    linewidth=1.5)
    if fol.flat:
        if fol.oscillating:
            # the face line: face_offset from the pivot toward the cam, along the arm
            p = fol.pivot_sign
            along = np.array([-p * math.cos(height), math.sin(height)])
            toward = np.array([-p * math.sin(height), -math.cos(height)])
            foot = np.array([p * fol.pivot_distance, 0.0]) + fol.face_offset * toward
            ends = foot + np.outer([0.3 * fol.pivot_distance, 1.3 * fol.pivot_distance], along)
        else:
            ends = np.array([[fol.offset - length, height], [fol.offset + length, height]])
        ax.plot(ends[:, 0], ends[:, 1], color=FOLLOWER, linewidth=2.0, label="follower face")
    elif fol.radius > 0:
        angle = np.linspace(0, 2 * math.pi, 181)
        ax.plot(trace[0] + fol.radius * np.cos(angle), trace[1] + fol.radius * np.sin(angle),
                color=FOLLOWER, linewidth=1.5, label=f"follower (r = {fol.radius:.4g} mm)")
    ax.plot([trace[0]], [trace[1]], ".", color=FOLLOWER)


def diagrams(ins: Inspection) -> str:
    """Panel under panel on a shared cam-angle axis: the lift (and the design's), the deviation
    against the tolerance, velocity and acceleration (per radian of cam angle without a speed),
    the pressure angle against its limit and the pitch curve's radius of curvature."""
    with_design = ins.deviation_mm is not None
    fig, axes = panel_stack(6 if with_design else 5)
    degrees = np.degrees(ins.theta)
    thin = slice(None, None, _THIN)
    lift_unit = "deg" if ins.oscillating else "mm"
    scale = math.degrees(1.0) if ins.oscillating else 1.0
    ax = axes.pop(0)
    ax.plot(degrees[thin], ins.lift[thin] * scale, color=CUT, linewidth=1.0, label="measured")
    if ins.design_lift is not None:
        ax.plot(degrees[thin], ins.design_lift[thin] * scale, color=PITCH, linewidth=0.8,
                linestyle="--", label="design")
    ax.set_ylabel(f"lift\n({lift_unit})", fontsize=8)
    ax.legend(fontsize=7, loc="upper right")
    if with_design:
        _deviation_panel(axes.pop(0), ins, degrees)
    omega = ins.setup.omega
    for order, name in ((1, "velocity"), (2, "acceleration")):
        ax = axes.pop(0)
        values = ins.motion[order]
        if omega is not None:
            values = values * omega**order / (1.0 if ins.oscillating else 1000.0)
            unit = ("rad" if ins.oscillating else "m") + ("/s" if order == 1 else "/s²")
        else:
            unit = ("rad" if ins.oscillating else "mm") + ("/rad" if order == 1 else "/rad²")
        ax.plot(degrees[thin], values[thin], color=CUT, linewidth=1.0)
        ax.axhline(0.0, color=REFERENCE, linewidth=0.5)
        ax.set_ylabel(f"{name}\n({unit})", fontsize=8)
    ax = axes.pop(0)
    limit = math.degrees(ins.setup.pressure_angle_limit)
    ax.plot(degrees[thin], np.degrees(ins.pressure_angle[thin]), color=CUT, linewidth=1.0,
            label="pressure angle φ")
    for sign in (1, -1):
        ax.axhline(sign * limit, color=BAD, linewidth=0.8, linestyle="--")
    ax.set_ylabel("pressure angle\n(deg)", fontsize=8)
    ax.legend(fontsize=7, loc="upper right")
    ax = axes.pop(0)
    ax.plot(degrees[thin], clip_radii(ins.pitch_radius[thin]), color=CUT, linewidth=1.0,
            label="pitch curve ρ")
    if ins.setup.follower.radius > 0:
        ax.axhline(ins.setup.follower.radius, color=BAD, linewidth=0.8, linestyle="--",
                   label=f"follower radius {ins.setup.follower.radius:.4g} mm")
    ax.set_ylabel("radius of\ncurvature (mm)", fontsize=8)
    ax.legend(fontsize=7, loc="upper right")
    all_axes = list(fig.axes)
    all_axes[-1].set_xlabel("cam angle θ (deg)")
    angle_axis(*all_axes)
    return fig.svg()


def _deviation_panel(ax: Axes, ins: Inspection, degrees: np.ndarray) -> None:
    assert ins.deviation_mm is not None
    deviation = ins.deviation_mm
    ax.plot(degrees, deviation, color=CUT, linewidth=0.8, label="measured − design")
    ax.axhline(0.0, color=REFERENCE, linewidth=0.5)
    tolerance = ins.setup.tolerance
    if tolerance is not None:
        for sign in (1, -1):
            ax.axhline(sign * tolerance, color=BAD, linewidth=0.8, linestyle="--")
        over = np.abs(deviation) > tolerance
        if over.any():
            ax.fill_between(degrees, deviation, 0, where=over, color=WARN, alpha=0.5,
                            label="over the tolerance")
        span = max(float(np.max(np.abs(deviation))), tolerance) * 1.15
        ax.set_ylim(-span, span)
    ax.set_ylabel("deviation\n(mm)", fontsize=8)
    ax.legend(fontsize=7, loc="best")
