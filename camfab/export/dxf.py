"""``NAME.dxf``: the cam plate for laser and CNC (SPEC §5), written with ezdxf.

Everything to be cut is on layer ``CUT`` as closed chains of LINE and ARC entities, or CIRCLEs —
never SPLINE — in the design's units with ``$INSUNITS`` set: the plate's contours,
kerf-compensated when the design gives a kerf. The outline is the tolerance-sampled profile fitted
with arcs, so each contour holds tens of entities, not thousands of tiny segments. Reference
geometry goes on ``PITCH``, ``BASE``, ``PRIME``, ``TOOLPATH`` (a milling cutter's centre path),
``MARK`` and ``NOTE``.
"""

from __future__ import annotations

import io
import re
from dataclasses import dataclass
from typing import Any

import numpy as np

from camfab.curves.profile import Profile
from camfab.export.part import READ_GAP, Arc, Circle, Drawing, Line

#: Layer name -> (ACI colour, linetype): CUT red, references in muted colours.
LAYERS = {
    "CUT": (1, "CONTINUOUS"),
    "POCKET": (6, "CONTINUOUS"),
    "PITCH": (5, "DASHED"),
    "BASE": (8, "CONTINUOUS"),
    "PRIME": (8, "DASHDOT"),
    "TOOLPATH": (4, "CONTINUOUS"),
    "MARK": (3, "CONTINUOUS"),
    "NOTE": (7, "CONTINUOUS"),
}

#: $INSUNITS codes of the design units.
INSUNITS = {"mm": 4, "in": 1}


def new_document(units: str) -> Any:
    """An R2010 drawing in *units* (``mm`` or ``in``) with camfab's layers."""
    from camfab.export.ezdxf_import import load_ezdxf

    ezdxf = load_ezdxf()
    doc = ezdxf.new("R2010", setup=["linetypes"])
    doc.header["$INSUNITS"] = INSUNITS[units]
    doc.header["$MEASUREMENT"] = 1 if units == "mm" else 0
    for name, (colour, linetype) in LAYERS.items():
        doc.layers.add(name, color=colour, linetype=linetype)
    return doc


def dxf_bytes(doc: Any) -> bytes:
    """The drawing as bytes, with its header's extents and page set from what it holds
    (:mod:`camfab.export.dxf_page`); the same for the same drawing on every run: ezdxf lists the
    CLASS of each entity type in use in the order of a set of names (which changes from run to
    run with Python's string hashing), so they are registered first, in sorted order."""
    from camfab.export.dxf_page import set_page

    set_page(doc)
    for name in sorted(doc.entitydb.dxf_types_in_use()):
        doc.classes.add_class(name)
    stream = io.StringIO()
    doc.write(stream)
    return _strip_volatile(stream.getvalue()).encode("utf-8")


def render_dxf(drawing: Drawing) -> bytes:
    """The DXF file of *drawing* as bytes (R2010, ASCII, no timestamps): its entities in the
    order drawn, on camfab's layers, in its units."""
    doc = new_document(drawing.units)
    msp = doc.modelspace()
    for entity in drawing.entities:
        attribs = {"layer": entity.layer}
        if isinstance(entity, Line):
            msp.add_line(entity.start, entity.end, dxfattribs=attribs)
        elif isinstance(entity, Arc):
            msp.add_arc(entity.centre, entity.radius, entity.start_deg, entity.end_deg,
                        dxfattribs=attribs)
        elif isinstance(entity, Circle):
            msp.add_circle(entity.centre, entity.radius, dxfattribs=attribs)
        else:
            msp.add_text(entity.text, height=entity.height,
                         dxfattribs=attribs).set_placement(entity.at)
    return dxf_bytes(doc)


def _strip_volatile(text: str) -> str:
    """Drop what changes on every save (header dates, edit time, fingerprint GUIDs, the time in
    ezdxf's signature), so the same design always gives the same bytes."""
    volatile = {"$TDCREATE", "$TDUCREATE", "$TDUPDATE", "$TDUUPDATE", "$TDINDWG", "$TDUSRTIMER",
                "$FINGERPRINTGUID", "$VERSIONGUID"}
    lines = text.splitlines()
    out: list[str] = []
    i = 0
    while i < len(lines):
        if lines[i].strip() == "9" and i + 1 < len(lines) and lines[i + 1].strip() in volatile:
            # skip the variable's name pair and its value pair
            i += 4
            continue
        out.append(lines[i])
        i += 1
    text = "\n".join(out) + "\n"
    # ezdxf signs the file "1.4.5 @ <time of writing>": keep the version, drop the time
    return re.sub(r"^(\d+\.\d+\S*) @ \d{4}-\d\d-\d\dT[\d:.+-]+$", r"\1", text, flags=re.M)


def read_cut_outline(data: bytes, mm_per_unit: float) -> Profile:
    """The largest closed contour on layer CUT of a DXF (the cam outline), in mm (see
    :func:`layer_loops`)."""
    from camfab.export.ezdxf_import import load_ezdxf

    ezdxf = load_ezdxf()
    loops = layer_loops(ezdxf.read(io.StringIO(data.decode("utf-8"))).modelspace(), "CUT",
                        mm_per_unit)
    if not loops:
        raise ValueError("the DXF has no closed contour on layer CUT")
    return loops[0]


def layer_loops(msp: Any, layer: str, mm_per_unit: float) -> list[Profile]:
    """The closed contours of the LINE, ARC and LWPOLYLINE entities on *layer* of a modelspace,
    in mm, largest first, each counter-clockwise from its vertex of least x: read by ezdxf and
    chained into loops by its edge miner, as a reader of the file would. (Not ezdxf's streaming
    reader: ``iterdxf.single_pass_modelspace`` of ezdxf 1.4 drops the last entity of the
    section.)"""
    from ezdxf import edgeminer, edgesmith

    entities = msp.query(f'LINE ARC LWPOLYLINE[layer=="{layer}"]')
    # numbered 1, 2, … for this read: the miner keeps edges in sets hashed by their ids, which
    # ezdxf draws from one counter for the whole process, so a later read of the same file
    # would chain its loops in another order and direction (and round their joins otherwise)
    edges = [edge._replace(id=number) for number, edge in enumerate(
        edgesmith.edges_from_entities_2d(entities, gap_tol=READ_GAP), start=1)]
    found: list[Profile] = []
    if not edges:  # (the edge miner refuses an empty deposit)
        return found
    for loop in edgeminer.find_all_loops(edgeminer.Deposit(edges, gap_tol=READ_GAP)):
        polyline = edgesmith.lwpolyline_from_chain(loop)
        points = np.array(list(polyline.get_points("xyb")), dtype=np.float64)
        found.append(Profile.from_points(points[:, :2] * mm_per_unit, points[:, 2]).canonical())
    return sorted(found, key=lambda p: -p.area)


@dataclass(frozen=True)
class DrawingRead:
    """A plate's DXF as a reader sees it (mm): the closed contours on ``POCKET`` (largest
    first), the CIRCLE radii and the closed contours on ``CUT`` (largest first), and the
    ``NOTE`` text."""

    pocket: list[Profile]
    cut_circles: list[float]
    cut_profiles: list[Profile]
    notes: list[str]


def read_dxf(data: bytes, mm_per_unit: float) -> DrawingRead:
    """Read a plate's DXF back: every layer's lines and arcs chained into loops by ezdxf's edge
    miner, as a reader of the file would."""
    from camfab.export.ezdxf_import import load_ezdxf

    ezdxf = load_ezdxf()
    doc = ezdxf.read(io.StringIO(data.decode("utf-8")))
    msp = doc.modelspace()
    circles = sorted((float(c.dxf.radius) * mm_per_unit
                      for c in msp.query('CIRCLE[layer=="CUT"]')), reverse=True)
    notes = [str(t.dxf.text) for t in msp.query('TEXT[layer=="NOTE"]')]
    return DrawingRead(layer_loops(msp, "POCKET", mm_per_unit), circles,
                       layer_loops(msp, "CUT", mm_per_unit), notes)
