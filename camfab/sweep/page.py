"""A sweep's summary page (``NAME-sweep.html``): how many variants passed, the feasible region
over the first two varied keys (each cell coloured by the share of its variants, over the other
keys, that pass every check; grey where none is a valid design; a cell where some fail names
their failing checks by a mark each, the page's legend saying which), and the best variants.

The region is gathered as the rows stream past (:class:`Region`): cells, not points, so its
memory is bounded by the plot (at most :data:`CELLS` a side, and in each the count of each
check that failed there), not by the sweep.
"""

from __future__ import annotations

import itertools
import math
import re
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from camfab.sweep.rows import FAILED, Row

#: The most cells along each axis of the region's plot (count).
CELLS = 120
#: The plot's area (px): at least :data:`PLOT`, at most :data:`MOST`, between them
#: :data:`CELL_SIZE` a cell (room for the marks of its failing checks).
PLOT, MOST, CELL_SIZE = (548, 370), (900, 600), (44, 30)
#: Margins (px) around the plot: above, right (at least), below (the ticks and the key's name),
#: and the least on the left; where the rotated name of the vertical key stands (its baseline).
TOP, RIGHT, BOTTOM, LEFT, NAME_AT = 16, 16, 54, 76, 16
#: Sizes of type (px): tick labels, the keys' names, a cell's marks (at most, and at least: a
#: cell too small for its marks names its checks in its tooltip only).
TICK, NAME, MARK, LEAST_MARK = 11, 13, 12, 8
#: The width (a share of the type's size) the layout reserves for a character of text, and for
#: a capital (wide enough for DejaVu Sans, a Debian browser's sans-serif).
CHAR, CAPITAL = 0.62, 0.75
#: The mark of a FAIL row that names no check (its worker died).
DIED = "its worker died"


@dataclass
class Axis:
    """A varied key on the plot: its name and the values in plot order (numbers ascending,
    text as first met)."""

    name: str
    values: list[Any]
    numeric: bool
    _position: dict[Any, int] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self._position = {v: i for i, v in enumerate(self.values)}

    @property
    def cells(self) -> int:
        return min(len(self.values), CELLS)

    def cell(self, value: Any) -> int:
        """The cell of *value*: its position among the values, binned to :data:`CELLS`."""
        return self._position[value] * self.cells // len(self.values)

    def label(self, cell: int) -> str:
        first = self.values[cell * len(self.values) // self.cells]
        return _short(first)


def axis_of(name: str, values: Sequence[Any]) -> Axis:
    """The plot's axis for a key taking *values* (each distinct one once, in order)."""
    distinct = list(dict.fromkeys(values))
    numeric = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in distinct)
    if numeric:
        distinct.sort()
    return Axis(name, distinct, numeric)


@dataclass
class Region:
    """The feasible region gathered over the rows: per cell of the first two varied keys (or
    the first against nothing), how many variants are OK, FAIL and INVALID, and how many of
    its variants fail each check."""

    x: Axis
    y: Axis | None
    counts: dict[tuple[int, int], list[int]] = field(default_factory=dict)
    failed: dict[tuple[int, int], Counter[str]] = field(default_factory=dict)

    def add(self, rows: Sequence[Row], status_at: int) -> None:
        """Count *rows* (their values after the variant's index; status at *status_at*, its
        message after it)."""
        slot = {"OK": 0, "FAIL": 1, "INVALID": 2}
        for row in rows:
            key = (self.x.cell(row[1]), 0 if self.y is None else self.y.cell(row[2]))
            self.counts.setdefault(key, [0, 0, 0])[slot[row[status_at]]] += 1
            if row[status_at] == "FAIL":
                self.failed.setdefault(key, Counter()).update(failed_checks(row[status_at + 1]))

    def checks(self) -> list[tuple[str, str, int]]:
        """Each check that fails somewhere: its mark (:func:`marks`), its id and in how many
        variants it fails, the most often failing first."""
        total: Counter[str] = Counter()
        for counter in self.failed.values():
            total.update(counter)
        names = sorted(total, key=lambda name: (-total[name], name))
        short = marks(names)
        return [(short[name], name, total[name]) for name in names]


def failed_checks(message: str | None) -> list[str]:
    """The checks a FAIL row's *message* names (``failed: pressure_angle, undercut``); a row
    that names none (its worker died) counts as :data:`DIED`."""
    text = message or ""
    if not text.startswith(FAILED):
        return [DIED]
    return [name.strip() for name in text[len(FAILED):].split(",") if name.strip()]


def marks(names: Sequence[str]) -> dict[str, str]:
    """A short mark for each check id, each different: its words' initials in capitals
    (``pressure_angle`` PA, ``undercut`` U), else its first two to four letters, else the
    initials and a number."""
    out: dict[str, str] = {}
    for name in names:
        words = [w for w in re.split(r"[^A-Za-z0-9]+", name) if w] or ["X"]
        letters = "".join(words).upper()
        initials = "".join(w[0] for w in words).upper()
        tries = itertools.chain([initials], (letters[:k] for k in range(2, 5)),
                                (f"{initials}{n}" for n in itertools.count(2)))
        out[name] = next(mark for mark in tries if mark not in out.values())
    return out


@dataclass(frozen=True)
class Layout:
    """The plot's geometry (px): the SVG's size, the plot's corner and size, and a cell's."""

    width: float
    height: float
    left: float
    plot_w: float
    plot_h: float
    cw: float
    ch: float
    x_step: int
    y_step: int


def _text_width(text: str, size: float) -> float:
    """The width (px) the layout reserves for *text* in type of *size* px."""
    return len(text) * CHAR * size


def layout(region: Region) -> Layout:
    """Room for every label: a left margin as wide as the longest label of the vertical key
    (``polynomial-345`` whole), a right one for the last label of the horizontal key, and as
    many of each key's labels as stand clear of each other."""
    x, y = region.x, region.y
    nx, ny = x.cells, (1 if y is None else y.cells)
    plot_w = min(max(nx * CELL_SIZE[0], PLOT[0]), MOST[0])
    plot_h = min(max(ny * CELL_SIZE[1], PLOT[1]), MOST[1])
    cw, ch = plot_w / nx, plot_h / ny
    widest_x = max(_text_width(x.label(c), TICK) for c in range(nx))
    x_step = max(1, math.ceil(nx / 8), math.ceil((widest_x + 8) / cw))
    y_step = max(1, math.ceil(ny / 8), math.ceil((TICK + 4) / ch))
    widest_y = 0.0 if y is None else max(_text_width(y.label(c), TICK) for c in range(ny))
    left = max(LEFT, NAME_AT + 8 + widest_y + 6, widest_x / 2 - cw / 2 + 2)
    last = (nx - 1) // x_step * x_step
    right = max(RIGHT, _text_width(x.label(last), TICK) / 2 - (nx - last - 0.5) * cw + 4)
    return Layout(round(left + plot_w + right), TOP + plot_h + BOTTOM, left, plot_w, plot_h,
                  cw, ch, x_step, y_step)


def region_svg(region: Region) -> str:
    """The region as an SVG plot (a cell per key pair; green all pass, through amber, to red
    none passes; grey none valid; the marks of the checks that fail in a cell written in it,
    as large as it holds them, its tooltip naming them in full)."""
    x, y = region.x, region.y
    box = layout(region)
    ny = 1 if y is None else y.cells
    short = {name: mark for mark, name, _ in region.checks()}
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{box.width}" '
             f'height="{box.height}" viewBox="0 0 {box.width} {box.height}" role="img" '
             f'aria-label="feasible region">',
             f'<rect x="{box.left:.2f}" y="{TOP}" width="{box.plot_w}" height="{box.plot_h}" '
             f'fill="#f4f4f4"/>']
    for (i, j), (ok, fail, invalid) in sorted(region.counts.items()):
        valid = ok + fail
        colour = "#b8b8b8" if valid == 0 else _colour(ok / valid)
        title = f"{x.name} {x.label(i)}" + ("" if y is None else f", {y.name} {y.label(j)}")
        title = f"{title}: {ok} OK, {fail} FAIL, {invalid} INVALID"
        failing = sorted(region.failed.get((i, j), {}).items(),
                         key=lambda item: list(short).index(item[0]))
        if failing:
            title += "\nfailing: " + ", ".join(f"{name} ({n})" for name, n in failing)
        left, top = box.left + i * box.cw, TOP + (ny - 1 - j) * box.ch
        parts.append(
            f'<rect x="{left:.2f}" y="{top:.2f}" width="{box.cw + 0.05:.2f}" '
            f'height="{box.ch + 0.05:.2f}" fill="{colour}" data-cell="{i} {j}">'
            f'<title>{_escape(title)}</title></rect>')
        if failing:
            parts.extend(_cell_marks([short[name] for name, _ in failing], left, top, box,
                                     colour, (i, j)))
    parts.extend(_ticks(x, box, horizontal=True))
    if y is not None:
        parts.extend(_ticks(y, box, horizontal=False))
    size = min(NAME, box.plot_w / max(1.0, _text_width(x.name, 1.0)))
    parts.append(f'<text x="{box.left + box.plot_w / 2:.2f}" y="{box.height - 8}" '
                 f'text-anchor="middle" font-size="{size:.3g}">{_escape(x.name)}</text>')
    if y is not None:
        size = min(NAME, box.plot_h / max(1.0, _text_width(y.name, 1.0)))
        parts.append(f'<text transform="translate({NAME_AT},{TOP + box.plot_h / 2}) '
                     f'rotate(-90)" text-anchor="middle" font-size="{size:.3g}">'
                     f'{_escape(y.name)}</text>')
    parts.append("</svg>")
    return "\n".join(parts)


def _cell_marks(names: list[str], left: float, top: float, box: Layout, colour: str,
                cell: tuple[int, int]) -> list[str]:
    """The marks of a cell's failing checks written across it, as large as it holds them (at
    most :data:`MARK` px): all of them, else the most often failing and a "+", else none."""
    for text in (" ".join(names), f"{names[0]}+" if len(names) > 1 else None):
        if text is None:
            continue
        size = min(MARK, 0.6 * box.ch, (box.cw - 4) / (len(text) * CAPITAL))
        if size >= LEAST_MARK:
            ink = "#ffffff" if _dark(colour) else "#222222"
            return [f'<text x="{left + box.cw / 2:.2f}" y="{top + box.ch / 2:.2f}" '
                    f'text-anchor="middle" dominant-baseline="central" '
                    f'font-size="{size:.3g}" font-weight="600" fill="{ink}" '
                    f'data-marks="{cell[0]} {cell[1]}">{_escape(text)}</text>']
    return []


def _dark(colour: str) -> bool:
    """Whether white reads better than black on *colour* (``#rrggbb``; its luma)."""
    r, g, b = (int(colour[k:k + 2], 16) for k in (1, 3, 5))
    return 0.299 * r + 0.587 * g + 0.114 * b < 150


def _ticks(axis: Axis, box: Layout, horizontal: bool) -> list[str]:
    out = []
    count = axis.cells
    for cell in range(0, count, box.x_step if horizontal else box.y_step):
        label = _escape(axis.label(cell))
        if horizontal:
            at = box.left + (cell + 0.5) * box.cw
            out.append(f'<text x="{at:.1f}" y="{TOP + box.plot_h + 16}" text-anchor="middle" '
                       f'font-size="{TICK}">{label}</text>')
        else:
            at = TOP + box.plot_h - (cell + 0.5) * box.ch
            out.append(f'<text x="{box.left - 6:.1f}" y="{at + 4:.1f}" text-anchor="end" '
                       f'font-size="{TICK}">{label}</text>')
    return out


def _colour(share: float) -> str:
    """Red (none passes) through amber to green (all pass)."""
    stops = ((0.0, (200, 60, 50)), (0.5, (235, 170, 40)), (1.0, (50, 160, 80)))
    for (a, ca), (b, cb) in itertools.pairwise(stops):
        if share <= b:
            t = (share - a) / (b - a)
            r, g, bl = (round(p + t * (q - p)) for p, q in zip(ca, cb, strict=True))
            return f"#{r:02x}{g:02x}{bl:02x}"
    return "#32a050"


def _short(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:.4g}"
    return str(value)


def _escape(text: str) -> str:
    import html

    return html.escape(text, quote=True)


def render_page(title: str, design: str, varied: Sequence[tuple[str, str]], counts: dict[str, int],
                seconds: float, region: Region, columns: Sequence[str], best: Sequence[Row],
                objective: str | None, table: str, stopped: bool) -> bytes:
    """The summary page's bytes (see the module)."""
    import jinja2

    env = jinja2.Environment(loader=jinja2.PackageLoader("camfab", "templates"),
                             autoescape=True, trim_blocks=True, lstrip_blocks=True)
    total = sum(counts.values())
    text = env.get_template("sweep.html.j2").render(
        title=title, design=design, varied=varied, counts=counts, total=total,
        seconds=seconds, rate=total / seconds if seconds > 0 else None,
        region=jinja2.utils.markupsafe.Markup(region_svg(region)), checks=region.checks(),
        columns=columns, best=[[_short(v) if v is not None else "" for v in r] for r in best],
        objective=objective, table=table, stopped=stopped)
    return text.encode("utf-8")
