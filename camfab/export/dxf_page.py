"""The header of a camfab DXF that says where the drawing is and what page it fits.

``$EXTMIN``/``$EXTMAX`` are the drawing's true extents (file units): lines by their ends, arcs to
their extremes (not their ends, and not a Bézier approximation's), circles, and text by a
monospaced box (ezdxf's stand-in font: each character as wide as the text is high, like
AutoCAD's txt font, so the same drawing gets the same header on every machine whatever fonts it
has). Readers scale the drawing by them (Inkscape's "scale to A4" import).

The page is the extents with a margin, in the drawing's units: ``$LIMMIN``/``$LIMMAX`` (the
model space limits) are the page in the drawing's coordinates; ``$PLIMMIN``/``$PLIMMAX`` (the
paper's limits) the page from (0, 0), with ``$PINSBASE`` where the drawing's origin lies on it
and ``$PSVPSCALE`` 1:1, so a program that prints the drawing on its paper (LibreCAD's
``dxf2pdf``) makes a page of the part's size with the part on it at true size.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from camfab.arrays import Array

#: Margin of the page around the drawing's extents, as a fraction of their larger side: room
#: for the width of a reader's text font beyond the monospaced estimate, and for line widths.
PAGE_MARGIN = 0.05


def drawing_extents(msp: Any) -> tuple[Array, Array]:
    """The lower-left and upper-right corners (file units) of everything in the modelspace
    *msp*: LINE, ARC, CIRCLE, LWPOLYLINE (vertices; camfab writes its bulges as ARCs) and TEXT.

    Raises
    ------
    ValueError
        The modelspace holds another kind of entity, or nothing.
    """
    from ezdxf.enums import MAP_TEXT_ENUM_TO_ALIGN_FLAGS
    from ezdxf.fonts.fonts import MonospaceFont
    from ezdxf.tools.text import TextLine

    points: list[Array] = []
    for entity in msp:
        kind = entity.dxftype()
        if kind == "LINE":
            points.append(np.array([entity.dxf.start.vec2, entity.dxf.end.vec2]))
        elif kind == "ARC":
            box = entity.construction_tool().bounding_box
            points.append(np.array([box.extmin, box.extmax]))
        elif kind == "CIRCLE":
            centre, radius = np.array(entity.dxf.center.vec2), float(entity.dxf.radius)
            points.append(np.array([centre - radius, centre + radius]))
        elif kind == "LWPOLYLINE":
            points.append(np.array(list(entity.get_points("xy")), dtype=np.float64))
        elif kind == "TEXT":
            align, insert, _ = entity.get_placement()
            halign, valign = MAP_TEXT_ENUM_TO_ALIGN_FLAGS[align]
            font = MonospaceFont(float(entity.dxf.height), float(entity.dxf.width))
            corners = TextLine(entity.dxf.text, font).corner_vertices(
                insert, halign, valign, math.radians(entity.dxf.rotation))
            points.append(np.array([(v.x, v.y) for v in corners]))
        else:
            raise ValueError(f"no extents for a {kind} entity")
    if not points:
        raise ValueError("an empty drawing has no extents")
    every = np.concatenate(points)
    return every.min(axis=0), every.max(axis=0)


def set_page(doc: Any) -> None:
    """Set the extents, limits and paper of *doc*'s header from its modelspace (see the module)."""
    msp = doc.modelspace()
    low, high = drawing_extents(msp)
    margin = PAGE_MARGIN * float(np.max(high - low))
    x0, y0, x1, y1 = float(low[0]), float(low[1]), float(high[0]), float(high[1])
    # ezdxf writes $EXTMIN/$EXTMAX, $LIMMIN/$LIMMAX (the model space's) and $PLIMMIN/$PLIMMAX
    # (the paper's) from the layouts' own records
    msp.dxf.extmin = (x0, y0, 0.0)
    msp.dxf.extmax = (x1, y1, 0.0)
    msp.dxf.limmin = (x0 - margin, y0 - margin)
    msp.dxf.limmax = (x1 + margin, y1 + margin)
    paper = doc.active_layout()
    paper.dxf.limmin = (0.0, 0.0)
    paper.dxf.limmax = (x1 - x0 + 2 * margin, y1 - y0 + 2 * margin)
    doc.header["$PINSBASE"] = (margin - x0, margin - y0, 0.0)
    doc.header["$PSVPSCALE"] = 1.0
