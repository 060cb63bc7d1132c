"""The report's drawings and diagrams as inline SVG, drawn by :mod:`camfab.export.chart`.

Every figure is a function of the analysis returning SVG text (no XML header), ready to paste
into the HTML page. Lengths are millimetres and angles degrees.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from camfab.export.chart import Axes, Figure
from camfab.motion.program import cycle_angles

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.geometry.disc_geometry import DiscGeometry
    from camfab.geometry.linear import LinearGeometry

#: Cam-angle step of the diagrams: 0.5° draws every feature a reader can see.
DIAGRAM_STEP = math.radians(0.5)

#: Colours: cut outline, pitch curve, references, violations, follower.
CUT, PITCH, REFERENCE, BAD, FOLLOWER, WARN = ("#c0392b", "#2c5aa0", "#999999", "#e67e22",
                                              "#2d7d46", "#d4ac0d")
#: A groove cam's pocket walls, and its wall-change marks.
POCKET, CHANGE = "#8e44ad", "#0e6e8c"


def thin(*arrays: np.ndarray) -> list[np.ndarray]:
    """Every n-th value of dense arrays (0.05° apart) so lines are drawn every 0.5°: finer than a
    reader can see, and ten times fewer points to write."""
    return [a[..., ::10] for a in arrays]


def angle_axis(*axes: Axes) -> None:
    """Cam angle from 0 to 360° with a tick every 60° on the bottom panel (the segment lines
    run through all), and at most four intervals on the values."""
    for ax in axes:
        ax.set_xlim(0, 360)
        ax.set_xticks(range(0, 361, 60) if ax is axes[-1] else [])
        ax.set_bins(y=4)


def _segment_marks(ax: Axes, analysis: Analysis, labels: bool) -> None:
    """Segment boundaries as vertical lines, with the laws written above the top plot."""
    for seg in analysis.program.segments:
        ax.axvline(math.degrees(seg.start), color=REFERENCE, linewidth=0.6, linestyle=":")
        if labels:
            name = seg.kind if seg.kind == "dwell" else f"{seg.kind}: {seg.law_name}"
            ax.text(math.degrees(seg.start + seg.span / 2), 1.02, name, ha="center",
                    va="bottom", fontsize=7, y_in_axes=True)


def panel_stack(rows: int) -> tuple[Figure, list[Axes]]:
    """The diagrams' figure: *rows* panels 1.45 in high, one under the other on a shared
    cam-angle axis, 9 in wide."""
    height = 1.45 * rows + 0.6
    fig = Figure(9.0, height, "diagrams", left=0.11, top=1 - 0.3 / height, bottom=0.45 / height)
    return fig, fig.subplots(rows, sharex=True)


def diagrams(analysis: Analysis) -> str:
    """One figure of the cycle, panel under panel on a shared cam-angle axis: s, v, a and j (per
    radian of cam angle without a speed), the pressure angle against its limit, the radii of
    curvature against the follower's, and with dynamics the contact force and camshaft torque.
    """
    rows = 8 if has_dynamics(analysis) else 6
    fig, axes = panel_stack(rows)
    _motion_panels(analysis, axes[:4])
    _pressure_panels(analysis, axes[4], axes[5])
    if rows == 8:
        _dynamics_panels(analysis, axes[6], axes[7])
    for ax in axes:
        _segment_marks(ax, analysis, labels=ax is axes[0])
    axes[-1].set_xlabel("cam angle θ (deg)")
    angle_axis(*axes)
    return fig.svg()


def has_dynamics(analysis: Analysis) -> bool:
    dyn = analysis.dynamics
    return dyn is not None and dyn.force_N is not None and dyn.torque_N_m is not None


def _motion_panels(analysis: Analysis, axes: list[Axes]) -> None:
    theta = cycle_angles(DIAGRAM_STEP)
    units = analysis.units
    omega = analysis.design.cam.omega
    motion = analysis.program.evaluate(theta)
    names = ("displacement", "velocity", "acceleration", "jerk")
    degrees = np.degrees(theta)
    for order, ax in enumerate(axes):
        values = motion[order]
        if order == 0:
            values = np.degrees(values) if units.oscillating else values
            unit = "deg" if units.oscillating else "mm"
        elif omega is not None:
            values = units.to_si(order, values, omega)
            unit = units.unit(order, True)
        else:
            unit = units.unit(order, False)
        ax.plot(degrees, values, color=PITCH, linewidth=1.0)
        ax.set_ylabel(f"{names[order]}\n({unit})", fontsize=8)
        ax.axhline(0.0, color=REFERENCE, linewidth=0.5)


def _pressure_panels(analysis: Analysis, top: Axes, bottom: Axes) -> None:
    limit = math.degrees(analysis.design.pressure_angle_limit)
    analysis.result.pressure_panels(analysis, top, bottom)
    for sign in (1, -1):
        top.axhline(sign * limit, color=BAD, linewidth=0.8, linestyle="--")
    top.set_ylabel("pressure angle\n(deg)", fontsize=8)
    bottom.set_ylabel("radius of\ncurvature (mm)", fontsize=8)
    for ax in (top, bottom):
        ax.legend(fontsize=7, loc="upper right")


def median(values: np.ndarray) -> float:
    """The median of *values* (not empty, none NaN), as ``np.median`` gives it, without the
    import of ``numpy.ma`` that ``np.median`` makes (to look for masked arrays: 12 ms)."""
    ordered = np.sort(values, axis=None)
    mid = ordered.size // 2
    return float(ordered[mid] if ordered.size % 2 else (ordered[mid - 1] + ordered[mid]) / 2.0)


def clip_radii(radius: np.ndarray) -> np.ndarray:
    """Radii for plotting: straight stretches (±∞) and the huge values next to them hidden."""
    finite = np.abs(radius[np.isfinite(radius)])
    cap = 4.0 * median(finite) if finite.size else 1.0
    return np.where(np.abs(radius) <= cap, radius, np.nan)


def _dynamics_panels(analysis: Analysis, top: Axes, bottom: Axes) -> None:
    dyn = analysis.dynamics
    assert dyn is not None and dyn.force_N is not None and dyn.torque_N_m is not None
    theta, force, static, torque = thin(np.degrees(dyn.theta), dyn.force_N, dyn.static_N,
                                         dyn.torque_N_m)
    top.plot(theta, force, color=PITCH, linewidth=1.0, label="contact force")
    top.plot(theta, static, color=REFERENCE, linewidth=0.8, label="spring and loads")
    top.axhline(0.0, color=BAD, linewidth=0.8, linestyle="--")
    if (force < 0).any():
        top.fill_between(theta, force, 0, where=force < 0, color=BAD, alpha=0.4,
                         label="contact lost")
    bottom.plot(theta, torque, color=FOLLOWER, linewidth=1.0, label="camshaft torque")
    top.set_ylabel("contact\nforce (N)", fontsize=8)
    bottom.set_ylabel("torque (N·m)", fontsize=8)
    for ax in (top, bottom):
        ax.legend(fontsize=7, loc="upper right")


def cam_drawing(analysis: Analysis) -> str | None:
    """The cam at θ = 0 with its follower, a drum's groove developed at its surface, or a
    linear cam's plate at travel 0: the kind's drawing."""
    return analysis.result.drawing(analysis)


def mark_failures(ax: Axes, analysis: Analysis, geom: DiscGeometry | LinearGeometry) -> None:
    """Dots on the profile of *geom* (a disc or linear cam's geometry) where the pressure angle
    is over the limit and where the envelope is undercut."""
    dense = geom.dense
    steep = np.abs(dense.pressure_angle) > analysis.design.pressure_angle_limit
    if steep.any():
        xy = dense.working.xy[steep]
        ax.plot(xy[:, 0], xy[:, 1], ".", color=WARN, markersize=2,
                label="pressure angle over the limit")
    if geom.undercut:
        cut = geom.working.xy[geom.cut] if geom.cut.any() else dense.working.xy[geom.folds]
        ax.plot(cut[:, 0], cut[:, 1], ".", color=BAD, markersize=2, label="undercut")
