"""Line charts and drawings written straight to SVG, for the reports' figures.

The reports draw a few dozen polylines per figure: curves over the cam angle, panel under panel,
and the cam at true shape. A general plotting library spends most of a build on them (matplotlib
took 0.2 s a design for the two figures of a disc cam's report, more than everything else in the
build together, most of it in creating and laying out tick artists). This module draws only what
the figures use, with numpy doing the coordinate work and one string format per polyline:

- :class:`Figure` holds axes laid out by fixed margins (fractions of the figure, as
  ``subplots_adjust`` takes them), panel under panel;
- :class:`Axes` takes lines with dashes and markers, fills, reference lines, text, arrows and
  a legend, scales itself to its data (5 % margins) or to given limits, keeps equal aspect for
  drawings, and puts "nice" ticks (steps of 1, 2, 2.5 and 5 times a power of ten) on both axes.

Sizes are points (1/72 in), as in the SVG written: ``width="792pt"`` and a viewBox in points.
The text stays text (sans-serif), so a page stays small and searchable. Ids are prefixed by the
figure's name, so several figures can share one HTML page. The output depends only on the
calls made: the same figure gives the same bytes.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from html import escape
from typing import Any

import numpy as np

from camfab.arrays import runs

#: Points per inch: figure sizes are given in inches, as in the figures' callers.
PT_PER_IN = 72.0

#: Font size (pt) of tick labels and of axis labels when none is given: 8.5 pt is 11.3 px on a
#: page at 100 % zoom.
TICK_FONT, LABEL_FONT = 8.5, 9.5

#: Tick mark length (pt), outward, and the gap (pt) between a tick and its label.
TICK_LENGTH, TICK_PAD = 3.5, 2.0

#: Gap (pt) between a panel and a legend beside it.
LEGEND_GAP = 10.0

#: Average glyph width of the sans-serif font as a fraction of its size, to size legend boxes.
GLYPH_WIDTH = 0.56

#: Widths of a tick label's glyphs as fractions of the font size, to keep the y label clear of
#: them: DejaVu Sans's, the widest of the figures' fonts (digits 0.64 em, its minus sign 0.84,
#: its point 0.32); the average above is too narrow for a column of digits.
DIGIT_WIDTH, TICK_GLYPHS = 0.64, {"−": 0.84, ".": 0.32, "×": 0.84}

#: Fraction of the data range left free at each end of an axis scaled to its data.
MARGIN = 0.05

#: Dash patterns per unit line width (as matplotlib's scaled dashes), by line style.
DASHES = {"--": (3.7, 1.6), ":": (1.0, 1.65), "-.": (6.4, 1.6, 1.0, 1.6)}

#: Multiples of a power of ten that tick steps may be.
NICE_STEPS = (1.0, 2.0, 2.5, 5.0, 10.0)

#: Coordinates (pt) are held within this distance of the figure: a value of 1e12 drawn off
#: the axes would otherwise write a huge number into the path (it is clipped anyway).
_FAR = 1.0e4

_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")

#: A title's field for the cam angle of the animation's frame: ``{θ}`` is the angle (deg),
#: ``{θ×k}`` k times it (a linear cam's travel). The title is written at θ = 0 with its
#: template as ``data-title``; the page's script writes it again at each frame's angle (the same
#: pattern and the same rounding: 6 significant digits, as the readout).
ANGLE_FIELD = re.compile(r"\{θ(?:×([-+0-9.eE]+))?\}")


def frame_title(template: str, theta_deg: float) -> str:
    """The title *template* at the cam angle *theta_deg* (its :data:`ANGLE_FIELD` fields
    filled in, as the page's script fills them)."""

    def value(match: re.Match[str]) -> str:
        scale = float(match.group(1)) if match.group(1) else 1.0
        return f"{float(f'{scale * theta_deg:.6g}') + 0.0:g}"

    return ANGLE_FIELD.sub(value, template)


@dataclass(frozen=True)
class Style:
    """How a line, marker, fill or text is drawn: colours, width (pt), dashes, alpha."""

    color: str = "#1f77b4"
    linewidth: float = 1.5
    linestyle: str = "-"
    marker: str | None = None
    markersize: float = 6.0
    markerfacecolor: str | None = None
    markeredgecolor: str | None = None
    alpha: float = 1.0


@dataclass
class _Item:
    kind: str  # line, fill, hline, vline, text, arrow, extent, image
    zorder: float
    style: Style
    label: str | None = None
    x: np.ndarray = field(default_factory=lambda: np.zeros(0))
    y: np.ndarray = field(default_factory=lambda: np.zeros(0))
    text: str = ""
    options: dict[str, Any] = field(default_factory=dict)
    group: str | None = None


def nice_ticks(low: float, high: float, bins: int) -> np.ndarray:
    """Round tick values within [*low*, *high*]: multiples of a step that is 1, 2, 2.5 or 5
    times a power of ten, the smallest such step giving at most *bins* intervals, or a smaller
    one where that leaves fewer than two ticks in the range."""
    span = high - low
    if not (math.isfinite(span) and span > 0.0):
        return np.array([low])
    raw = span / max(bins, 1)
    decade = 10.0 ** math.floor(math.log10(raw))
    steps = [s * decade for s in (0.5, *NICE_STEPS)]
    first = next(i for i, s in enumerate(steps) if s >= raw * (1.0 - 1e-9))
    for step in steps[first::-1]:
        ticks = np.arange(math.ceil(low / step - 1e-9), math.floor(high / step + 1e-9) + 1) * step
        if ticks.size >= 2:
            break
    return ticks


def tick_labels(ticks: np.ndarray) -> tuple[list[str], str]:
    """Labels of *ticks* with as many decimals as their step needs, and a common factor
    ("×10⁶") shown once by the axis when the values are very large or very small."""
    if ticks.size == 0:
        return [], ""
    largest = float(np.max(np.abs(ticks)))
    exponent = 0
    if largest >= 1e5 or 0.0 < largest < 1e-3:
        exponent = math.floor(math.log10(largest))
    scaled = ticks / 10.0**exponent
    step = float(np.min(np.diff(scaled))) if scaled.size > 1 else abs(float(scaled[0])) or 1.0
    # the fewest decimals that write the step exactly (25 → 0, 2.5 → 1, 0.25 → 2)
    decimals = next((d for d in range(12) if abs(round(step, d) - step) <= 1e-6 * step), 12)
    labels = [f"{v + 0.0:.{decimals}f}".replace("-", "−") for v in np.round(scaled, decimals)]
    factor = f"×10{str(exponent).translate(_SUPERSCRIPT)}" if exponent else ""
    return labels, factor


def text_width(text: str, size: float) -> float:
    """An estimate of the width (pt) of *text* at *size* pt (its longest line)."""
    return max((len(line) for line in text.split("\n")), default=0) * size * GLYPH_WIDTH


def tick_label_width(text: str, size: float) -> float:
    """An upper estimate of the width (pt) of the tick label *text* at *size* pt."""
    return size * sum(TICK_GLYPHS.get(c, DIGIT_WIDTH) for c in text)


def _num(value: float) -> str:
    return f"{value:.2f}"


def _path(x: np.ndarray, y: np.ndarray) -> str:
    """Path data of a polyline in points, broken where a value is not finite."""
    good = np.isfinite(x) & np.isfinite(y)
    if not good.any():
        return ""
    x = np.clip(x, -_FAR, _FAR)
    y = np.clip(y, -_FAR, _FAR)
    parts = []
    for start, stop in runs(good):
        xy = np.column_stack((x[start:stop], y[start:stop])).ravel().tolist()
        parts.append(("M%.2f %.2f" + " L%.2f %.2f" * (stop - start - 1)) % tuple(xy))
    return " ".join(parts)


def _stroke(style: Style) -> str:
    attrs = f' stroke="{style.color}" stroke-width="{_num(style.linewidth)}"'
    if style.linestyle in DASHES:
        dashes = ",".join(_num(d * style.linewidth) for d in DASHES[style.linestyle])
        attrs += f' stroke-dasharray="{dashes}"'
    if style.alpha < 1.0:
        attrs += f' stroke-opacity="{style.alpha:.3g}"'
    return attrs


def _markers(x: np.ndarray, y: np.ndarray, style: Style) -> str:
    """Markers at the points: ``.`` (a dot half the marker size), ``o`` (a circle) or ``+``."""
    good = np.isfinite(x) & np.isfinite(y)
    x, y = x[good], y[good]
    if not x.size:
        return ""
    size = style.markersize
    edge = style.markeredgecolor or style.color
    if style.marker == "+":
        h = size / 2.0
        xy = np.column_stack((x - h, y, x + h, y, x, y - h, x, y + h)).ravel().tolist()
        d = ("M%.2f %.2f L%.2f %.2f M%.2f %.2f L%.2f %.2f " * x.size) % tuple(xy)
        return f'<path d="{d.strip()}" fill="none" stroke="{edge}" stroke-width="1"/>'
    r = size / 4.0 if style.marker == "." else size / 2.0
    xy = np.column_stack((x - r, y)).ravel().tolist()
    arc = f" a{_num(r)} {_num(r)} 0 1 0 {_num(2 * r)} 0 a{_num(r)} {_num(r)} 0 1 0 {_num(-2 * r)} 0"
    d = ("M%.2f %.2f" + arc + " ") * x.size % tuple(xy)
    face = style.markerfacecolor or style.color
    return (f'<path d="{d.strip()}" fill="{face}" stroke="{edge}" '
            f'stroke-width="{_num(0.5 if style.marker == "." else 1.0)}"/>')


def _text(x: float, y: float, text: str, size: float, color: str = "#000000",
          anchor: str = "middle", baseline: str = "central", rotate: bool = False,
          attributes: str = "") -> str:
    """A text element at (x, y) pt; several lines are stacked (left to right when rotated);
    *attributes* are written on the element as given."""
    lines = text.split("\n")
    turn = f' transform="rotate(-90 {_num(x)} {_num(y)})"' if rotate else ""
    head = (f'<text x="{_num(x)}" y="{_num(y)}" font-size="{_num(size)}" fill="{color}" '
            f'text-anchor="{anchor}" dominant-baseline="{baseline}"{turn}{attributes}>')
    if len(lines) == 1:
        return head + escape(text) + "</text>"
    leading = 1.2 * size
    first = -leading * (len(lines) - 1) / 2.0
    spans = "".join(f'<tspan x="{_num(x)}" dy="{_num(first if i == 0 else leading)}">'
                    f"{escape(line)}</tspan>" for i, line in enumerate(lines))
    return head + spans + "</text>"


class Axes:
    """One panel: data drawn in data units, scaled into its box on the figure (points, y down)."""

    def __init__(self, box: tuple[float, float, float, float], name: str) -> None:
        self.box = box  # left, top, width, height (pt)
        self.name = name
        self.items: list[_Item] = []
        self.xlim: tuple[float, float] | None = None
        self.ylim: tuple[float, float] | None = None
        self.equal = False
        self.xticks: Sequence[float] | None = None
        self.yticks: Sequence[float] | None = None
        self.xbins, self.ybins = 0, 0
        self.xlabel = self.ylabel = self.title = ""
        self.xlabel_size = self.ylabel_size = LABEL_FONT
        self.title_size = 10.0
        self.xtick_labels = True
        self.legend_options: dict[str, Any] | None = None
        #: Whether the frame, the ticks and their labels are drawn (not on a sketch).
        self.axis_on = True
        self.shared: list[Axes] = [self]
        #: The group the items added now go into (drawn together in a ``<g>``), and the
        #: animation frames of each group: one SVG transform per frame.
        self.current_group: str | None = None
        self.frames: dict[str, list[str]] = {}

    def _add(self, item: _Item) -> None:
        item.group = self.current_group
        self.items.append(item)

    @contextmanager
    def group(self, name: str) -> Iterator[None]:
        """Items added inside go into the group *name*: one ``<g>``, which :meth:`animate`
        can move."""
        outer, self.current_group = self.current_group, name
        try:
            yield
        finally:
            self.current_group = outer

    def animate(self, name: str, frames: list[str]) -> None:
        """Frames of the group *name*: its SVG ``transform`` at each step of an animation
        (written on the group as ``data-frames``, with the panel's mapping of data to points as
        ``data-map``, :meth:`to_frame`; the page's script applies them)."""
        self.frames[name] = frames

    def include(self, x: Any, y: Any) -> None:
        """Points the panel's limits must hold, drawn as nothing (where an animated group will
        move to)."""
        self._add(_Item("extent", 0.0, Style(), None, np.asarray(x, dtype=float).ravel(),
                                np.asarray(y, dtype=float).ravel()))

    def to_frame(self) -> tuple[float, float, float, float]:
        """How data maps onto the figure once everything is added: (x, y) of the data origin
        (pt) and the points per data unit across and up: px = x0 + kx·x, py = y0 − ky·y."""
        left, top, width, height, (x0, x1), (y0, y1) = self.frame()
        kx, ky = width / (x1 - x0), height / (y1 - y0)
        return left - x0 * kx, top + height + y0 * ky, kx, ky

    # --- adding things -------------------------------------------------------------------------

    def plot(self, x: Any, y: Any, fmt: str | None = None, *, color: str = "#1f77b4",
             linewidth: float = 1.5, linestyle: str = "-", label: str | None = None,
             markersize: float = 6.0, markerfacecolor: str | None = None,
             markeredgecolor: str | None = None, zorder: float = 2.0) -> None:
        """A polyline through (x, y), or markers when *fmt* is ``"."``, ``"o"`` or ``"+"``
        (NaN breaks a line)."""
        style = Style(color, linewidth, linestyle, fmt, markersize,
                      "none" if markerfacecolor == "none" else markerfacecolor, markeredgecolor)
        self._add(_Item("line", zorder, style, label, np.asarray(x, dtype=float).ravel(),
                                np.asarray(y, dtype=float).ravel()))

    def fill(self, x: Any, y: Any, *, color: str, zorder: float = 1.0, alpha: float = 1.0,
             label: str | None = None) -> None:
        """A filled polygon through (x, y)."""
        self._add(_Item("fill", zorder, Style(color, alpha=alpha), label,
                                np.asarray(x, dtype=float), np.asarray(y, dtype=float)))

    def fill_between(self, x: Any, y1: Any, y2: float = 0.0, *, where: Any = None,
                     color: str, alpha: float = 1.0, label: str | None = None) -> None:
        """The area between the curve (x, y1) and the level *y2*, where *where* holds."""
        x, y1 = np.asarray(x, dtype=float), np.asarray(y1, dtype=float)
        mask = np.ones(x.shape, bool) if where is None else np.asarray(where, bool)
        for k, (start, stop) in enumerate(runs(mask)):
            xs, ys = x[start:stop], y1[start:stop]
            self.fill(np.concatenate((xs, xs[::-1])),
                      np.concatenate((ys, np.full(xs.shape, y2))), color=color, alpha=alpha,
                      label=label if k == 0 else None)

    def axhline(self, y: float, *, color: str, linewidth: float = 1.0, linestyle: str = "-",
                label: str | None = None) -> None:
        """A horizontal line across the panel at *y* (it counts in the panel's y range)."""
        self._add(_Item("hline", 2.0, Style(color, linewidth, linestyle), label,
                                y=np.array([float(y)])))

    def image(self, png: bytes, x: tuple[float, float], y: tuple[float, float]) -> None:
        """A raster (PNG bytes, :mod:`camfab.export.png`) stretched over the data rectangle
        from *x*[0] to *x*[1] across and *y*[0] to *y*[1] up (its first row at the top)."""
        from base64 import b64encode

        self.include(list(x), list(y))
        self._add(_Item("image", 0.5, Style(), None, np.array(x, dtype=float),
                        np.array(y, dtype=float), b64encode(png).decode("ascii")))

    def axvspan(self, x0: float, x1: float, *, color: str, alpha: float = 1.0,
                label: str | None = None) -> None:
        """A band across the panel's height from *x0* to *x1* (it does not count in the
        panel's range)."""
        self._add(_Item("vspan", 0.5, Style(color, alpha=alpha), label,
                        np.array([float(x0), float(x1)])))

    def axvline(self, x: float, *, color: str, linewidth: float = 1.0,
                linestyle: str = "-", label: str | None = None) -> None:
        """A vertical line across the panel at *x*."""
        self._add(_Item("vline", 2.0, Style(color, linewidth, linestyle), label,
                        x=np.array([float(x)])))

    def text(self, x: float, y: float, text: str, *, fontsize: float = 10.0,
             color: str = "#000000", ha: str = "center", va: str = "center",
             y_in_axes: bool = False) -> None:
        """Text at (x, y) in data units; with *y_in_axes*, y is a fraction of the panel's
        height (1 is its top edge)."""
        self._add(_Item("text", 3.0, Style(color), None, np.array([x]), np.array([y]),
                                text, {"size": fontsize, "ha": ha, "va": va,
                                       "y_in_axes": y_in_axes}))

    def arrow(self, start: Sequence[float], end: Sequence[float], *, color: str,
              linewidth: float = 1.0) -> None:
        """An arrow from *start* to *end* (data units), its head at *end*."""
        self._add(_Item("arrow", 3.0, Style(color, linewidth), None,
                                np.array([start[0], end[0]], float),
                                np.array([start[1], end[1]], float)))

    def legend(self, *, fontsize: float = 7.0, loc: str = "upper right", ncol: int = 1,
               outside_right: bool = False) -> None:
        """A legend of the labelled items at *loc* (``upper right``, ``upper left``,
        ``lower left``, ``lower right``, or ``best``: the corner over the fewest data points),
        or to the right of the panel."""
        self.legend_options = {"size": fontsize, "loc": loc, "ncol": ncol,
                               "outside": outside_right}

    # --- settings ------------------------------------------------------------------------------

    def set_xlim(self, low: float, high: float) -> None:
        self.xlim = (float(low), float(high))

    def set_ylim(self, low: float, high: float) -> None:
        self.ylim = (float(low), float(high))

    def set_axis_off(self) -> None:
        """No frame, ticks or tick labels: a sketch drawn to scale, its coordinates unsaid."""
        self.axis_on = False

    def set_aspect(self, aspect: str) -> None:
        """``"equal"``: one millimetre is as long across as up (the panel's box shrinks)."""
        self.equal = aspect == "equal"

    def set_xticks(self, ticks: Sequence[float]) -> None:
        """Ticks at *ticks* on the x axis (none for an empty list); they are labelled unless the
        panel shares its x axis with one below it."""
        self.xticks = list(ticks)

    def set_yticks(self, ticks: Sequence[float]) -> None:
        """Ticks at *ticks* on the y axis (none for an empty list)."""
        self.yticks = list(ticks)

    def set_bins(self, x: int = 0, y: int = 0) -> None:
        """At most this many tick intervals on each axis (0: by the axis' length)."""
        self.xbins, self.ybins = x, y

    def set_xlabel(self, text: str, fontsize: float = LABEL_FONT) -> None:
        self.xlabel, self.xlabel_size = text, fontsize

    def set_ylabel(self, text: str, fontsize: float = LABEL_FONT) -> None:
        self.ylabel, self.ylabel_size = text, fontsize

    def set_title(self, text: str, fontsize: float = 10.0) -> None:
        """The panel's title; ``{θ}`` in it (:data:`ANGLE_FIELD`) follows the animation's
        cam angle."""
        self.title, self.title_size = text, fontsize

    # --- layout --------------------------------------------------------------------------------

    def _data_range(self, axis: str) -> tuple[float, float] | None:
        values = []
        for item in self.items:
            if item.kind in ("line", "fill", "extent") or (
                    item.kind == "hline" and axis == "y") or (item.kind == "vline" and axis == "x"):
                v = item.x if axis == "x" else item.y
                v = v[np.isfinite(v)]
                if v.size:
                    values.append((float(v.min()), float(v.max())))
        if not values:
            return None
        return min(v[0] for v in values), max(v[1] for v in values)

    def limits(self) -> tuple[tuple[float, float], tuple[float, float]]:
        """The panel's x and y limits: as set, or the data's with a margin (shared x across
        the panels of a figure made with ``sharex``)."""
        if self.xlim is not None:
            xlim = self.xlim
        else:
            ranges = [r for ax in self.shared if (r := ax._data_range("x")) is not None]
            xlim = _padded((min(r[0] for r in ranges), max(r[1] for r in ranges))
                           if ranges else None)
        ylim = self.ylim if self.ylim is not None else _padded(self._data_range("y"))
        return xlim, ylim

    def frame(self) -> tuple[float, float, float, float, tuple[float, float],
                             tuple[float, float]]:
        """The box (left, top, width, height, pt) the data is drawn in, and the limits; with
        equal aspect the box shrinks about its centre to fit the data at one scale."""
        (x0, x1), (y0, y1) = self.limits()
        left, top, width, height = self.box
        if self.equal:
            scale = min(width / (x1 - x0), height / (y1 - y0))
            new_w, new_h = scale * (x1 - x0), scale * (y1 - y0)
            left += (width - new_w) / 2.0
            top += (height - new_h) / 2.0
            width, height = new_w, new_h
        return left, top, width, height, (x0, x1), (y0, y1)

    def render(self, figure_name: str, index: int) -> str:
        """The panel as SVG: its clipped contents, frame, ticks, labels, title and legend."""
        left, top, width, height, (x0, x1), (y0, y1) = self.frame()

        def px(x: np.ndarray) -> np.ndarray:
            return left + (x - x0) * (width / (x1 - x0))

        def py(y: np.ndarray) -> np.ndarray:
            return top + height - (y - y0) * (height / (y1 - y0))

        clip = f"{figure_name}-clip{index}"
        out = [f'<clipPath id="{clip}"><rect x="{_num(left)}" y="{_num(top)}" '
               f'width="{_num(width)}" height="{_num(height)}"/></clipPath>',
               f'<g clip-path="url(#{clip})">']
        items = sorted(self.items, key=lambda i: i.zorder)
        # drawn things stay inside the panel; text and arrows may stand outside it; a group's
        # items are drawn together where its first item falls
        box = (left, top, width, height)
        done: set[str] = set()
        for item in items:
            if item.kind == "extent" or item.group in done or (
                    item.kind in ("text", "arrow") and item.group is None):
                continue
            if item.group is None:
                out.append(self._item_svg(item, px, py, box))
                continue
            done.add(item.group)
            frames = self.frames.get(item.group)
            data = ""
            if frames is not None:
                mapping = " ".join(f"{v:.6f}" for v in self.to_frame())
                data = f" data-frames='{json.dumps(frames)}' data-map=\"{mapping}\""
            out.append(f'<g id="{figure_name}-{item.group}"{data}>')
            out += [self._item_svg(i, px, py, box) for i in items
                    if i.group == item.group and i.kind != "extent"]
            out.append("</g>")
        out.append("</g>")
        out += [self._item_svg(i, px, py, (left, top, width, height)) for i in items
                if i.kind in ("text", "arrow") and i.group is None]
        if self.axis_on:
            out.append(f'<rect x="{_num(left)}" y="{_num(top)}" width="{_num(width)}" '
                       f'height="{_num(height)}" fill="none" stroke="#000000" '
                       f'stroke-width="0.8"/>')
            out.append(self._ticks(px, py, (left, top, width, height), (x0, x1), (y0, y1)))
        if self.title:
            # a title with the cam angle in it: written at θ = 0, its template with it
            animated = ANGLE_FIELD.search(self.title) is not None
            out.append(_text(left + width / 2.0, top - 6.0,
                             frame_title(self.title, 0.0) if animated else self.title,
                             self.title_size, baseline="auto",
                             attributes=f' class="frame-title" data-title="{escape(self.title)}"'
                             if animated else ""))
        if self.legend_options is not None:
            out.append(self._legend(px, py, (left, top, width, height)))
        return "".join(out)

    def _item_svg(self, item: _Item, px: Any, py: Any,
                  box: tuple[float, float, float, float]) -> str:
        left, top, width, height = box
        s = item.style
        if item.kind == "line":
            x, y = px(item.x), py(item.y)
            if s.marker is not None:
                return _markers(x, y, s)
            d = _path(x, y)
            return f'<path d="{d}" fill="none"{_stroke(s)} stroke-linejoin="round"/>' if d else ""
        if item.kind == "fill":
            d = _path(px(item.x), py(item.y))
            opacity = f' fill-opacity="{s.alpha:.3g}"' if s.alpha < 1.0 else ""
            return f'<path d="{d} Z" fill="{s.color}"{opacity} stroke="none"/>' if d else ""
        if item.kind in ("hline", "vline") and not np.isfinite(item.x if item.kind == "vline"
                                                                else item.y).all():
            return ""
        if item.kind == "hline":
            y = float(py(item.y)[0])
            return (f'<path d="M{_num(left)} {_num(y)} L{_num(left + width)} {_num(y)}" '
                    f'fill="none"{_stroke(s)}/>')
        if item.kind == "vline":
            x = float(px(item.x)[0])
            return (f'<path d="M{_num(x)} {_num(top)} L{_num(x)} {_num(top + height)}" '
                    f'fill="none"{_stroke(s)}/>')
        if item.kind == "arrow":
            return _arrow(px(item.x), py(item.y), s)
        if item.kind == "image":
            (x0, x1), (y0, y1) = px(item.x), py(item.y)
            return (f'<image x="{_num(min(x0, x1))}" y="{_num(min(y0, y1))}" '
                    f'width="{_num(abs(x1 - x0))}" height="{_num(abs(y1 - y0))}" '
                    f'preserveAspectRatio="none" style="image-rendering:pixelated" '
                    f'href="data:image/png;base64,{item.text}"/>')
        if item.kind == "vspan":
            x0, x1 = (float(v) for v in px(item.x))
            opacity = f' fill-opacity="{s.alpha:.3g}"' if s.alpha < 1.0 else ""
            return (f'<rect x="{_num(x0)}" y="{_num(top)}" width="{_num(x1 - x0)}" '
                    f'height="{_num(height)}" fill="{s.color}"{opacity}/>')
        o = item.options
        x = float(px(item.x)[0])
        y = top + height * (1.0 - float(item.y[0])) if o["y_in_axes"] else float(py(item.y)[0])
        anchor = {"left": "start", "center": "middle", "right": "end"}[o["ha"]]
        baseline = {"bottom": "auto", "center": "central", "top": "hanging"}[o["va"]]
        return _text(x, y, item.text, o["size"], s.color, anchor, baseline)

    def _ticks(self, px: Any, py: Any, box: tuple[float, float, float, float],
               xlim: tuple[float, float], ylim: tuple[float, float]) -> str:
        left, top, width, height = box
        bottom = top + height
        out = []
        if self.xticks is not None:
            xt = np.array([t for t in self.xticks if xlim[0] <= t <= xlim[1]], float)
        else:
            xt = nice_ticks(*xlim, self.xbins or max(3, int(width / 60.0)))
        if self.yticks is not None:
            yt = np.array([t for t in self.yticks if ylim[0] <= t <= ylim[1]], float)
        else:
            yt = nice_ticks(*ylim, self.ybins or max(3, int(height / 45.0)))
        marks = [f"M{_num(x)} {_num(bottom)} l0 {_num(TICK_LENGTH)}" for x in px(xt)]
        marks += [f"M{_num(left)} {_num(y)} l{_num(-TICK_LENGTH)} 0" for y in py(yt)]
        if marks:
            out.append(f'<path d="{" ".join(marks)}" stroke="#000000" stroke-width="0.8"/>')
        label_depth = 0.0
        if self.xtick_labels and xt.size:
            labels, factor = tick_labels(xt)
            y = bottom + TICK_LENGTH + TICK_PAD
            out += [_text(x, y, t, TICK_FONT, baseline="hanging") for x, t in zip(px(xt), labels,
                                                                                    strict=True)]
            if factor:
                out.append(_text(left + width, y + TICK_FONT * 1.3, factor, TICK_FONT,
                                 anchor="end", baseline="hanging"))
            label_depth = TICK_FONT * 1.2
        if self.xlabel:
            out.append(_text(left + width / 2.0, bottom + TICK_LENGTH + TICK_PAD + label_depth
                             + 4.0, self.xlabel, self.xlabel_size, baseline="hanging"))
        widest = 0.0
        if yt.size:
            labels, factor = tick_labels(yt)
            x = left - TICK_LENGTH - TICK_PAD
            out += [_text(x, y, t, TICK_FONT, anchor="end") for y, t in zip(py(yt), labels,
                                                                            strict=True)]
            widest = max(tick_label_width(t, TICK_FONT) for t in labels)
            if factor:
                out.append(_text(left, top - 2.0, factor, TICK_FONT, anchor="start",
                                 baseline="auto"))
        if self.ylabel:
            lines = self.ylabel.count("\n") + 1
            x = left - TICK_LENGTH - TICK_PAD - widest - 4.0 - 0.6 * lines * self.ylabel_size
            out.append(_text(x, top + height / 2.0, self.ylabel, self.ylabel_size, rotate=True))
        return "".join(out)

    def _legend(self, px: Any, py: Any, box: tuple[float, float, float, float]) -> str:
        entries = [i for i in self.items if i.label]
        if not entries:
            return ""
        o = self.legend_options or {}
        size, ncol = o["size"], max(1, min(o["ncol"], len(entries)))
        rows = math.ceil(len(entries) / ncol)
        sample, pad, row_h = 2.0 * size, 0.5 * size, 1.35 * size

        def tall(e: _Item) -> float:  # an entry's height: a label of several lines is taller
            return row_h + 1.2 * size * (e.label or "").count("\n")

        columns = [entries[c * rows:(c + 1) * rows] for c in range(ncol)]
        col_w = [sample + 0.6 * size + max(text_width(e.label or "", size) for e in col)
                 for col in columns if col]
        w = sum(col_w) + pad * (len(col_w) + 1)
        h = max(sum(tall(e) for e in col) for col in columns if col) + pad
        left, top, width, height = box
        if o["outside"]:  # beside the panel, a fixed gap from it whatever its width
            x, y = left + width + LEGEND_GAP, top + (height - h) / 2.0
        else:
            x, y = self._corner(o["loc"], w, h, px, py, box)
        out = [f'<rect x="{_num(x)}" y="{_num(y)}" width="{_num(w)}" height="{_num(h)}" '
               f'fill="#ffffff" fill-opacity="0.85" stroke="#cccccc" stroke-width="0.8" '
               f'rx="2"/>']
        cx = x + pad
        for col, cw in zip(columns, col_w, strict=False):
            cy = y + pad / 2.0
            for e in col:
                cy += tall(e) / 2.0  # the entry's middle, its lines about it
                out.append(_legend_sample(e, cx, cy, sample))
                out.append(_text(cx + sample + 0.6 * size, cy, e.label or "", size,
                                 anchor="start"))
                cy += tall(e) / 2.0
            cx += cw + pad
        return "".join(out)

    def _corner(self, loc: str, w: float, h: float, px: Any, py: Any,
                box: tuple[float, float, float, float]) -> tuple[float, float]:
        left, top, width, height = box
        inset = 4.0
        corners = {"upper right": (left + width - w - inset, top + inset),
                   "upper left": (left + inset, top + inset),
                   "lower left": (left + inset, top + height - h - inset),
                   "lower right": (left + width - w - inset, top + height - h - inset)}
        if loc != "best":
            return corners[loc]
        xs = np.concatenate([px(i.x) for i in self.items if i.kind == "line"] or [np.zeros(0)])
        ys = np.concatenate([py(i.y) for i in self.items if i.kind == "line"] or [np.zeros(0)])

        def covered(corner: tuple[float, float]) -> int:
            cx, cy = corner
            return int(np.count_nonzero((xs >= cx) & (xs <= cx + w) & (ys >= cy) & (ys <= cy + h)))

        return min(corners.values(), key=covered)


def _padded(span: tuple[float, float] | None) -> tuple[float, float]:
    """A data range with :data:`MARGIN` free at each end; an empty or zero range widened."""
    if span is None:
        return 0.0, 1.0
    low, high = span
    if high - low <= 1e-12 * max(abs(low), abs(high), 1e-300):
        delta = 0.05 * abs(low) if low else 1.0
        return low - delta, high + delta
    pad = MARGIN * (high - low)
    return low - pad, high + pad


def _legend_sample(item: _Item, x: float, y: float, length: float) -> str:
    s = item.style
    if item.kind in ("fill", "vspan"):
        opacity = f' fill-opacity="{s.alpha:.3g}"' if s.alpha < 1.0 else ""
        return (f'<rect x="{_num(x)}" y="{_num(y - 0.3 * length)}" width="{_num(length)}" '
                f'height="{_num(0.6 * length)}" fill="{s.color}"{opacity}/>')
    if item.kind == "line" and s.marker is not None:
        return _markers(np.array([x + length / 2.0]), np.array([y]), s)
    return (f'<path d="M{_num(x)} {_num(y)} L{_num(x + length)} {_num(y)}" '
            f'fill="none"{_stroke(s)}/>')


def _arrow(x: np.ndarray, y: np.ndarray, style: Style) -> str:
    """A line from the first point to the second with an open head at the second."""
    dx, dy = x[1] - x[0], y[1] - y[0]
    length = math.hypot(dx, dy) or 1.0
    ux, uy = dx / length, dy / length
    size = 4.0 + 2.0 * style.linewidth
    head = [(x[1] - size * (ux * 0.9 + uy * 0.5), y[1] - size * (uy * 0.9 - ux * 0.5)),
            (x[1] - size * (ux * 0.9 - uy * 0.5), y[1] - size * (uy * 0.9 + ux * 0.5))]
    d = (f"M{_num(x[0])} {_num(y[0])} L{_num(x[1])} {_num(y[1])} "
         f"M{_num(head[0][0])} {_num(head[0][1])} L{_num(x[1])} {_num(y[1])} "
         f"L{_num(head[1][0])} {_num(head[1][1])}")
    return f'<path d="{d}" fill="none"{_stroke(style)}/>'


class Figure:
    """A figure of *width_in* × *height_in* inches whose panels fill the area inside the
    margins (fractions of the figure: *left*, *right*, *top*, *bottom*; *hspace* is the gap
    between panels as a fraction of a panel's height). *name* prefixes the SVG ids."""

    def __init__(self, width_in: float, height_in: float, name: str, *, left: float = 0.1,
                 right: float = 0.98, top: float = 0.93, bottom: float = 0.1,
                 hspace: float = 0.12) -> None:
        self.width, self.height = width_in * PT_PER_IN, height_in * PT_PER_IN
        self.name = name
        self.margins = (left, right, top, bottom, hspace)
        self.axes: list[Axes] = []
        #: SVG drawn over the panels, as given (pt).
        self.overlays: list[str] = []

    def subplots(self, rows: int = 1, sharex: bool = False) -> list[Axes]:
        """*rows* panels, one under the other (sharing their x range with *sharex*; only the
        bottom one then labels its x ticks)."""
        left, right, top, bottom, hspace = self.margins
        total = (top - bottom) * self.height
        panel = total / (rows + hspace * (rows - 1))
        x, width = left * self.width, (right - left) * self.width
        axes = [Axes((x, (1.0 - top) * self.height + i * panel * (1.0 + hspace), width, panel),
                     f"{self.name}{i}") for i in range(rows)]
        if sharex:
            for ax in axes:
                ax.shared = axes
                ax.xtick_labels = ax is axes[-1]
        self.axes += axes
        return axes

    def svg(self) -> str:
        """The figure as an ``<svg>`` element (no XML header), ready to paste into a page."""
        w, h = _num(self.width), _num(self.height)
        body = "".join(ax.render(self.name, i) for i, ax in enumerate(self.axes))
        body += "".join(self.overlays)
        return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}pt" height="{h}pt" '
                f'viewBox="0 0 {w} {h}" font-family="DejaVu Sans, Helvetica, Arial, sans-serif" '
                f'stroke-linecap="butt">'
                f'<rect width="{w}" height="{h}" fill="#ffffff"/>{body}</svg>')
