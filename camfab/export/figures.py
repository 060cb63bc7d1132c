"""The report's drawings and diagrams as inline SVG, drawn by :mod:`camfab.export.chart`.

Every figure is a function of the analysis returning SVG text (no XML header), ready to paste
into the HTML page. Lengths are millimetres and angles degrees.
"""

from __future__ import annotations

import math
import textwrap
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

#: Font size (pt) of the figures' legends and notes: 11 px and more on the page.
LEGEND_FONT = 8.5

#: Width (in) of the report's figures: a card of the page is at most 1100 px wide, 1060 px
#: inside its padding (11.04 in at 96 px to the inch), and a figure fills its card's width
#: (the page's CSS) at about its own size, so a point of it is a point on the screen and its
#: 8.5 pt text (:data:`LEGEND_FONT`, the tick labels) 11.3 px at 100 % zoom.
FIGURE_WIDTH = 11.0

#: Room (in) left of a figure's panels for the tick labels and the y label, and right of them
#: for the legends and notes beside them: the same at every width, so the panels take the rest.
LEFT_ROOM, RIGHT_ROOM = 1.0, 2.6


#: The most characters a line of a note beside a panel holds (in :data:`RIGHT_ROOM`, less the
#: 6° of the cam-angle axis it starts after, at :data:`LEGEND_FONT`).
NOTE_CHARS = 30


def side_margins(width: float = FIGURE_WIDTH) -> tuple[float, float]:
    """The *left* and *right* margins (fractions of a figure *width* in wide, as
    :class:`~camfab.export.chart.Figure` takes them) that leave :data:`LEFT_ROOM` and
    :data:`RIGHT_ROOM`."""
    return LEFT_ROOM / width, 1.0 - RIGHT_ROOM / width


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


def segment_marks(ax: Axes, analysis: Analysis, labels: bool) -> None:
    """Segment boundaries as vertical lines, with the laws written above the top plot where
    the segment is wide enough for its words (else its kind, else nothing)."""
    from camfab.export.chart import text_width

    per_degree = ax.box[2] / 360.0
    for seg in analysis.program.segments:
        ax.axvline(math.degrees(seg.start), color=REFERENCE, linewidth=0.6, linestyle=":")
        if labels:
            room = math.degrees(seg.span) * per_degree
            name = next((n for n in (seg.kind if seg.kind == "dwell" else
                                     f"{seg.kind}: {seg.law_name}", seg.kind)
                         if text_width(n, LEGEND_FONT) < 0.95 * room), None)
            if name is not None:
                ax.text(math.degrees(seg.start + seg.span / 2), 1.02, name, ha="center",
                        va="bottom", fontsize=LEGEND_FONT, y_in_axes=True)


def panel_stack(rows: int, name: str = "diagrams") -> tuple[Figure, list[Axes]]:
    """A figure of *rows* panels 1.45 in high, one under the other on a shared cam-angle axis,
    :data:`FIGURE_WIDTH` wide (*name* prefixes its SVG ids: one per figure of a page)."""
    height = 1.45 * rows + 0.6
    left, right = side_margins()
    fig = Figure(FIGURE_WIDTH, height, name, left=left, right=right, top=1 - 0.3 / height,
                 bottom=0.45 / height)
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
        segment_marks(ax, analysis, labels=ax is axes[0])
    axes[-1].set_xlabel("cam angle θ (deg)")
    angle_axis(*axes)
    add_cursor(fig, axes)
    return fig.svg()


def add_cursor(fig: Figure, axes: list[Axes]) -> None:
    """A vertical line through every panel at θ = 0, which the page's script moves to the
    animation's cam angle: it is at x0 + kx·θ (pt, θ in degrees)."""
    ox, _, kx, _ = axes[0].to_frame()
    top = axes[0].frame()[1]
    bottom = axes[-1].frame()[1] + axes[-1].frame()[3]
    fig.overlays.append(f'<path class="cursor" data-cursor="{ox:.3f} {kx:.5f}" '
                        f'd="M{ox:.2f} {top:.2f} L{ox:.2f} {bottom:.2f}" stroke="#c0392b" '
                        f'stroke-width="1" stroke-opacity="0.8" fill="none"/>')


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
        steps = [f for f in analysis.findings if f.id == "continuity" and not f.ok
                 and f.quantity == names[order - 1]] if order else []
        if steps:  # a step of the derivative below: this one is unbounded there; said
            # beside the panel, where no curve is, in lines as wide as the room there
            at = ", ".join(f"{a:.4g}°" for a, _ in steps[0].ranges_deg)
            words = f"∞ where the {names[order - 1]} steps (at {at}); drawn between"
            ax.text(366.0, 0.5, "\n".join(textwrap.wrap(words, NOTE_CHARS)), ha="left",
                    va="center", fontsize=LEGEND_FONT, color="#555555", y_in_axes=True)
        ax.set_ylabel(f"{names[order]}\n({unit})", fontsize=LEGEND_FONT)
        ax.axhline(0.0, color=REFERENCE, linewidth=0.5)


def _pressure_panels(analysis: Analysis, top: Axes, bottom: Axes) -> None:
    limit = math.degrees(analysis.design.pressure_angle_limit)
    top.set_ylabel("pressure angle\n(deg)", fontsize=LEGEND_FONT)
    bottom.set_ylabel("radius of\ncurvature (mm)", fontsize=LEGEND_FONT)  # (a kind may rename)
    analysis.result.pressure_panels(analysis, top, bottom)
    for sign in (1, -1):
        top.axhline(sign * limit, color=BAD, linewidth=0.8, linestyle="--")
    for ax in (top, bottom):
        ax.legend(fontsize=LEGEND_FONT, outside_right=True)


def median(values: np.ndarray) -> float:
    """The median of *values* (not empty, none NaN), as ``np.median`` gives it, without the
    import of ``numpy.ma`` that ``np.median`` makes (to look for masked arrays: 12 ms)."""
    ordered = np.sort(values, axis=None)
    mid = ordered.size // 2
    return float(ordered[mid] if ordered.size % 2 else (ordered[mid - 1] + ordered[mid]) / 2.0)


def clip_radii(radius: np.ndarray, ax: Axes | None = None) -> np.ndarray:
    """Radii for plotting: straight stretches (±∞) and the huge values next to them hidden,
    and said so on *ax* when given."""
    finite = np.abs(radius[np.isfinite(radius)])
    cap = 4.0 * median(finite) if finite.size else 1.0
    hidden = ~(np.abs(radius) <= cap)
    if ax is not None and hidden.any():  # said beside the panel, under its legend
        ax.text(366.0, 0.02, f"|ρ| above {cap:.4g} mm\n(nearly straight) not drawn",
                ha="left", va="bottom", fontsize=LEGEND_FONT, color="#555555",
                y_in_axes=True)
    return np.where(hidden, np.nan, radius)


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
    top.set_ylabel("contact\nforce (N)", fontsize=LEGEND_FONT)
    bottom.set_ylabel("torque (N·m)", fontsize=LEGEND_FONT)
    for ax in (top, bottom):
        ax.legend(fontsize=LEGEND_FONT, outside_right=True)


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
        ax.plot(xy[:, 0], xy[:, 1], ".", color=WARN, markersize=5,
                label="pressure angle over the limit")
    if geom.undercut:
        cut = geom.working.xy[geom.cut] if geom.cut.any() else dense.working.xy[geom.folds]
        ax.plot(cut[:, 0], cut[:, 1], ".", color=BAD, markersize=7, label="undercut")


#: The animation's steps are the motion table's rows, at least this far apart (rad).
FRAME_STEP = math.radians(1.0)


def frame_angles(table_step: float) -> np.ndarray:
    """The cam angles (rad) of the report's animation: every motion-table row (*table_step*
    apart), or every n-th where the table is finer than :data:`FRAME_STEP`."""
    every = max(1, math.ceil(FRAME_STEP / table_step - 1e-9))
    return cycle_angles(table_step)[::every]


def group_points(ax: Axes, name: str) -> np.ndarray:
    """(N, 2) points (data units) of the lines and fills of group *name* of *ax*."""
    parts = [np.column_stack((i.x, i.y)) for i in ax.items
             if i.group == name and i.kind in ("line", "fill")]
    points = np.vstack(parts) if parts else np.zeros((0, 2))
    return points[np.isfinite(points).all(axis=1)]


def turned(points: np.ndarray, centre: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """*points* turned about *centre* by each of *angles* (rad, counter-clockwise), stacked."""
    rel = points - centre
    c, s = np.cos(angles)[:, None], np.sin(angles)[:, None]
    x = c * rel[:, 0] - s * rel[:, 1]
    y = s * rel[:, 0] + c * rel[:, 1]
    return np.column_stack((x.ravel(), y.ravel())) + centre


def rotations(angles: np.ndarray, centre: tuple[float, float]) -> list[str]:
    """SVG transforms turning a group by *angles* (rad, counter-clockwise in the drawing)
    about *centre* (pt): SVG's y runs down, so its rotation is the opposite."""
    cx, cy = centre
    return [f"rotate({-math.degrees(a) + 0.0:.4f} {cx:.3f} {cy:.3f})" for a in angles]


def translations(dx: np.ndarray, dy: np.ndarray) -> list[str]:
    """SVG transforms moving a group by (dx, dy) pt."""
    return [f"translate({x + 0.0:.3f} {y + 0.0:.3f})" for x, y in zip(dx, dy, strict=True)]


def scale_bar(ax: Axes, span: float, unit: str, scale: float = 1.0,
              right: bool = False) -> None:
    """A bar of a round length (about a fifth of *span*, data units = mm) in the lower left
    (*right*: right) corner, labelled in the design's *unit* (*scale*: design units per mm)."""
    from camfab.export.chart import nice_ticks

    (x0, x1), (y0, y1) = ax.limits()
    target = 0.2 * span * scale
    steps = nice_ticks(0.0, target, 1)
    length = float(steps[-1]) if steps.size > 1 and steps[-1] > 0 else target
    mm = length / scale
    left, bottom = x0 + 0.04 * (x1 - x0), y0 + 0.05 * (y1 - y0)
    if right:
        left = x1 - 0.04 * (x1 - x0) - mm
    tick = 0.012 * (y1 - y0)
    ax.plot([left, left, left + mm, left + mm], [bottom + tick, bottom, bottom, bottom + tick],
            color="#000000", linewidth=1.5)
    ax.text(left + mm / 2.0, bottom + 2.0 * tick, f"{length:g} {unit}", ha="center",
            va="bottom", fontsize=LEGEND_FONT)



def bands(ax: Axes, theta: np.ndarray, mask: np.ndarray, label: str) -> None:
    """Coloured bands across *ax* over the cam angles (*theta*, rad) where *mask* holds."""
    from camfab.angles import ranges_deg

    for k, (a, b) in enumerate(ranges_deg(theta, mask)):
        pieces = [(a, b)] if a <= b else [(a, 360.0), (0.0, b)]
        for i, (start, end) in enumerate(pieces):
            ax.axvspan(start, max(end, start + 0.5), color=BAD, alpha=0.22,
                       label=label if k == 0 and i == 0 else None)
