"""The setup sheet's pictures, as inline SVG through :mod:`camfab.export.chart`: where the work
zero is on the part, and the toolpath.

The toolpath is drawn as the program writer gives it (:class:`~camfab.analysis.setup_sheet.
Toolpath`): the tool centre's cutting moves solid, its rapid moves dashed and faint, on the
writer's axes; a plan view (both axes lengths in one unit) at equal scale, an unrolled path or a
swing against the cam angle at the scales that fill the panel. The work zero's picture is a small
sketch to scale of the part as it sits on the machine, chosen by the program's axes: a plate from
above and from the front (``XYZ``), a drum from the side (``XZA``), a globoid on its table-table
machine (``XZAB``, ``XYZAB``), a cam on a grinder's C axis beside its wheel (``XC``).

Lengths are millimetres, angles degrees.
"""

from __future__ import annotations

import math
import re
import textwrap
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from camfab.export.chart import Axes, Figure
from camfab.export.figures import (
    CUT,
    FIGURE_WIDTH,
    LEFT_ROOM,
    LEGEND_FONT,
    REFERENCE,
    RIGHT_ROOM,
    side_margins,
)

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.analysis.setup_sheet import Setup
    from camfab.arrays import Array

#: The points of a toolpath are thinned to one per cell of this size (pt) on the figure: finer
#: than a screen shows, and a long program's path a few thousand points on the page, not
#: hundreds of thousands.
PATH_CELL_PT = 0.3

#: Height (in) of the toolpath's panel when its axes are at different scales, and the least and
#: most when at one scale (a plan view takes the height its shape needs within these).
PANEL_HEIGHT, PLAN_HEIGHTS = 3.0, (1.6, 6.0)

#: Room (in) below the toolpath's panel for the tick labels and the axis label, and above it.
BELOW, ABOVE = 0.62, 0.2

#: The sketch of the work zero: its size (in).
SKETCH_SIZE = (5.0, 2.5)

#: The most characters of a line of the toolpath's y label (beside a panel 3 in high).
YLABEL_CHARS = 30

#: Colours of the sketches: the part, its edges, the axes and the work zero.
PART, EDGE, AXIS_INK = "#e9e9e9", "#555555", "#000000"

#: A length unit in brackets at the end of an axis label: "X (mm)", "Y (in)".
_LENGTH_UNIT = re.compile(r"\((mm|in)\)\s*$")


def toolpath_figure(setup: Setup, name: str) -> str | None:
    """The program's toolpath (cutting moves solid, rapid moves dashed) on its axes, the first
    cut marked and, in a plan view, the work zero; None without a toolpath to draw. *name*
    prefixes the SVG's ids (one per figure of a page)."""
    path = setup.toolpath
    if path is None:
        return None
    cutting, rapid = _points(path.cutting), _points(path.rapid)
    drawn = np.vstack((cutting, rapid))
    drawn = drawn[np.isfinite(drawn).all(axis=1)]
    if not drawn.size:
        return None
    plan = same_length_unit(path.x_label, path.y_label)
    span = np.maximum(np.ptp(drawn, axis=0), 1e-9)
    width = FIGURE_WIDTH - LEFT_ROOM - RIGHT_ROOM
    height = (float(np.clip(width * span[1] / span[0], *PLAN_HEIGHTS)) if plan
              else PANEL_HEIGHT)
    total = height + BELOW + ABOVE
    left, right = side_margins()
    fig = Figure(FIGURE_WIDTH, total, name, left=left, right=right, top=1.0 - ABOVE / total,
                 bottom=BELOW / total)
    [ax] = fig.subplots()
    if plan:
        ax.set_aspect("equal")
        scale = min(width / span[0], height / span[1]) * 72.0
        cell = np.array([PATH_CELL_PT / scale] * 2)
    else:
        cell = PATH_CELL_PT / (np.array([width, height]) * 72.0 / span)
    if rapid.size:
        r = thinned(rapid, cell)
        ax.plot(r[:, 0], r[:, 1], color=REFERENCE, linewidth=0.7, linestyle="--",
                label="rapid moves")
    if cutting.size:
        c = thinned(cutting, cell)
        ax.plot(c[:, 0], c[:, 1], color=CUT, linewidth=0.9, label="cutting moves")
        first = cutting[np.isfinite(cutting).all(axis=1)]
        if first.size:
            ax.plot(first[:1, 0], first[:1, 1], "o", color=CUT, markersize=5,
                    markerfacecolor="#ffffff", label="first cut")
    if plan:
        ax.plot([0.0], [0.0], "+", color=AXIS_INK, markersize=10, label="work zero")
    ax.set_xlabel(path.x_label, fontsize=LEGEND_FONT)
    ax.set_ylabel("\n".join(textwrap.wrap(path.y_label, YLABEL_CHARS)), fontsize=LEGEND_FONT)
    ax.legend(fontsize=LEGEND_FONT, outside_right=True)
    return fig.svg()


def same_length_unit(x_label: str, y_label: str) -> bool:
    """Whether both axis labels end in the same length unit ("X (mm)", "Y (mm)"): a plan view,
    drawn at one scale."""
    x, y = _LENGTH_UNIT.search(x_label), _LENGTH_UNIT.search(y_label)
    return x is not None and y is not None and x.group(1) == y.group(1)


def _points(points: Any) -> Array:
    """*points* (N, 2) as a float array; none (or not rows of points): (0, 2)."""
    out = np.asarray(points, dtype=float)
    return out[:, :2] if out.ndim == 2 and out.shape[1] >= 2 else np.zeros((0, 2))


def thinned(points: Array, cell: Array) -> Array:
    """*points* (N, 2; rows of NaN split pieces) with every point dropped that falls in the
    same cell (*cell*: its size across and up, data units) as the point before it, but for each
    piece's ends: the path as drawn moves by less than a cell."""
    good = np.isfinite(points).all(axis=1)
    cells = np.floor(np.where(good[:, None], points, 0.0) / cell)
    keep = np.ones(len(points), bool)
    keep[1:] = (cells[1:] != cells[:-1]).any(axis=1) | ~good[1:] | ~good[:-1]
    keep[:-1] |= ~good[1:]  # a piece's last point
    keep[-1:] = True
    return points[keep]


# --- the work zero ------------------------------------------------------------------------------

def work_zero_sketch(setup: Setup, analysis: Analysis, geometry: dict[str, Any],
                     name: str) -> str | None:
    """A small sketch to scale of the part on the machine with the work zero and the axes, by
    the program's axes; None for axes it does not know. *geometry* is the JSON report's
    ``geometry`` (mm)."""
    axes = setup.axes.upper()
    draw: Callable[[Figure, Setup, Analysis, dict[str, Any]], bool]
    if "B" in axes:
        draw = _globoid
    elif "A" in axes:
        draw = _drum
    elif "C" in axes and "Y" not in axes:
        draw = _grinder
    elif {"X", "Y", "Z"} <= set(axes):
        draw = _plate
    else:
        return None
    fig = Figure(*SKETCH_SIZE, name, left=0.02, right=0.98, top=0.9, bottom=0.03)
    if not draw(fig, setup, analysis, geometry):
        return None
    titles = Axes((0.0, 0.0, fig.width, fig.height), f"{name}t")
    titles.set_axis_off()
    titles.set_xlim(0.0, 1.0)
    titles.set_ylim(0.0, 1.0)
    for ax in fig.axes:  # each panel's title at the top, over its middle
        left, _, width, _ = ax.box
        titles.text((left + width / 2.0) / fig.width, 0.98, ax.title, fontsize=LEGEND_FONT,
                    va="top")
        ax.title = ""
    fig.axes.append(titles)
    return fig.svg()


def _panel(fig: Figure, left: float, right: float, title: str) -> Axes:
    """A panel of the sketch between *left* and *right* (fractions of its width), equal scale,
    no frame or ticks, titled."""
    _, _, top, bottom, _ = fig.margins
    box = (left * fig.width, (1.0 - top) * fig.height, (right - left) * fig.width,
           (top - bottom) * fig.height)
    ax = Axes(box, f"{fig.name}{len(fig.axes)}")
    ax.set_aspect("equal")
    ax.set_axis_off()
    ax.title = title  # (written at the sketch's top by work_zero_sketch)
    fig.axes.append(ax)
    return ax


def _body(ax: Axes, x: Array, y: Array) -> None:
    """A part's face: the polygon (x, y) filled, its edge drawn."""
    ax.fill(x, y, color=PART)
    ax.plot(np.append(x, x[:1]), np.append(y, y[:1]), color=EDGE, linewidth=0.8)


def _axis_line(ax: Axes, start: tuple[float, float], end: tuple[float, float]) -> None:
    """An axis of the part (a centre line), chain-dotted."""
    ax.plot([start[0], end[0]], [start[1], end[1]], color=EDGE, linewidth=0.6, linestyle="-.")


def _hidden(ax: Axes, x: Any, y: Any) -> None:
    """An edge out of sight (a bore), dashed."""
    ax.plot(x, y, color=EDGE, linewidth=0.6, linestyle="--")


def _arrow(ax: Axes, start: tuple[float, float], end: tuple[float, float], label: str,
           ha: str = "center", va: str = "center",
           offset: tuple[float, float] = (0.0, 0.0)) -> None:
    """An axis of the machine: an arrow from *start* to *end* with *label* past its head
    (*offset* from it, data units)."""
    ax.arrow(start, end, color=AXIS_INK, linewidth=1.2)
    ax.text(end[0] + offset[0], end[1] + offset[1], label, fontsize=LEGEND_FONT, ha=ha, va=va)


def _turn(ax: Axes, centre: tuple[float, float], radii: tuple[float, float],
          angles_deg: tuple[float, float]) -> tuple[float, float]:
    """A rotary axis: an arc of the ellipse about *centre* with *radii* from the first of
    *angles_deg* to the second, its head at the second; the head's point."""
    t = np.radians(np.linspace(*angles_deg, 60))
    x = centre[0] + radii[0] * np.cos(t)
    y = centre[1] + radii[1] * np.sin(t)
    ax.plot(x[:-3], y[:-3], color=AXIS_INK, linewidth=1.2)
    ax.arrow((x[-4], y[-4]), (x[-1], y[-1]), color=AXIS_INK, linewidth=1.2)
    return float(x[-1]), float(y[-1])


def _zero(ax: Axes, at: tuple[float, float] = (0.0, 0.0)) -> None:
    """The work zero: a filled dot."""
    ax.plot([at[0]], [at[1]], "o", color=AXIS_INK, markersize=5)


def _plate(fig: Figure, setup: Setup, analysis: Analysis, geometry: dict[str, Any]) -> bool:
    """A plate from above (the tool centre's path round it, X and Y from the work zero) and
    from the front (the plate on its bottom face, the bore's axis, X and Z from the work zero on
    the top face)."""
    path = _points(setup.toolpath.cutting) if setup.toolpath is not None else np.zeros((0, 2))
    path = path[np.isfinite(path).all(axis=1)]
    design = analysis.design
    tool = max((t.diameter_mm for t in setup.tools), default=0.0) / 2.0
    if not path.size:  # the plate's reach about its centre
        reach = float(geometry.get("max_radius_mm") or design.cam.base_radius or 50.0)
        path = np.array([[-reach, -reach], [reach, reach]])
    corner, far = path.min(axis=0), path.max(axis=0)
    size = max(float(np.max(far - corner)), 1e-6)
    low, high = float(corner[0]) + tool, float(far[0]) - tool
    if high <= low:
        low, high = float(corner[0]), float(far[0])
    top = _panel(fig, 0.0, 0.42, "from above")
    if setup.toolpath is not None and len(path) > 2:
        c = thinned(path, np.full(2, size / 400.0))
        top.plot(c[:, 0], c[:, 1], color=REFERENCE, linewidth=0.6)
    arm = 0.45 * max(float(np.min(far - corner)), 0.15 * size)
    _arrow(top, (0.0, 0.0), (arm, 0.0), "X", ha="left", offset=(0.03 * size, 0.0))
    _arrow(top, (0.0, 0.0), (0.0, arm), "Y", va="bottom", offset=(0.0, 0.03 * size))
    _zero(top)
    top.include([corner[0], far[0], arm * 1.3], [corner[1], far[1], arm * 1.3])
    front = _panel(fig, 0.46, 1.0, "from the front")
    thick = float(design.cam.thickness or geometry.get("thickness_mm") or 0.15 * (high - low))
    _body(front, np.array([low, high, high, low]), np.array([0.0, 0.0, -thick, -thick]))
    bore = design.cam.bore
    if bore:
        for x in (-bore / 2.0, bore / 2.0):
            _hidden(front, [x, x], [0.0, -thick])
    _axis_line(front, (0.0, 0.25 * thick), (0.0, -1.25 * thick))
    span = high - low
    up = max(0.3 * span, 2.0 * thick)
    _arrow(front, (0.0, 0.0), (0.0, up), "Z", va="bottom", offset=(0.0, 0.03 * span))
    _arrow(front, (0.0, 0.0), (0.35 * span, 0.0), "X", va="bottom",
           offset=(0.0, 0.04 * span))
    _zero(front)
    front.text(high + 0.04 * span, 0.0, "Z0:\ntop face", fontsize=LEGEND_FONT, ha="left",
               va="center")
    front.include([low, high + 0.42 * span], [-1.3 * thick, up + 0.12 * span])
    return True


def _drum(fig: Figure, setup: Setup, analysis: Analysis, geometry: dict[str, Any]) -> bool:
    """A drum from the side, as it sits at A = 0: its axis along X from its face at axial
    position 0, Z radial through the groove at cam angle 0 (the top of the picture: the
    design's +Y), the groove's walls on the half in sight, A turning about X."""
    radius, length = geometry.get("radius_mm"), geometry.get("length_mm")
    if not radius or not length:
        return False
    ax = _panel(fig, 0.0, 1.0, "the drum from the side, at A = 0")
    _body(ax, np.array([0.0, length, length, 0.0]), np.array([-radius, -radius, radius, radius]))
    start, wide = geometry.get("groove_start_mm"), geometry.get("groove_width_mm")
    if start is not None and wide:
        # the point of the drum at cam angle θ lies at the height R·cos θ; the half in sight
        # (from the design's −X) is θ of 180° to 360° on a ccw drum, 0° to 180° on a cw one
        half = 0.0 if analysis.design.cam.rotation == "cw" else math.pi
        theta = np.linspace(half, half + math.pi, 181)
        centre = start + analysis.program.evaluate(theta)[0]
        for side in (-wide / 2.0, wide / 2.0):
            ax.plot(centre + side, radius * np.cos(theta), color=EDGE, linewidth=0.8)
    bore = geometry.get("bore_radius_mm")
    if bore:
        for y in (-bore, bore):
            _hidden(ax, [0.0, length], [y, y])
    _axis_line(ax, (-0.15 * length, 0.0), (1.12 * length, 0.0))
    _arrow(ax, (0.0, 0.0), (0.45 * length, 0.0), "X", ha="left", va="bottom",
           offset=(0.02 * length, 0.04 * radius))
    _arrow(ax, (0.0, 0.0), (0.0, 1.3 * radius), "Z", va="bottom", offset=(0.0, 0.06 * radius))
    _zero(ax)
    head = _turn(ax, (1.2 * length, 0.0), (0.07 * length, 0.55 * radius), (110.0, -150.0))
    ax.text(1.2 * length + 0.12 * length, 0.0, "A", fontsize=LEGEND_FONT, ha="left",
            va="center")
    ax.text(-0.06 * length, -0.12 * radius, "face at\naxial 0", fontsize=LEGEND_FONT,
            ha="right", va="top")
    ax.include([-0.5 * length, 1.4 * length, head[0]], [-1.05 * radius, 1.55 * radius])
    return True


def _globoid(fig: Figure, setup: Setup, analysis: Analysis, geometry: dict[str, Any]) -> bool:
    """A globoid on its table-table machine at A = B = 0, seen from −Y: the blank about the
    cam's axis along X (A turns about it), the cutter pointing down on the line of centres
    (standing vertical: the pivot above the cam's axis for a concave globoid, below it for a
    convex one) with its tip at the roller's point, B's axis where the settings put it (B
    turns about it), the work zero on the cam's axis at its middle plane."""
    need = ("pivot_distance_mm", "width_mm", "surface_from_pivot_mm", "arm_length_mm")
    if any(not geometry.get(k) for k in need):
        return False
    pivot, width = geometry["pivot_distance_mm"], geometry["width_mm"]
    surface, arm = geometry["surface_from_pivot_mm"], geometry["arm_length_mm"]
    inward = 1.0 if geometry.get("globoid") == "concave" else -1.0
    z = np.linspace(-width / 2.0, width / 2.0, 81)
    ring = np.sqrt(np.maximum(surface**2 - z**2, 0.0))
    radius = inward * (pivot - ring)
    ax = _panel(fig, 0.0, 1.0, "on the machine at A = B = 0, seen from −Y")
    _body(ax, np.concatenate((z, z[::-1])), np.concatenate((radius, -radius[::-1])))
    bore = geometry.get("bore_radius_mm")
    if bore:
        for y in (-bore, bore):
            _hidden(ax, [-width / 2.0, width / 2.0], [y, y])
    _axis_line(ax, (-0.6 * width, 0.0), (0.6 * width, 0.0))
    # the cutter, the roller's size, its tip where the roller's point is: ℓ from the pivot
    tip = inward * (pivot - arm)
    half = max((t.diameter_mm for t in setup.tools), default=0.0) / 2.0 or (
        geometry.get("roller_radius_mm") or 0.05 * width)
    rmax = float(np.max(np.abs(radius)))
    # (its flutes and on, out of the blank: its end open, the tool going on to the spindle)
    tall = max(geometry.get("roller_length_mm") or 4.0 * half, rmax - tip + 0.2 * width)
    ax.fill([-half, half, half, -half], [tip, tip, tip + tall, tip + tall], color="#f5d6d2")
    ax.plot([-half, -half, half, half], [tip + tall, tip, tip, tip + tall], color=CUT,
            linewidth=0.9)
    ax.text(half + 0.04 * width, tip + tall, "cutter", fontsize=LEGEND_FONT, ha="left",
            va="top")
    # B's axis along Y, B clockwise as seen here (the right-hand rule about +Y, seen from −Y)
    machine = getattr(analysis.design.machining, "machine", None)
    b = (float(getattr(machine, "b_axis_x", 0.0)), float(getattr(machine, "b_axis_z", 0.0)))
    turn = 0.14 * width
    ax.plot([b[0]], [b[1]], "o", color=AXIS_INK, markersize=7, markerfacecolor="#ffffff")
    b_head = _turn(ax, b, (turn, turn), (-20.0, -160.0))
    ax.text(b[0] - 1.1 * turn, b[1] - 0.3 * turn, "B", fontsize=LEGEND_FONT, ha="right",
            va="top")
    end = 0.6 * width + 0.06 * width
    a_head = _turn(ax, (end, 0.0), (0.05 * width, 0.5 * rmax), (110.0, -150.0))
    ax.text(end + 0.09 * width, 0.0, "A", fontsize=LEGEND_FONT, ha="left", va="center")
    reach = 0.3 * width
    _arrow(ax, (0.0, 0.0), (reach, 0.0), "X", va="bottom", offset=(0.0, 0.03 * width))
    _arrow(ax, (0.0, 0.0), (0.0, 0.6 * rmax), "Z", ha="right", offset=(-0.04 * width, 0.0))
    _zero(ax)
    ax.include([-0.62 * width, end + 0.16 * width, b[0] - 1.2 * turn, b_head[0], a_head[0]],
               [-rmax * 1.05, rmax * 1.05, tip + tall * 1.05, b[1] - 1.1 * turn,
                b[1] + 1.1 * turn])
    return True


def _grinder(fig: Figure, setup: Setup, analysis: Analysis, geometry: dict[str, Any]) -> bool:
    """A cam on a grinder's C axis, seen from the face its drawing shows: the cam (its base
    circle) about the work zero, the wheel (the program's tool) beside it along X, C turning
    the way the cam turns in use."""
    cam = float(geometry.get("base_radius_mm") or geometry.get("max_radius_mm") or 0.0)
    wheel = max((t.diameter_mm for t in setup.tools), default=0.0) / 2.0
    if cam <= 0.0 or wheel <= 0.0:
        return False
    ax = _panel(fig, 0.0, 1.0, "the cam and the wheel, seen from the cam's drawn face")
    t = np.linspace(0.0, 2.0 * math.pi, 121)
    _body(ax, cam * np.cos(t), cam * np.sin(t))
    centre = cam + wheel
    ax.plot(centre + wheel * np.cos(t), wheel * np.sin(t), color=CUT, linewidth=0.9)
    ax.text(centre, -1.06 * wheel, "wheel", fontsize=LEGEND_FONT, ha="center", va="top")
    _arrow(ax, (0.0, 0.0), (centre, 0.0), "X", ha="left", va="bottom",
           offset=(0.03 * max(cam, wheel), 0.03 * max(cam, wheel)))
    turn = max(1.3 * cam, 0.3 * wheel)  # (round the cam, or as large as it can be read)
    # C grows as the cam turns in use, seen from the face its drawing shows
    sense = (300.0, 60.0) if analysis.design.cam.rotation == "cw" else (60.0, 300.0)
    head = _turn(ax, (0.0, 0.0), (turn, turn), sense)
    ax.text(-1.08 * turn, 0.0, "C", fontsize=LEGEND_FONT, ha="right", va="center")
    _zero(ax)
    ax.include([-1.35 * turn, centre + 1.1 * wheel, head[0]],
               [-1.3 * max(turn, wheel), 1.15 * max(turn, wheel)])
    return True
