"""``NAME.dxf`` of a groove cam: the plate cut out, the groove milled into its face.

``CUT``: the plate's outer circle and the bore (with its keyway), kerf-compensated when the design
gives a kerf. ``POCKET``: the groove's inner and outer walls as closed chains of LINE and ARC
entities within the tolerance (milled, so never kerf-offset); the depth is written on ``NOTE``.
``PITCH``: the pitch curve, the roller centre's path and the groove's centre line. ``BASE`` and
``PRIME`` circles, ``TOOLPATH`` (with ``cutter_radius``: round the plate, inside the holes, and
along the groove), ``MARK`` (centre cross, θ = 0 tick, and a tick across the groove wherever
contact passes from one wall to the other).
"""

from __future__ import annotations

import io
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from camfab.export.dxf import add_contour, add_contours, dxf_bytes, layer_loops, new_document
from camfab.geometry.arcfit import fit_arcs
from camfab.geometry.curves import perp
from camfab.geometry.profile import Profile

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.geometry.plate import Contours

#: A wall-change tick runs this many groove half widths either side of the pitch curve: across
#: both walls and a little beyond.
TICK_REACH = 1.4


def render_groove_dxf(analysis: Analysis, cut: Contours, toolpath: Contours | None,
                      kerf: float) -> bytes:
    """The groove cam's DXF as bytes: *cut* (mm) on ``CUT``, the walls on ``POCKET``, the
    references, marks and notes (see the module)."""
    design, geom, walls = analysis.design, analysis.geometry, analysis.groove
    assert geom is not None and walls is not None
    scale = 1.0 / design.mm_per_unit
    doc = new_document(design)
    msp = doc.modelspace()
    add_contour(msp, fit_arcs(geom.pitch.xy, geom.tolerance), scale, "PITCH")
    msp.add_circle((0.0, 0.0), geom.cam.base_radius * scale, dxfattribs={"layer": "BASE"})
    msp.add_circle((0.0, 0.0), geom.cam.prime_radius * scale, dxfattribs={"layer": "PRIME"})
    _add_marks(msp, analysis, scale)
    _add_notes(msp, analysis, scale, kerf)
    if toolpath is not None:
        add_contours(msp, toolpath, scale, "TOOLPATH")
    add_contour(msp, walls.inner, scale, "POCKET")
    add_contour(msp, walls.outer, scale, "POCKET")
    add_contours(msp, cut, scale, "CUT")
    return dxf_bytes(doc)


def _add_marks(msp: Any, analysis: Analysis, scale: float) -> None:
    geom, walls = analysis.geometry, analysis.groove
    assert geom is not None and walls is not None
    rb = geom.cam.base_radius
    size = 0.15 * rb * scale
    mark = {"layer": "MARK"}
    msp.add_line((-size, 0.0), (size, 0.0), dxfattribs=mark)
    msp.add_line((0.0, -size), (0.0, size), dxfattribs=mark)
    msp.add_line((0.0, 0.6 * rb * scale), (0.0, 0.9 * rb * scale), dxfattribs=mark)
    changes = walls.contact.changes
    if changes.size:
        pitch = geom.cam.pitch(changes, analysis.program.evaluate(changes))
        reach = TICK_REACH * walls.radius * perp(pitch.tangent)
        for a, b in zip((pitch.xy - reach) * scale, (pitch.xy + reach) * scale, strict=True):
            msp.add_line(tuple(a), tuple(b), dxfattribs=mark)


def _add_notes(msp: Any, analysis: Analysis, scale: float, kerf: float) -> None:
    design, geom, walls = analysis.design, analysis.geometry, analysis.groove
    assert geom is not None and walls is not None
    unit = design.units

    def length(mm: float) -> str:
        return f"{mm * scale:.6g} {unit}"

    lines = [f"{design.name}: groove cam, {design.cam.rotation}, base radius "
             f"{length(geom.cam.base_radius)} (the inner wall's smallest), plate radius "
             f"{length(walls.outer_radius)}, thickness {length(walls.thickness)}",
             f"POCKET: groove depth {length(walls.depth)} into the front face (floor at "
             f"z = {length(walls.thickness - walls.depth)}), groove width {length(walls.width)} "
             f"(roller radius {length(walls.roller_radius)}, clearance {length(walls.clearance)})",
             f"groove walls of {len(walls.inner.vertices)} and {len(walls.outer.vertices)} lines "
             f"and arcs within {design.manufacturing.tolerance * scale:.3g} {unit}; PITCH: the "
             f"roller centre's path"]
    changes = walls.contact.changes_deg
    if changes:
        lines.append("MARK ticks across the groove: contact changes walls at "
                     + ", ".join(f"{a:.4g}°" for a in changes)
                     + " (the roller reverses its spin)")
    if kerf > 0.0:
        lines.append(f"CUT offset for a kerf of {kerf * scale:.4g} {unit} (POCKET is milled: "
                     "not offset)")
    cutter = design.manufacturing.cutter_radius
    if cutter > 0.0:
        lines.append(f"TOOLPATH: centre of a cutter of radius {cutter * scale:.4g} {unit}")
    height = max(walls.outer_radius * scale * 0.04, 1e-3)
    left = -walls.outer_radius * scale
    low = -(walls.outer_radius + max(cutter, kerf)) * scale - 1.5 * height
    for row, line in enumerate(lines, start=1):
        msp.add_text(line, height=height, dxfattribs={"layer": "NOTE"}).set_placement(
            (left, low - 1.6 * row * height))


@dataclass(frozen=True)
class GrooveDrawing:
    """A groove cam's DXF as a reader sees it (mm): the closed contours on ``POCKET`` (largest
    first: the outer wall, then the inner), the CIRCLE radii and the closed contours on
    ``CUT`` (largest first), and the ``NOTE`` text."""

    pocket: list[Profile]
    cut_circles: list[float]
    cut_profiles: list[Profile]
    notes: list[str]


def read_groove_dxf(data: bytes, mm_per_unit: float) -> GrooveDrawing:
    """Read a groove cam's DXF back: every layer's lines and arcs chained into loops by ezdxf's
    edge miner, as a reader of the file would."""
    from camfab.export.ezdxf_import import load_ezdxf

    ezdxf = load_ezdxf()
    doc = ezdxf.read(io.StringIO(data.decode("utf-8")))
    msp = doc.modelspace()
    circles = sorted((float(c.dxf.radius) * mm_per_unit
                      for c in msp.query('CIRCLE[layer=="CUT"]')), reverse=True)
    notes = [str(t.dxf.text) for t in msp.query('TEXT[layer=="NOTE"]')]
    return GrooveDrawing(layer_loops(msp, "POCKET", mm_per_unit), circles,
                         layer_loops(msp, "CUT", mm_per_unit), notes)


