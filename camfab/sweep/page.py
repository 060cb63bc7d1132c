"""A sweep's summary page (``NAME-sweep.html``): how many variants passed, the feasible region
over the first two varied keys (each cell coloured by the share of its variants, over the other
keys, that pass every check; grey where none is a valid design), and the best variants.

The region is gathered as the rows stream past (:class:`Region`): cells, not points, so its
memory is bounded by the plot (at most :data:`CELLS` a side), not by the sweep.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from camfab.sweep.rows import Row

#: The most cells along each axis of the region's plot (count).
CELLS = 120
#: Plot size (px) and margins.
WIDTH, HEIGHT, LEFT, BOTTOM, TOP, RIGHT = 640, 440, 76, 54, 16, 16


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
    the first against nothing), how many variants are OK, FAIL and INVALID."""

    x: Axis
    y: Axis | None
    counts: dict[tuple[int, int], list[int]] = field(default_factory=dict)

    def add(self, rows: Sequence[Row], status_at: int) -> None:
        """Count *rows* (their values after the variant's index; status at *status_at*)."""
        slot = {"OK": 0, "FAIL": 1, "INVALID": 2}
        for row in rows:
            key = (self.x.cell(row[1]), 0 if self.y is None else self.y.cell(row[2]))
            self.counts.setdefault(key, [0, 0, 0])[slot[row[status_at]]] += 1


def region_svg(region: Region) -> str:
    """The region as an SVG plot (a cell per key pair; green all pass, through amber, to red
    none passes; grey none valid)."""
    x, y = region.x, region.y
    nx, ny = x.cells, (1 if y is None else y.cells)
    plot_w, plot_h = WIDTH - LEFT - RIGHT, HEIGHT - TOP - BOTTOM
    cw, ch = plot_w / nx, plot_h / ny
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{HEIGHT}" '
             f'viewBox="0 0 {WIDTH} {HEIGHT}" role="img" aria-label="feasible region">',
             f'<rect x="{LEFT}" y="{TOP}" width="{plot_w}" height="{plot_h}" fill="#f4f4f4"/>']
    for (i, j), (ok, fail, invalid) in sorted(region.counts.items()):
        valid = ok + fail
        colour = "#b8b8b8" if valid == 0 else _colour(ok / valid)
        title = f"{x.name} {x.label(i)}" + ("" if y is None else f", {y.name} {y.label(j)}")
        parts.append(
            f'<rect x="{LEFT + i * cw:.2f}" y="{TOP + (ny - 1 - j) * ch:.2f}" '
            f'width="{cw + 0.05:.2f}" height="{ch + 0.05:.2f}" fill="{colour}">'
            f'<title>{_escape(title)}: {ok} OK, {fail} FAIL, {invalid} INVALID</title></rect>')
    parts.extend(_ticks(x, nx, cw, horizontal=True))
    if y is not None:
        parts.extend(_ticks(y, ny, ch, horizontal=False))
    parts.append(f'<text x="{LEFT + plot_w / 2}" y="{HEIGHT - 8}" text-anchor="middle" '
                 f'font-size="13">{_escape(x.name)}</text>')
    if y is not None:
        parts.append(f'<text transform="translate(16,{TOP + plot_h / 2}) rotate(-90)" '
                     f'text-anchor="middle" font-size="13">{_escape(y.name)}</text>')
    parts.append("</svg>")
    return "\n".join(parts)


def _ticks(axis: Axis, count: int, size: float, horizontal: bool) -> list[str]:
    step = max(1, math.ceil(count / 8))
    out = []
    for cell in range(0, count, step):
        label = _escape(axis.label(cell))
        if horizontal:
            at = LEFT + (cell + 0.5) * size
            out.append(f'<text x="{at:.1f}" y="{HEIGHT - BOTTOM + 16}" text-anchor="middle" '
                       f'font-size="11">{label}</text>')
        else:
            at = HEIGHT - BOTTOM - (cell + 0.5) * size
            out.append(f'<text x="{LEFT - 6}" y="{at + 4:.1f}" text-anchor="end" '
                       f'font-size="11">{label}</text>')
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
        region=jinja2.utils.markupsafe.Markup(region_svg(region)),
        columns=columns, best=[[_short(v) if v is not None else "" for v in r] for r in best],
        objective=objective, table=table, stopped=stopped)
    return text.encode("utf-8")
