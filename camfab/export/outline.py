"""Read a made or scanned cam's outline for ``camfab inspect``: a DXF drawing or a CSV of points.

A DXF is read with ezdxf, whoever wrote it: LINE, ARC, CIRCLE, LWPOLYLINE (bulges kept as arcs),
2-D POLYLINE, and SPLINE and ELLIPSE flattened into short lines. Closed entities are contours by
themselves; the open ones are chained end to end by ezdxf's edge miner. The outline is the largest
closed contour (by area) on the layer asked for, by default ``CUT`` when the drawing has that layer
(a camfab drawing, a laser file) and every layer otherwise. Lengths are converted to millimetres
from ``$INSUNITS`` unless the units are given.

A CSV holds one point per row, in order along the outline (as a coordinate measuring machine
scans it): the columns ``x`` and ``y`` when a header names them, else the first two columns;
commas, semicolons, tabs or spaces separate the values, ``#`` starts a comment. The points are
joined by straight lines.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from camfab.errors import OutlineError
from camfab.geometry.profile import Profile

#: $INSUNITS codes -> millimetres per drawing unit (0, unitless, is absent: the caller decides).
INSUNITS_MM = {1: 25.4, 2: 304.8, 3: 1_609_344.0, 4: 1.0, 5: 10.0, 6: 1000.0, 8: 2.54e-5,
               9: 0.0254, 10: 914.4, 13: 1e-3, 14: 100.0}

#: Millimetres per unit of the ``--units`` choices.
UNITS_MM = {"mm": 1.0, "in": 25.4}

#: Ends of entities closer than this (mm) meet: a micrometre, below what any drawing or
#: measurement of a cam resolves and far above the rounding of coordinates in a DXF file.
JOIN_GAP_MM = 1e-3

#: Largest distance (mm) of the lines a SPLINE or ELLIPSE is flattened into from the curve: a
#: tenth of a micrometre, negligible against any inspection tolerance.
FLATTEN_SAGITTA_MM = 1e-4

#: Seconds the edge miner may spend chaining loose entities into loops (it backtracks); a drawing
#: that needs longer holds more than one part's outline and wants ``--layer``.
CHAIN_TIMEOUT_S = 20.0

#: Largest file read (bytes): a DXF of one cam plate or a scan of one outline is far smaller.
MAX_BYTES = 200_000_000

#: camfab's note that the CUT layer is a laser beam's path: ``CUT offset for a kerf of 0.2 mm``.
_KERF_NOTE = re.compile(r"CUT offset for a kerf of ([0-9.eE+-]+) (mm|in)")

_SPLIT = re.compile(r"[,;\t ]+")


@dataclass(frozen=True)
class Outline:
    """A cam's outline as read, in millimetres in the file's frame (not yet centred).

    Attributes
    ----------
    profile
        The largest closed contour, counter-clockwise.
    source
        What was read, for the report ("24 lines and arcs on layer CUT", "3,600 points").
    mm_per_unit
        Millimetres per unit of the file's coordinates.
    units
        How the unit was chosen ("mm from $INSUNITS", "in (--units)").
    kerf_mm
        The kerf a camfab drawing says its CUT layer is offset for, else None.
    points_only
        True when the outline is a chain of straight lines through points (a scan, a flattened
        curve), False when it has arcs (a CAD drawing of lines and arcs).
    """

    profile: Profile
    source: str
    mm_per_unit: float
    units: str
    kerf_mm: float | None
    points_only: bool


def read_outline(path: Path, *, units: str | None = None, default_units: str = "mm",
                 layer: str | None = None) -> Outline:
    """The outline in the DXF or CSV file *path* (by its suffix; anything but ``.dxf`` is read
    as CSV).

    Parameters
    ----------
    units
        ``mm`` or ``in``: the unit of the file's coordinates, over its ``$INSUNITS``.
    default_units
        The unit when neither *units* nor ``$INSUNITS`` says (a CSV, a unitless DXF).
    layer
        DXF: read only this layer (default: ``CUT`` when present, else every layer).

    Raises
    ------
    OutlineError
        The file is missing or unreadable, or holds no closed outline.
    """
    name = str(path)
    try:
        size = path.stat().st_size
        if size > MAX_BYTES:
            raise OutlineError(name, f"is too large for an outline ({size:,} bytes)")
        data = path.read_bytes()
    except IsADirectoryError:
        raise OutlineError(name, "is a folder, not a DXF or CSV file") from None
    except FileNotFoundError:
        raise OutlineError(name, "no such file") from None
    except OSError as exc:
        raise OutlineError(name, f"cannot be read ({exc.strerror or exc})") from None
    if path.suffix.lower() == ".dxf":
        return _read_dxf(name, data, units, default_units, layer)
    if layer is not None:
        raise OutlineError(name, "--layer applies to DXF files only")
    return _read_csv(name, data, units or default_units)


# -- CSV --------------------------------------------------------------------------------------

def _read_csv(name: str, data: bytes, units: str) -> Outline:
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise OutlineError(name, "is not a text file (expected a CSV of x, y points)") from None
    columns = (0, 1)
    rows: list[tuple[float, float]] = []
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        fields = [f.strip().strip('"') for f in _SPLIT.split(line) if f.strip()]
        if not rows and not _numeric(fields[0]):
            columns = _header_columns(name, number, fields)
            continue
        if len(fields) <= max(columns):
            raise OutlineError(name, f"expected {max(columns) + 1} values (x, y), got "
                               f"{len(fields)}: {raw.strip()!r}", number)
        try:
            x, y = float(fields[columns[0]]), float(fields[columns[1]])
        except ValueError:
            raise OutlineError(name, f"not a pair of numbers: {raw.strip()!r}", number) from None
        if not (math.isfinite(x) and math.isfinite(y)):
            raise OutlineError(name, f"not a pair of finite numbers: {raw.strip()!r}", number)
        rows.append((x, y))
    if len(rows) < 3:
        raise OutlineError(name, f"holds {len(rows)} point(s); an outline needs at least 3 "
                           "(one x, y point per row, in order along the outline)")
    scale = UNITS_MM[units]
    try:
        profile = Profile.from_points(np.array(rows) * scale).ccw()
    except ValueError as exc:
        raise OutlineError(name, str(exc)) from None
    if len(profile.vertices) < 3 or profile.area == 0.0:
        raise OutlineError(name, "the points enclose no area (not a closed outline)")
    return Outline(profile, f"{len(rows):,} points joined by straight lines", scale, units,
                   None, True)


def _numeric(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _header_columns(name: str, number: int, fields: list[str]) -> tuple[int, int]:
    """The x and y columns named in a header row (``x``, ``X_mm``, ``x (mm)``), else 0 and 1."""
    keys = [re.sub(r"[^a-z].*$", "", f.lower()) for f in fields]
    if "x" in keys and "y" in keys:
        return keys.index("x"), keys.index("y")
    if len(fields) < 2:
        raise OutlineError(name, f"not a pair of numbers: {' '.join(fields)!r}", number)
    return 0, 1


# -- DXF --------------------------------------------------------------------------------------

def _read_dxf(name: str, data: bytes, units: str | None, default_units: str,
              layer: str | None) -> Outline:
    import io

    from camfab.export.ezdxf_import import load_ezdxf

    ezdxf = load_ezdxf()
    from ezdxf.lldxf.const import DXFError

    try:
        if data[:22] == b"AutoCAD Binary DXF\r\n\x1a\x00":
            raise OutlineError(name, "is a binary DXF; save it as an ASCII DXF")
        doc = ezdxf.read(io.StringIO(data.decode("utf-8", errors="replace")))
    except (DXFError, ValueError, TypeError) as exc:
        if isinstance(exc, OutlineError):
            raise
        raise OutlineError(name, f"is not a readable DXF file ({exc})") from None
    msp = doc.modelspace()
    code = int(doc.header.get("$INSUNITS", 0) or 0)
    if units is not None:
        mm_per_unit, unit_text = UNITS_MM[units], f"{units} (--units)"
    elif code in INSUNITS_MM:
        mm_per_unit, unit_text = INSUNITS_MM[code], f"{_unit_name(code)} ($INSUNITS {code})"
    else:
        mm_per_unit, unit_text = UNITS_MM[default_units], f"{default_units} (no $INSUNITS)"
    layers = {e.dxf.layer.upper() for e in msp}
    if layer is None:
        chosen = "CUT" if "CUT" in layers else None
    else:
        if layer.upper() not in layers:
            shown = ", ".join(sorted(layers)) or "none"
            raise OutlineError(name, f"has no entities on layer '{layer}' (layers: {shown})")
        chosen = layer
    types = "LINE ARC CIRCLE LWPOLYLINE POLYLINE SPLINE ELLIPSE"
    query = types if chosen is None else f'{types}[layer=="{chosen}"]i'
    entities = list(msp.query(query))
    where = "on every layer" if chosen is None else f"on layer {chosen}"
    candidates = _contours(name, entities, mm_per_unit, where)
    if not candidates:
        raise OutlineError(name, f"has no closed contour {where} (lines, arcs, polylines, "
                           "circles or splines meeting end to end)")
    profile, count = max(candidates, key=lambda c: c[0].area)
    return Outline(profile.ccw(), f"the largest closed contour {where}: {count} entities, "
                   f"{len(profile.vertices)} lines and arcs", mm_per_unit, unit_text,
                   _kerf_note(msp, mm_per_unit), not bool(np.any(profile.bulges != 0.0)))


def _unit_name(code: int) -> str:
    return {1: "in", 2: "ft", 3: "mi", 4: "mm", 5: "cm", 6: "m", 8: "µin", 9: "mil", 10: "yd",
            13: "µm", 14: "dm"}[code]


def _contours(name: str, entities: list[Any], mm_per_unit: float,
              where: str) -> list[tuple[Profile, int]]:
    """Every closed contour of *entities* (mm), with how many entities make it."""
    from ezdxf import edgeminer, edgesmith

    sagitta = FLATTEN_SAGITTA_MM / mm_per_unit
    found: list[tuple[Profile, int]] = []
    loose = []
    for entity in entities:
        closed = _closed_points(entity, sagitta)
        if closed is None:
            loose.append(entity)
        elif len(closed) >= 2:
            _keep(found, closed, mm_per_unit, 1)
    gap = JOIN_GAP_MM / mm_per_unit
    # numbered for this read, as camfab.export.dxf.layer_loops does: the same loops every time
    edges = [edge._replace(id=number) for number, edge in enumerate(
        edgesmith.edges_from_entities_2d(loose, gap_tol=gap), start=1)]
    if not edges:
        return found
    try:
        loops = edgeminer.find_all_loops(edgeminer.Deposit(edges, gap_tol=gap),
                                         timeout=CHAIN_TIMEOUT_S)
    except TimeoutError:
        raise OutlineError(name, f"has too many loose entities {where} to chain into an "
                           "outline; choose the outline's layer with --layer") from None
    for loop in loops:
        polyline = edgesmith.lwpolyline_from_chain(loop, max_sagitta=sagitta)
        _keep(found, np.array(list(polyline.get_points("xyb")), dtype=np.float64),
              mm_per_unit, len(loop))
    return found


def _keep(found: list[tuple[Profile, int]], points: np.ndarray, mm_per_unit: float,
          count: int) -> None:
    try:
        profile = Profile.from_points(points[:, :2] * mm_per_unit, points[:, 2])
    except ValueError:
        return
    if len(profile.vertices) >= 2 and profile.area > 0.0:
        found.append((profile, count))


def _closed_points(entity: Any, sagitta: float) -> np.ndarray | None:
    """(N, 3) x, y, bulge of a closed entity (a contour by itself), or None for an open one."""
    kind = entity.dxftype()
    if kind == "CIRCLE":
        cx, cy = entity.dxf.center.x, entity.dxf.center.y
        r = entity.dxf.radius
        return np.array([[cx + r, cy, 1.0], [cx - r, cy, 1.0]])
    if kind == "LWPOLYLINE" and entity.closed:
        return np.array(list(entity.get_points("xyb")), dtype=np.float64)
    if kind == "POLYLINE" and entity.is_closed and entity.is_2d_polyline:
        return np.array([(v.dxf.location.x, v.dxf.location.y, v.dxf.bulge)
                         for v in entity.vertices], dtype=np.float64)
    if kind == "SPLINE" and entity.closed:
        return _flat(entity.flattening(sagitta))
    if kind == "ELLIPSE" and _full_turn(entity):
        return _flat(entity.flattening(sagitta))
    return None


def _full_turn(ellipse: Any) -> bool:
    span = (ellipse.dxf.end_param - ellipse.dxf.start_param) % (2 * math.pi)
    return span < 1e-9 or span > 2 * math.pi - 1e-9


def _flat(points: Any) -> np.ndarray:
    xy = np.array([(p.x, p.y) for p in points], dtype=np.float64)
    return np.column_stack((xy, np.zeros(len(xy))))


def _kerf_note(msp: Any, mm_per_unit: float) -> float | None:
    """The kerf (mm) a camfab drawing's NOTE says its CUT layer is offset for."""
    for text in msp.query("TEXT MTEXT"):
        content = text.dxf.text if text.dxftype() == "TEXT" else text.text
        match = _KERF_NOTE.search(content or "")
        if match:
            return float(match.group(1)) * UNITS_MM.get(match.group(2), mm_per_unit)
    return None
