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
import math
import re
from typing import TYPE_CHECKING, Any

import numpy as np

from camfab.geometry.arcfit import fit_arcs
from camfab.geometry.profile import Profile

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.geometry.plate import Contours, Plate


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

#: Ends of lines and arcs closer than this (file units) meet, for the reader of the CUT layer:
#: an arc's ends are recomputed from its centre, radius and angles, which for a nearly straight
#: arc (radius 10⁶ × its chord) rounds them by about 1e-9.
READ_GAP = 1e-6

#: $INSUNITS codes of the design units.
INSUNITS = {"mm": 4, "in": 1}


def add_contour(msp: Any, profile: Profile, scale: float, layer: str,
                 closed: bool = True) -> None:
    """A contour as LINE and ARC entities meeting end to end (an open one without its closing
    edge).

    Not one LWPOLYLINE with bulges: OpenSCAD's DXF import (among others) drops the bulges and
    cuts chords, while every DXF reader takes lines and arcs, and CAD/CAM programs chain them
    into the closed contour.
    """
    attribs = {"layer": layer}
    if closed:
        profile = _readable(profile, READ_GAP / scale)
    v = profile.vertices * scale
    following = np.roll(v, -1, axis=0)
    arcs = profile.arcs()
    arc_at = {int(i): k for k, i in enumerate(arcs.index)}
    for i in range(len(v) if closed else len(v) - 1):
        k = arc_at.get(i)
        if k is None:
            msp.add_line(tuple(v[i]), tuple(following[i]), dxfattribs=attribs)
            continue
        start = math.degrees(float(arcs.start_angle[k]))
        sweep = math.degrees(float(arcs.sweep[k]))
        low, high = (start, start + sweep) if sweep > 0 else (start + sweep, start)
        msp.add_arc(tuple(arcs.centre[k] * scale), float(arcs.radius[k]) * scale, low, high,
                    dxfattribs=attribs)


def _readable(profile: Profile, gap: float) -> Profile:
    """*profile* without edges shorter than *gap* (mm): a reader drops them (a tiny nose arc),
    and the edges either side would no longer meet; the edge before now ends where the next
    begins, moved by at most the dropped edge's length."""
    v = profile.vertices
    keep = np.hypot(*(np.roll(v, -1, axis=0) - v).T) > gap
    if keep.all() or np.count_nonzero(keep) < 2:
        return profile
    return Profile(v[keep], profile.bulges[keep])


def add_contours(msp: Any, contours: Contours, scale: float, layer: str) -> None:
    for profile in contours.profiles:
        add_contour(msp, profile, scale, layer)
    for radius in contours.circles:
        msp.add_circle((0.0, 0.0), radius * scale, dxfattribs={"layer": layer})


def new_document(design: Any) -> Any:
    """An R2010 drawing in the design's units with camfab's layers."""
    from camfab.export.ezdxf_import import load_ezdxf

    ezdxf = load_ezdxf()
    doc = ezdxf.new("R2010", setup=["linetypes"])
    doc.header["$INSUNITS"] = INSUNITS[design.units]
    doc.header["$MEASUREMENT"] = 1 if design.units == "mm" else 0
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


def render_dxf(analysis: Analysis, plate: Plate, label: str | None = None) -> bytes:
    """The DXF file of *plate* as bytes (R2010, ASCII, no timestamps); *label* names the cam in
    the note (by default its type: "disc cam")."""
    design, geom = analysis.design, analysis.geometry
    assert geom is not None, "only disc cams have a plate outline"
    scale = 1.0 / design.mm_per_unit
    doc = new_document(design)
    msp = doc.modelspace()
    # references first, what is cut last: drawn on top where they coincide (a knife's pitch
    # curve is its profile)
    add_contour(msp, fit_arcs(geom.pitch.xy, geom.tolerance), scale, "PITCH")
    msp.add_circle((0.0, 0.0), geom.cam.base_radius * scale, dxfattribs={"layer": "BASE"})
    if geom.cam.prime_radius != geom.cam.base_radius:
        msp.add_circle((0.0, 0.0), geom.cam.prime_radius * scale, dxfattribs={"layer": "PRIME"})
    _add_marks(msp, analysis, scale, plate, label)
    if plate.toolpath is not None:
        add_contours(msp, plate.toolpath, scale, "TOOLPATH")
    add_contours(msp, plate.cut, scale, "CUT")
    return dxf_bytes(doc)


def render_development_dxf(analysis: Analysis, band: Profile, centre: Profile,
                           size: tuple[float, float]) -> bytes:
    """The DXF of a drum cam's groove developed at its surface: the groove between its walls as
    one closed contour on ``CUT`` (cut open at the seam), the roller axis's track on ``PITCH``
    (an open chain), the developed surface's rectangle (*size*, mm) on ``MARK``, and a note."""
    design = analysis.design
    scale = 1.0 / design.mm_per_unit
    doc = new_document(design)
    msp = doc.modelspace()
    width, height = size[0] * scale, size[1] * scale
    corners = [(0.0, 0.0), (width, 0.0), (width, height), (0.0, height)]
    for a, b in zip(corners, corners[1:] + corners[:1], strict=True):
        msp.add_line(a, b, dxfattribs={"layer": "MARK"})
    add_contour(msp, centre, scale, "PITCH", closed=False)
    unit = design.units
    text = [f"{design.name}: drum cam, {design.cam.rotation}, groove developed at the surface "
            f"(radius {(design.cam.radius or 0.0) * scale:.6g} {unit}), seen from outside",
            f"groove of {len(band.vertices)} lines and arcs within "
            f"{design.manufacturing.tolerance * scale:.3g} {unit}"]
    text_height = max(height * 0.03, 1e-3)
    for row, line in enumerate(text, start=1):
        msp.add_text(line, height=text_height, dxfattribs={"layer": "NOTE"}).set_placement(
            (0.0, -1.6 * row * text_height))
    add_contour(msp, band, scale, "CUT")
    return dxf_bytes(doc)


def _add_marks(msp: Any, analysis: Analysis, scale: float, plate: Plate,
               label: str | None = None) -> None:
    geom = analysis.geometry
    assert geom is not None
    rb = geom.cam.base_radius
    size = 0.15 * rb * scale
    msp.add_line((-size, 0.0), (size, 0.0), dxfattribs={"layer": "MARK"})
    msp.add_line((0.0, -size), (0.0, size), dxfattribs={"layer": "MARK"})
    # θ = 0: a tick on +Y just inside the base circle, where the follower sits
    msp.add_line((0.0, 0.6 * rb * scale), (0.0, 0.9 * rb * scale), dxfattribs={"layer": "MARK"})
    design = analysis.design
    unit = design.units
    kind = label or f"{design.cam.type} cam"
    lines = [f"{design.name}: {kind}, {design.cam.rotation}, base radius {rb * scale:.6g} "
             f"{unit}",
             f"outline of {len(plate.cut.profiles[0].vertices)} lines and arcs within "
             f"{design.manufacturing.tolerance * scale:.3g} {unit}"]
    if design.cam.shaped:
        shape = design.shape
        flank = ("straight flanks" if shape.flank_radius is None else
                 f"flank radius {shape.flank_radius * scale:.6g} {unit}")
        lines[1] = (f"exact outline of {len(plate.outline.vertices)} lines and arcs: {flank}, "
                    f"nose radius {shape.nose_radius * scale:.6g} {unit}")
    if plate.kerf > 0.0:
        lines.append(f"CUT offset for a kerf of {plate.kerf * scale:.4g} {unit}")
    cutter = design.manufacturing.cutter_radius
    if cutter > 0.0:
        lines.append(f"TOOLPATH: centre of a cutter of radius {cutter * scale:.4g} {unit}")
    height = max(rb * scale * 0.06, 1e-3)
    # below everything drawn: the profile, the pitch curve and the toolpath around them
    drawn = np.vstack((geom.outline_points(), geom.pitch.xy))
    margin = max(cutter, plate.kerf)
    left = (float(np.min(drawn[:, 0])) - margin) * scale
    low = (float(np.min(drawn[:, 1])) - margin) * scale - 1.5 * height
    for row, line in enumerate(lines, start=1):
        msp.add_text(line, height=height, dxfattribs={"layer": "NOTE"}).set_placement(
            (left, low - 1.6 * row * height))


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
