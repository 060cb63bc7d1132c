"""``NAME.svg``: the CUT contours at true size (SPEC §5), outlines only, arcs as SVG arcs.

The drawing is in the design's units (``width``/``height`` carry ``mm`` or ``in``), with the
cam frame's +Y pointing up: SVG's y axis points down, so y is negated and every arc's turning
sense with it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING
from xml.sax.saxutils import escape

import numpy as np

from camfab.geometry.profile import Profile

if TYPE_CHECKING:
    from camfab.geometry.plate import Plate
    from camfab.pipeline import Analysis

#: Margin around the drawing, as a fraction of its size.
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


def render_svg(analysis: Analysis, plate: Plate) -> bytes:
    """The SVG file as bytes: the plate's CUT contours (the outline first), as the DXF has them."""
    design = analysis.design
    scale = 1.0 / design.mm_per_unit
    shapes = [f'<path d="{path_data(profile, scale)}"/>' for profile in plate.cut.profiles]
    shapes += [f'<circle cx="0" cy="0" r="{_num(radius * scale)}"/>'
               for radius in plate.cut.circles]
    # a square about the cam centre holding the outline; the margin also covers the arcs'
    # slight bulge beyond their end points
    reach = float(np.max(plate.cut.profiles[0].radii())) * scale
    pad = MARGIN * 2 * reach
    x0 = y0 = -reach - pad
    width = 2 * reach + 2 * pad
    unit = design.units
    stroke = _num(width / 1000.0)
    head = (f'<svg xmlns="http://www.w3.org/2000/svg" width="{_num(width)}{unit}" '
            f'height="{_num(width)}{unit}" viewBox="{_num(x0)} {_num(y0)} {_num(width)} '
            f'{_num(width)}">')
    title = f"<title>{escape(design.name)}: CUT contours, {unit}</title>"
    body = (f'<g fill="none" stroke="#d00000" stroke-width="{stroke}">'
            + "".join(shapes) + "</g>")
    return (head + title + body + "</svg>\n").encode("utf-8")
