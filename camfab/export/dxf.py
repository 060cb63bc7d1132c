"""``NAME.dxf``: the cam plate for laser and CNC (SPEC §5), written with ezdxf.

Everything to be cut is on layer ``CUT`` as closed LWPOLYLINEs of lines and arcs (bulges) or
CIRCLEs — never SPLINE — in the design's units with ``$INSUNITS`` set. The outline is the
tolerance-sampled profile fitted with arcs, so each contour holds tens of entities, not thousands
of tiny segments. Reference geometry goes on ``PITCH``, ``BASE``, ``PRIME``, ``MARK`` and ``NOTE``.
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
    from camfab.pipeline import Analysis


#: Layer name -> (ACI colour, linetype): CUT red, references in muted colours.
LAYERS = {
    "CUT": (1, "CONTINUOUS"),
    "PITCH": (5, "DASHED"),
    "BASE": (8, "CONTINUOUS"),
    "PRIME": (8, "DASHDOT"),
    "MARK": (3, "CONTINUOUS"),
    "NOTE": (7, "CONTINUOUS"),
}

#: $INSUNITS codes of the design units.
INSUNITS = {"mm": 4, "in": 1}


def bore_contour(diameter: float, keyway: tuple[float, float] | None) -> Profile | None:
    """The bore as a closed contour (mm): None for a plain round bore (a CIRCLE is written), or
    the circle with a keyway of (width, depth) cut on +Y, the depth measured from the bore's top."""
    if keyway is None:
        return None
    r = diameter / 2.0
    width, depth = keyway
    half = width / 2.0
    foot = math.sqrt(max(r * r - half * half, 0.0))
    top = r + depth
    # around the hole: up the keyway's right side, across, down its left side, round the bottom
    # of the bore back to the start in two arcs (each under half a circle)
    sweep = 2.0 * math.pi - 2.0 * math.asin(min(half / r, 1.0))
    vertices = np.array([[half, foot], [half, top], [-half, top], [-half, foot], [0.0, -r]])
    bulge = math.tan(sweep / 8.0)
    return Profile(vertices, np.array([0.0, 0.0, 0.0, bulge, bulge]))


def _add_contour(msp: Any, profile: Profile, scale: float, layer: str) -> None:
    points = [(float(x) * scale, float(y) * scale, float(b))
              for (x, y), b in zip(profile.vertices, profile.bulges, strict=True)]
    msp.add_lwpolyline(points, format="xyb", close=True, dxfattribs={"layer": layer})


def cut_outline(analysis: Analysis) -> Profile:
    """The cam outline as it is written: the profile fitted with arcs (mm).

    The fit may stray as far as the profile's own sampling tolerance (half the design tolerance,
    less where the pressure angle is steep), so the two together stay within the tolerance and
    the follower's lift error with them.
    """
    geom = analysis.geometry
    assert geom is not None
    return fit_arcs(geom.profile.vertices, geom.tolerance)


def render_dxf(analysis: Analysis, outline: Profile | None = None) -> bytes:
    """The DXF file as bytes (R2010, ASCII, no timestamps)."""
    import ezdxf

    design, geom = analysis.design, analysis.geometry
    assert geom is not None, "only disc cams have a plate outline"
    scale = 1.0 / design.mm_per_unit
    doc = ezdxf.new("R2010", setup=["linetypes"])
    doc.header["$INSUNITS"] = INSUNITS[design.units]
    doc.header["$MEASUREMENT"] = 1 if design.units == "mm" else 0
    for name, (colour, linetype) in LAYERS.items():
        doc.layers.add(name, color=colour, linetype=linetype)
    msp = doc.modelspace()
    if outline is None:
        outline = cut_outline(analysis)
    _add_contour(msp, outline, scale, "CUT")
    cam = design.cam
    if cam.bore is not None:
        keyway = None if cam.keyway is None else (cam.keyway.width, cam.keyway.depth)
        hole = bore_contour(cam.bore, keyway)
        if hole is None:
            msp.add_circle((0.0, 0.0), cam.bore / 2.0 * scale, dxfattribs={"layer": "CUT"})
        else:
            _add_contour(msp, hole, scale, "CUT")
    _add_contour(msp, fit_arcs(geom.pitch.xy, geom.tolerance), scale, "PITCH")
    msp.add_circle((0.0, 0.0), geom.cam.base_radius * scale, dxfattribs={"layer": "BASE"})
    if geom.cam.prime_radius != geom.cam.base_radius:
        msp.add_circle((0.0, 0.0), geom.cam.prime_radius * scale, dxfattribs={"layer": "PRIME"})
    _add_marks(msp, analysis, scale, len(outline.vertices))
    stream = io.StringIO()
    doc.write(stream)
    return _strip_volatile(stream.getvalue()).encode("utf-8")


def _add_marks(msp: Any, analysis: Analysis, scale: float, entities: int) -> None:
    geom = analysis.geometry
    assert geom is not None
    rb = geom.cam.base_radius
    size = 0.15 * rb * scale
    msp.add_line((-size, 0.0), (size, 0.0), dxfattribs={"layer": "MARK"})
    msp.add_line((0.0, -size), (0.0, size), dxfattribs={"layer": "MARK"})
    # θ = 0: a tick on +Y just inside the base circle, where the follower sits
    msp.add_line((0.0, 0.6 * rb * scale), (0.0, 0.9 * rb * scale), dxfattribs={"layer": "MARK"})
    design = analysis.design
    text = (f"{design.name}: disc cam, {design.cam.rotation}, base radius "
            f"{rb * scale:.6g} {design.units}; outline of {entities} lines and arcs within "
            f"{design.manufacturing.tolerance * scale:.3g} {design.units}")
    height = max(rb * scale * 0.06, 1e-3)
    low = float(np.min(geom.profile.vertices[:, 1])) * scale
    msp.add_text(text, height=height, dxfattribs={"layer": "NOTE"}).set_placement(
        (-float(np.max(np.abs(geom.profile.vertices[:, 0]))) * scale, low - 3 * height))


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
    """The largest closed contour on layer CUT of a DXF (the cam outline), in mm."""
    import ezdxf

    doc = ezdxf.read(io.StringIO(data.decode("utf-8")))
    best: Profile | None = None
    entity: Any
    for entity in doc.modelspace().query('LWPOLYLINE[layer=="CUT"]'):
        points = np.array(list(entity.get_points("xyb")), dtype=np.float64)
        profile = Profile(points[:, :2] * mm_per_unit, points[:, 2])
        if best is None or profile.area > best.area:
            best = profile
    if best is None:
        raise ValueError("the DXF has no closed contour on layer CUT")
    return best
