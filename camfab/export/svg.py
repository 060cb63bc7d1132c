"""``NAME.svg``: the CUT contours at true size (SPEC §5), outlines only, arcs as SVG arcs.

The drawing is in the design's units (``width``/``height`` carry ``mm`` or ``in``), with the
cam frame's +Y pointing up: SVG's y axis points down, so y is negated and every arc's turning
sense with it. The page (``width``, ``height``, ``viewBox``) is the contours' exact bounding box,
arcs taken to their extremes rather than their ends, with a margin.
"""

from __future__ import annotations

from html import escape
from typing import TYPE_CHECKING

import numpy as np

from camfab.arrays import Array
from camfab.curves.profile import Profile

if TYPE_CHECKING:
    from camfab.design import Design
    from camfab.geometry.plate import Contours

#: Margin around the drawing (its exact bounding box), as a fraction of its size: room for the
#: stroke's half width (a thousandth of the size) and for a reader's rounding.
MARGIN = 0.05


def _num(value: float) -> str:
    return f"{value:.6f}".rstrip("0").rstrip(".") or "0"


def path_data(profile: Profile, scale: float) -> str:
    """An SVG path (``M``, ``L``, ``A``, ``Z``) for a closed contour, y negated."""
    v = profile.vertices * scale
    arcs = profile.arcs()
    arc_at = {int(i): k for k, i in enumerate(arcs.index)}
    parts = [f"M{_num(v[0, 0])} {_num(-v[0, 1])}"]
    count = len(v)
    for i in range(count):
        end = v[(i + 1) % count]
        k = arc_at.get(i)
        if k is None:
            parts.append(f"L{_num(end[0])} {_num(-end[1])}")
            continue
        sweep = float(arcs.sweep[k])
        radius = _num(float(arcs.radius[k]) * scale)
        large = 1 if abs(sweep) > np.pi else 0
        flag = 0 if sweep > 0 else 1  # counter-clockwise in the cam frame is clockwise here
        parts.append(f"A{radius} {radius} 0 {large} {flag} {_num(end[0])} {_num(-end[1])}")
    parts.append("Z")
    return " ".join(parts)


def drawn_bounds(contours: Contours, pocket: Contours | None = None) -> tuple[Array, Array]:
    """The exact bounding box (mm) of *contours* and the *pocket* walls: the lower-left and
    upper-right corners, arcs to their true extremes (not just their ends)."""
    boxes = [profile.bounds() for profile in contours.profiles]
    if pocket is not None:
        boxes += [profile.bounds() for profile in pocket.profiles]
    boxes += [(np.array([-r, -r]), np.array([r, r])) for r in contours.circles]
    return (np.min([low for low, _ in boxes], axis=0),
            np.max([high for _, high in boxes], axis=0))


def render_svg(design: Design, contours: Contours, pocket: Contours | None = None) -> bytes:
    """The SVG file as bytes: *contours* (mm; a disc's CUT contours, or a drum's developed
    groove) at true size, outlines only; a groove cam's *pocket* walls (to mill, not to cut
    through) in blue in a group of their own, ``id="POCKET"``."""
    scale = 1.0 / design.mm_per_unit
    shapes = [f'<path d="{path_data(profile, scale)}"/>' for profile in contours.profiles]
    shapes += [f'<circle cx="0" cy="0" r="{_num(radius * scale)}"/>'
               for radius in contours.circles]
    walls = [] if pocket is None else [f'<path d="{path_data(profile, scale)}"/>'
                                       for profile in pocket.profiles]
    low, high = (corner * scale for corner in drawn_bounds(contours, pocket))
    pad = MARGIN * float(np.max(high - low))
    width, height = high[0] - low[0] + 2 * pad, high[1] - low[1] + 2 * pad
    unit = design.units
    stroke = _num(max(width, height) / 1000.0)
    head = (f'<svg xmlns="http://www.w3.org/2000/svg" width="{_num(width)}{unit}" '
            f'height="{_num(height)}{unit}" viewBox="{_num(low[0] - pad)} {_num(-high[1] - pad)} '
            f'{_num(width)} {_num(height)}">')
    what = "CUT contours" + (" (red) and the groove's POCKET walls (blue)" if walls else "")
    title = f"<title>{escape(design.name, quote=False)}: {what}, {unit}</title>"
    body = (f'<g fill="none" stroke="#d00000" stroke-width="{stroke}">'
            + "".join(shapes) + "</g>")
    if walls:
        body += (f'<g id="POCKET" fill="none" stroke="#0050d0" stroke-width="{stroke}">'
                 + "".join(walls) + "</g>")
    return (head + title + body + "</svg>\n").encode("utf-8")
