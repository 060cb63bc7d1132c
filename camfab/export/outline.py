"""Read a made or scanned cam's outline for ``camfab inspect``: a DXF drawing or a CSV of points.

A DXF is read with ezdxf, whoever wrote it (through its recover path, which repairs what it can
of a damaged file: :func:`_parse_dxf`): LINE, ARC, CIRCLE, LWPOLYLINE (bulges kept as arcs),
2-D POLYLINE, and SPLINE and ELLIPSE flattened into short lines. Closed entities (and open
polylines whose ends meet) are contours by themselves; the open ones are chained end to end
(:mod:`camfab.geometry.chains`; ezdxf's edge miner where three or more meet at a point). The
outline is the largest closed contour (by area) on the layer asked for, by default ``CUT`` when
the drawing has that layer (a camfab drawing, a laser file) and every layer otherwise. Lengths
are converted to millimetres from ``$INSUNITS`` unless the units are given.

A CSV holds one point per row, in order along the outline (as a coordinate measuring machine
scans it): the columns ``x`` and ``y`` when a header names them, else the first two columns;
commas, semicolons, tabs or spaces separate the values (with semicolons or tabs, a comma may be
the decimal mark), ``#`` starts a comment. The points are joined by straight lines.

Both are read within limits, so that a bad file is refused at once rather than read for minutes:
a regular file of at most :data:`MAX_BYTES`; a DXF of at most :data:`MAX_DXF_ENTITIES` entities
and :data:`MAX_DXF_TAGS` group codes; an outline of at most :data:`MAX_POINTS` points, between
:data:`MIN_OUTLINE_MM` and :data:`MAX_OUTLINE_MM` across, within :data:`MAX_COORDINATE_MM` of the
origin. Every number is checked finite, every radius not negative, before anything is computed
from it; a refusal names the file and the line or entity.
"""

from __future__ import annotations

import logging
import math
import re
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from camfab.arrays import Array
from camfab.curves.profile import Profile
from camfab.errors import OutlineError

#: $INSUNITS codes -> millimetres per drawing unit, every code of the DXF reference (0, unitless,
#: is absent: the caller decides; the astronomical ones fail the size limits, with a message).
INSUNITS_MM = {1: 25.4, 2: 304.8, 3: 1_609_344.0, 4: 1.0, 5: 10.0, 6: 1000.0, 7: 1e6,
               8: 2.54e-5, 9: 0.0254, 10: 914.4, 11: 1e-7, 12: 1e-6, 13: 1e-3, 14: 100.0,
               15: 1e4, 16: 1e5, 17: 1e12, 18: 1.495978707e14, 19: 9.4607304725808e18,
               20: 3.0856775814913673e19, 21: 1.2e6 / 3937.0, 22: 1e5 / 3937.0,
               23: 3.6e6 / 3937.0, 24: 6.336e9 / 3937.0}
_INSUNITS_NAMES = {1: "in", 2: "ft", 3: "mi", 4: "mm", 5: "cm", 6: "m", 7: "km", 8: "µin",
                   9: "mil", 10: "yd", 11: "Å", 12: "nm", 13: "µm", 14: "dm", 15: "dam",
                   16: "hm", 17: "Gm", 18: "au", 19: "ly", 20: "pc", 21: "US survey ft",
                   22: "US survey in", 23: "US survey yd", 24: "US survey mi"}

#: Millimetres per unit of the ``--units`` choices.
UNITS_MM = {"mm": 1.0, "in": 25.4}

#: Ends of entities closer than this (mm) meet: a micrometre, below what any drawing or
#: measurement of a cam resolves and far above the rounding of coordinates in a DXF file.
JOIN_GAP_MM = 1e-3

#: Largest distance (mm) of the lines a SPLINE or ELLIPSE is flattened into from the curve: a
#: tenth of a micrometre, negligible against any inspection tolerance; or, for a curve more
#: than 100 mm across, this share of its size (a circle is then some 2,000 lines whatever its
#: size, instead of 600,000 for one of a kilometre).
FLATTEN_SAGITTA_MM = 1e-4
FLATTEN_SHARE = 1e-6

#: Seconds ezdxf's edge miner may spend finding the loops of entities that meet three or more at
#: a point (a search that can branch without end); a drawing that needs longer holds more than
#: one part's outline on the layer and wants ``--layer``.
CHAIN_TIMEOUT_S = 2.0

#: Most pieces of such tangled parts handed to the edge miner; more are refused at once.
MAX_TANGLED_PIECES = 2_000

#: Largest outline file (bytes). A cam's DXF or a dense scan of one outline is a few megabytes.
MAX_BYTES = 20_000_000

#: Most entities (and table entries and objects) a DXF may hold, and most group codes: ezdxf
#: reads some 15,000 entities or 150,000 group codes a second on one core, so these keep the
#: reading to a second or two. A cam's drawing holds hundreds of entities; a scan drawn as lines
#: a few thousand; a polyline of 100,000 points some 200,000 group codes.
MAX_DXF_ENTITIES = 20_000
MAX_DXF_TAGS = 250_000

#: Most control and fit points of the SPLINEs read, and their largest degree: ezdxf flattens
#: some 6,000 control points a second, and a spline through fit points first solves for its
#: control points (time and memory growing as their square). CAD programs draw a cam's spline
#: with tens to hundreds of points, of degree 3; none goes past degree 11.
MAX_SPLINE_POINTS = 2_000
MAX_SPLINE_DEGREE = 11

#: Most lines of a CSV, and most points of an outline (a CSV's rows, a DXF outline's vertices):
#: a scan every 2 µm along a 400 mm outline.
MAX_CSV_LINES = 1_000_000
MAX_POINTS = 200_000

#: Smallest outline (mm across): a thousand join gaps; the smallest cams (a watch's heart cam)
#: are a few millimetres across. A smaller one is nearly always a drawing read in a wrong unit.
MIN_OUTLINE_MM = 1.0

#: Largest outline (mm across), 10 m, and farthest coordinate from the origin (mm), 1 km: beyond
#: any cam, and they bound the points the outline is sampled into.
MAX_OUTLINE_MM = 10_000.0
MAX_COORDINATE_MM = 1e6

#: camfab's note that the CUT layer is a laser beam's path: ``CUT offset for a kerf of 0.2 mm``.
_KERF_NOTE = re.compile(r"CUT offset for a kerf of\s*(\S*)\s*(\S*)")

#: A structure tag of a DXF: group code 0 and a name (an entity, table entry, object, section).
_DXF_OBJECT = re.compile(rb"(?m)^[ \t]*0[ \t]*\r?\n[ \t]*[A-Za-z_$]")

#: The tag that opens a section of a DXF: a file without one holds no drawing (ezdxf's recover
#: path reads anything else into an empty one).
_DXF_SECTION = re.compile(rb"(?mi)^[ \t]*0[ \t]*\r?\n[ \t]*SECTION[ \t]*\r?$")

#: What ezdxf raises on a damaged file or entity (it has no single base for them).
_DXF_FAILURES: tuple[type[BaseException], ...] = (ValueError, TypeError, IndexError, KeyError,
                                                  AttributeError, ArithmeticError, RecursionError)

#: DXF entities an outline is read from.
OUTLINE_TYPES = ("LINE", "ARC", "CIRCLE", "LWPOLYLINE", "POLYLINE", "SPLINE", "ELLIPSE")

_SPLIT = re.compile(r"[, ]+")
_SPLIT_STRICT = re.compile(r"\s*[;\t]\s*")


@dataclass(frozen=True)
class KerfNote:
    """camfab's note in a drawing that its CUT layer is a laser beam's path, as written.

    Attributes
    ----------
    text
        The note's text.
    entity
        Which entity holds it ("TEXT #2F on layer NOTE").
    """

    text: str
    entity: str

    def kerf_mm(self, file: str) -> float:
        """The kerf (mm) the note declares.

        Raises
        ------
        OutlineError
            The note is damaged: no number of millimetres or inches after "a kerf of".
        """
        match = _KERF_NOTE.search(self.text)
        number, unit = (match.group(1), match.group(2)) if match else ("", "")
        try:
            value = float(number)
        except ValueError:
            value = math.nan
        if unit not in UNITS_MM or not math.isfinite(value):
            raise OutlineError(file, f"{self.entity}: the note {self.text.strip()!r} gives no "
                               "kerf in mm or in; give the kerf with --kerf")
        return value * UNITS_MM[unit]


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
    kerf_note
        A camfab drawing's note that its CUT layer is offset for a kerf, else None.
    points_only
        True when the outline is a chain of straight lines through points (a scan, a flattened
        curve), False when it has arcs (a CAD drawing of lines and arcs).
    """

    profile: Profile
    source: str
    mm_per_unit: float
    units: str
    kerf_note: KerfNote | None
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
    InputFileError
        The file is missing, not a regular file, or larger than :data:`MAX_BYTES`.
    OutlineError
        The file is unreadable, over a limit, or holds no usable closed outline.
    """
    from camfab.files import read_bounded

    name = str(path)
    data = read_bounded(path, MAX_BYTES, "a DXF or CSV outline")
    if path.suffix.lower() == ".dxf":
        return _read_dxf(name, data, units, default_units, layer)
    if layer is not None:
        raise OutlineError(name, "--layer applies to DXF files only")
    return _read_csv(name, data, units or default_units)


# -- the outline --------------------------------------------------------------------------------

def _checked(name: str, profile: Profile, unit_text: str) -> Profile:
    """*profile* (mm) when its size and number of points are within the limits."""
    if len(profile.vertices) > MAX_POINTS:
        raise OutlineError(name, f"the outline has {len(profile.vertices):,} points; inspect "
                           f"takes at most {MAX_POINTS:,}")
    extent = _extent_points(profile)
    far = float(np.max(np.abs(extent)))
    if not far <= MAX_COORDINATE_MM:
        raise OutlineError(name, f"the outline reaches {far:.3g} mm from the origin (coordinates "
                           f"in {unit_text}); an outline lies within {MAX_COORDINATE_MM:,.0f} mm "
                           "of it")
    across = float(np.max(np.ptp(extent, axis=0)))
    if across < MIN_OUTLINE_MM:
        raise OutlineError(name, f"the outline is only {across:.3g} mm across (coordinates in "
                           f"{unit_text}); an outline is at least {MIN_OUTLINE_MM:g} mm across: "
                           "is the unit right? (--units)")
    if across > MAX_OUTLINE_MM:
        raise OutlineError(name, f"the outline is {across:.3g} mm across (coordinates in "
                           f"{unit_text}); an outline is at most {MAX_OUTLINE_MM:,.0f} mm across:"
                           " is the unit right? (--units)")
    return profile


def _extent_points(profile: Profile) -> Array:
    """Points (mm) whose bounding box is the contour's: its vertices, the middle of each arc,
    and for an arc over half a turn the four ends of its circle's axes."""
    arcs = profile.arcs()
    middle = arcs.start_angle + 0.5 * arcs.sweep
    with np.errstate(invalid="ignore", over="ignore"):
        apex = arcs.centre + arcs.radius[:, None] * np.column_stack((np.cos(middle),
                                                                     np.sin(middle)))
        wide = np.abs(arcs.sweep) > math.pi
        axes = [arcs.centre[wide] + arcs.radius[wide, None] * np.array(d)
                for d in ((1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0))]
    return np.concatenate([profile.vertices, apex, *axes])


# -- CSV ----------------------------------------------------------------------------------------

def _read_csv(name: str, data: bytes, units: str) -> Outline:
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data[:exc.start].count(b"\n") + 1
        raise OutlineError(name, "is not a text file (expected a CSV of x, y points)",
                           line) from None
    if text.count("\n") > MAX_CSV_LINES:
        raise OutlineError(name, f"has more than {MAX_CSV_LINES:,} lines; a CSV outline holds at "
                           f"most {MAX_POINTS:,} points")
    columns = (0, 1)
    pairs: list[tuple[float, float]] = []
    lines: list[int] = []
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        fields = _fields(line)
        if not fields:
            raise OutlineError(name, f"not a pair of numbers: {raw.strip()!r}", number)
        if not pairs and not _numeric(fields[0]):
            columns = _header_columns(name, number, fields)
            continue
        if len(fields) <= max(columns):
            raise OutlineError(name, f"expected {max(columns) + 1} values (x, y), got "
                               f"{len(fields)}: {raw.strip()!r}", number)
        try:
            pairs.append((float(fields[columns[0]]), float(fields[columns[1]])))
        except ValueError:
            raise OutlineError(name, f"not a pair of numbers: {raw.strip()!r}", number) from None
        lines.append(number)
        if len(pairs) > MAX_POINTS:
            raise OutlineError(name, f"holds more than {MAX_POINTS:,} points; inspect takes at "
                               "most that many", number)
    if len(pairs) < 3:
        raise OutlineError(name, f"holds {len(pairs)} point(s); an outline needs at least 3 "
                           "(one x, y point per row, in order along the outline)")
    scale = UNITS_MM[units]
    xy = np.array(pairs, dtype=np.float64)
    with np.errstate(over="ignore"):
        mm = xy * scale
    bad = np.flatnonzero(~np.isfinite(mm).all(axis=1))
    if bad.size:
        k = int(bad[0])
        raise OutlineError(name, f"not a pair of finite numbers: {xy[k, 0]:g}, {xy[k, 1]:g}",
                           lines[k])
    far = np.flatnonzero(np.abs(mm).max(axis=1) > MAX_COORDINATE_MM)
    if far.size:
        k = int(far[0])
        raise OutlineError(name, f"the point {xy[k, 0]:g}, {xy[k, 1]:g} lies "
                           f"{float(np.abs(mm[k]).max()):.3g} mm from the origin (coordinates in "
                           f"{units}); an outline lies within {MAX_COORDINATE_MM:,.0f} mm of it",
                           lines[k])
    try:
        profile = Profile.from_points(mm).ccw()
    except ValueError as exc:
        raise OutlineError(name, str(exc)) from None
    if len(profile.vertices) < 3 or profile.area == 0.0:
        raise OutlineError(name, "the points enclose no area (not a closed outline)")
    return Outline(_checked(name, profile, units), f"{len(pairs):,} points joined by straight "
                   "lines", scale, units, None, True)


def _fields(line: str) -> list[str]:
    """The values of a CSV line: separated by semicolons or tabs when it has them (a comma is
    then a decimal mark), else by commas or spaces."""
    if ";" in line or "\t" in line:
        fields = [f.strip('"').replace(",", ".") for f in _SPLIT_STRICT.split(line)]
    else:
        fields = [f.strip('"') for f in _SPLIT.split(line)]
    return [f for f in fields if f]


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


# -- DXF: the file ------------------------------------------------------------------------------

def _read_dxf(name: str, data: bytes, units: str | None, default_units: str,
              layer: str | None) -> Outline:
    with _quiet_ezdxf():
        return _read_drawing(name, data, units, default_units, layer)


@contextmanager
def _quiet_ezdxf() -> Iterator[None]:
    """ezdxf logs what it repairs in a damaged file ("non-unique entity handle") and, with no
    handler set up, Python prints that on stderr; inspect's stderr is its one line."""
    logger = logging.getLogger("ezdxf")
    level = logger.level
    logger.setLevel(logging.CRITICAL + 1)
    try:
        yield
    finally:
        logger.setLevel(level)


def _read_drawing(name: str, data: bytes, units: str | None, default_units: str,
                  layer: str | None) -> Outline:
    _check_dxf_size(name, data)
    doc, dropped = _parse_dxf(name, data)
    mm_per_unit, unit_text = _dxf_units(name, doc, units, default_units)
    msp = doc.modelspace()
    entities, chosen = _layer_entities(name, msp, layer)
    where = "on every layer" if chosen is None else f"on layer {chosen}"
    _check_entities(name, entities, mm_per_unit)
    _check_splines(name, entities)
    candidates = _contours(name, entities, mm_per_unit, where)
    if not candidates:
        said = f"; ezdxf's audit of the damaged file: {_said(dropped[0])}" if dropped else ""
        raise OutlineError(name, f"has no closed contour {where} (lines, arcs, polylines, "
                           f"circles or splines meeting end to end){said}")
    profile, count = max(candidates, key=lambda c: c[0].area)
    profile = _checked(name, profile.ccw(), unit_text)
    return Outline(profile, f"the largest closed contour {where}: {count} entities, "
                   f"{len(profile.vertices)} lines and arcs", mm_per_unit, unit_text,
                   _kerf_note(msp), not bool(np.any(profile.bulges != 0.0)))


def _check_dxf_size(name: str, data: bytes) -> None:
    """Refuse a binary DXF, and one with more entities or group codes than are read in a few
    seconds, before it is parsed."""
    if data[:22] == b"AutoCAD Binary DXF\r\n\x1a\x00":
        raise OutlineError(name, "is a binary DXF; save it as an ASCII DXF")
    if _DXF_SECTION.search(data) is None:
        raise OutlineError(name, "is not a readable DXF file (it has no SECTION)")
    tags = max(data.count(b"\n"), data.count(b"\r")) // 2
    if tags > MAX_DXF_TAGS:
        raise OutlineError(name, f"holds {tags:,} group codes; inspect reads a DXF of at most "
                           f"{MAX_DXF_TAGS:,} (save only the outline's layer, or its outline as "
                           "one polyline)")
    objects = sum(1 for _ in _DXF_OBJECT.finditer(data))
    if objects > MAX_DXF_ENTITIES:
        raise OutlineError(name, f"holds {objects:,} entities and objects; inspect reads a DXF of "
                           f"at most {MAX_DXF_ENTITIES:,} (save only the outline's layer, or its "
                           "outline as one polyline)")


def _parse_dxf(name: str, data: bytes) -> tuple[Any, list[str]]:
    """The drawing in *data*, and what ezdxf's audit said of the outline's kinds of entity (a
    damaged one removed), for a refusal to tell.

    It is read through ezdxf's recover path: that repairs what it can of a damaged file (group
    codes out of place, a structure tag missing, an invalid handle or number), decodes the text
    as the file's version and code page say (bytes that are not that, as U+FFFD) and audits what
    it read. What that cannot read (its audit trips on a damaged table or layout the outline
    does not need) ezdxf's plain reader may; a file neither reads is refused."""
    import io

    from camfab.export.ezdxf_import import load_ezdxf

    ezdxf = load_ezdxf()
    from ezdxf import recover
    from ezdxf.lldxf.const import DXFError

    # AssertionError: ezdxf checks some of what it reads with assert
    failures = (DXFError, StopIteration, AssertionError, *_DXF_FAILURES)
    try:
        doc, auditor = recover.read(io.BytesIO(data), errors="replace")
    except failures as exc:
        refusal = OutlineError(name, f"is not a readable DXF file ({_said(exc)})")
    else:
        said = [entry.message for entry in (*auditor.errors, *auditor.fixes)]
        return doc, [text for text in said if any(kind in text for kind in OUTLINE_TYPES)]
    try:
        return ezdxf.read(io.StringIO(data.decode("utf-8", errors="replace"))), []
    except failures:
        raise refusal from None


def _dxf_units(name: str, doc: Any, units: str | None, default_units: str) -> tuple[float, str]:
    """Millimetres per drawing unit, and how they were chosen: ``--units``, else ``$INSUNITS``,
    else the default."""
    if units is not None:
        return UNITS_MM[units], f"{units} (--units)"
    raw = doc.header.get("$INSUNITS", 0)
    try:
        code = int(raw or 0)
    except (TypeError, ValueError):
        code = -1
    if code == 0:
        return UNITS_MM[default_units], f"{default_units} (no $INSUNITS)"
    if code not in INSUNITS_MM:
        raise OutlineError(name, f"$INSUNITS is {raw!r}, not a unit of the DXF reference; give "
                           "the file's unit with --units")
    return INSUNITS_MM[code], f"{_INSUNITS_NAMES[code]} ($INSUNITS {code})"


#: The layer of a groove cam's walls in camfab's drawings (and the refusal of such a drawing:
#: its cam is the groove, which inspect does not measure from a DXF).
GROOVE_LAYER = "POCKET"
GROOVE_REFUSAL = ("is a groove cam's drawing: its cam is the groove between the two walls on "
                  "layer POCKET, and its CUT layer holds the plate's blank, not a cam outline; "
                  "give --design DESIGN.yaml to measure the groove's two walls against it (or "
                  "--layer with the layer of an outline to read that instead)")


def _layer_entities(name: str, msp: Any, layer: str | None) -> tuple[list[Any], str | None]:
    """The outline entities on *layer* (any case; default ``CUT`` when the drawing has it, else
    every layer), and the layer chosen. Matched in Python, never through a query string, so a
    layer name may hold any character."""
    # an entity of a type ezdxf does not know (a damaged file's) has no layer: not drawn
    every = [e for e in msp if e.dxf.is_supported("layer")]
    layers = {str(e.dxf.layer).upper(): str(e.dxf.layer) for e in every}
    if layer is None:
        chosen = "CUT" if "CUT" in layers else None
    elif layer.upper() in layers:
        chosen = layer
    else:
        shown = sorted(layers.values(), key=str.upper)
        listed = ", ".join(repr(n) for n in shown[:20]) or "none"
        more = f" and {len(shown) - 20} more" if len(shown) > 20 else ""
        raise OutlineError(name, f"has no entities on layer {layer!r} (layers: {listed}{more})")
    wanted = None if chosen is None else chosen.upper()
    if wanted in (None, "CUT", GROOVE_LAYER) and any(
            e.dxftype() in OUTLINE_TYPES and str(e.dxf.layer).upper() == GROOVE_LAYER
            for e in every):
        # a groove cam's drawing: CUT holds the plate's blank (a circle about the cam's centre,
        # whose "lift" is none), the cam is the groove; never measure the one as the other
        raise OutlineError(name, GROOVE_REFUSAL)
    entities = [e for e in every if e.dxftype() in OUTLINE_TYPES
                and (wanted is None or str(e.dxf.layer).upper() == wanted)]
    return entities, chosen


def _said(error: BaseException | str) -> str:
    """What ezdxf said of a damaged file or entity (an error, or its audit's message), in at
    most 200 characters."""
    text = " ".join(str(error).split()) or type(error).__name__
    return text if len(text) <= 200 else text[:197] + "..."


def _label(entity: Any) -> str:
    """An entity as a reader of the file finds it: ``LWPOLYLINE #2F on layer CUT``."""
    return f"{entity.dxftype()} #{entity.dxf.get('handle', '?')} on layer {entity.dxf.layer}"


# -- DXF: the entities' numbers -----------------------------------------------------------------

def _check_entities(name: str, entities: list[Any], mm_per_unit: float) -> None:
    """Refuse the first entity with a number that is not finite, a negative radius, or a point
    farther than :data:`MAX_COORDINATE_MM` from the origin (all entities checked at once)."""
    numbers = [_entity_numbers(name, e) for e in entities]
    if not numbers:
        return
    points = np.concatenate([p for p, _, _ in numbers])
    others = np.concatenate([o for _, o, _ in numbers])
    owner = np.repeat(np.arange(len(numbers)), [len(p) for p, _, _ in numbers])
    other_owner = np.repeat(np.arange(len(numbers)), [len(o) for _, o, _ in numbers])
    finite = np.isfinite(points).all(axis=1)
    bad = np.concatenate((owner[~finite], other_owner[~np.isfinite(others)]))
    if bad.size:
        raise OutlineError(name, f"{_label(entities[int(bad.min())])}: holds a coordinate or "
                           "number that is not finite (NaN or infinity)")
    radii = np.array([r for _, _, r in numbers])
    negative = np.flatnonzero(radii < 0.0)
    if negative.size:
        k = int(negative[0])
        raise OutlineError(name, f"{_label(entities[k])}: radius {radii[k]:g} is negative")
    with np.errstate(over="ignore"):
        reach = np.abs(points).max(axis=1, initial=0.0) * mm_per_unit
    far = np.flatnonzero(~(reach <= MAX_COORDINATE_MM))
    if far.size:
        k = int(far[0])
        raise OutlineError(name, f"{_label(entities[int(owner[k])])}: lies {reach[k]:.3g} mm from"
                           f" the origin; an outline lies within {MAX_COORDINATE_MM:,.0f} mm of "
                           "it (is the unit right? --units)")


def _check_splines(name: str, entities: list[Any]) -> None:
    """Refuse a SPLINE of a degree past :data:`MAX_SPLINE_DEGREE`, or SPLINEs of more than
    :data:`MAX_SPLINE_POINTS` control and fit points in all, before any is flattened."""
    total = 0
    for entity in entities:
        if entity.dxftype() != "SPLINE":
            continue
        degree = entity.dxf.degree
        if not 1 <= degree <= MAX_SPLINE_DEGREE:
            raise OutlineError(name, f"{_label(entity)}: degree {degree}; a SPLINE of degree 1 to "
                               f"{MAX_SPLINE_DEGREE} is read")
        total += len(entity.control_points) + len(entity.fit_points)
        if total > MAX_SPLINE_POINTS:
            raise OutlineError(name, f"{_label(entity)}: the SPLINEs hold more than "
                               f"{MAX_SPLINE_POINTS:,} control and fit points; inspect flattens "
                               "at most that many (save the outline as a polyline)")


def _entity_numbers(name: str, entity: Any) -> tuple[Array, Array, float]:
    """The (k, 2) points that bound *entity* (drawing units), its other numbers (bulges,
    ratios, weights, knots, angles, its extrusion) and its radius (0 when it has none)."""
    try:
        return _NUMBERS[entity.dxftype()](entity)
    except _DXF_FAILURES as exc:
        raise OutlineError(name, f"{_label(entity)}: cannot be read ({_said(exc)})") from None


def _xy(*points: Any) -> Array:
    return np.array([(float(p[0]), float(p[1])) for p in points], dtype=np.float64).reshape(-1, 2)


def _floats(*values: Any) -> Array:
    return np.array([float(v) for v in values], dtype=np.float64)


def _line_numbers(line: Any) -> tuple[Array, Array, float]:
    return _xy(line.dxf.start, line.dxf.end), _floats(*line.dxf.extrusion), 0.0


def _circle_numbers(circle: Any) -> tuple[Array, Array, float]:
    dxf = circle.dxf
    c, r = dxf.center, float(dxf.radius)
    angles = (dxf.start_angle, dxf.end_angle) if circle.dxftype() == "ARC" else ()
    return (_xy((c[0] - r, c[1] - r), (c[0] + r, c[1] + r)),
            _floats(r, *dxf.extrusion, *angles), r)


def _lwpolyline_numbers(polyline: Any) -> tuple[Array, Array, float]:
    values = np.asarray(polyline.lwpoints.values, dtype=np.float64).reshape(-1, 5)
    return (values[:, :2], np.concatenate((values[:, 4], _floats(polyline.dxf.elevation,
                                                                 *polyline.dxf.extrusion))), 0.0)


def _polyline_numbers(polyline: Any) -> tuple[Array, Array, float]:
    vertices = list(polyline.vertices)
    return (_xy(*(v.dxf.location for v in vertices)),
            _floats(*(v.dxf.bulge for v in vertices), *polyline.dxf.extrusion), 0.0)


def _spline_numbers(spline: Any) -> tuple[Array, Array, float]:
    return (_xy(*spline.control_points, *spline.fit_points),
            _floats(*spline.weights, *spline.knots, *spline.dxf.extrusion), 0.0)


def _ellipse_numbers(ellipse: Any) -> tuple[Array, Array, float]:
    dxf = ellipse.dxf
    c = _floats(dxf.center[0], dxf.center[1])
    major = _floats(dxf.major_axis[0], dxf.major_axis[1])
    minor = float(dxf.ratio) * np.array((-major[1], major[0]))
    corners = [c + major, c - major, c + minor, c - minor]
    return (_xy(*corners), _floats(dxf.ratio, dxf.start_param, dxf.end_param, *dxf.extrusion),
            0.0)


_NUMBERS: dict[str, Callable[[Any], tuple[Array, Array, float]]] = {
    "LINE": _line_numbers, "ARC": _circle_numbers, "CIRCLE": _circle_numbers,
    "LWPOLYLINE": _lwpolyline_numbers, "POLYLINE": _polyline_numbers,
    "SPLINE": _spline_numbers, "ELLIPSE": _ellipse_numbers}


# -- DXF: the contours --------------------------------------------------------------------------

def _contours(name: str, entities: list[Any], mm_per_unit: float,
              where: str) -> list[tuple[Profile, int]]:
    """Every closed contour of *entities* (mm), with how many entities make it."""
    from ezdxf import edgesmith

    from camfab.geometry.chains import chain

    gap = JOIN_GAP_MM / mm_per_unit
    found: list[tuple[Profile, int]] = []
    edges = []
    for entity in entities:
        sagitta = _sagitta(entity, mm_per_unit)
        try:
            closed = _closed_points(entity, sagitta, gap)
            edge = None if closed is not None else edgesmith.make_edge_2d(entity, gap_tol=gap)
        except _DXF_FAILURES as exc:
            raise OutlineError(name, f"{_label(entity)}: cannot be read ({_said(exc)})") from None
        if closed is not None:
            _keep(found, closed, mm_per_unit, 1)
        elif edge is not None:
            edges.append(edge)
    if not edges:
        return found
    pieces = [_piece(name, edge, _sagitta(edge.payload, mm_per_unit)) for edge in edges]
    starts = np.array([p[0, :2] for p in pieces])
    ends = np.array([p[-1, :2] for p in pieces])
    chaining = chain(starts, ends, gap)
    for order, backwards in chaining.loops:
        _keep(found, _joined(pieces, order, backwards), mm_per_unit, len(order))
    if chaining.tangled.size:
        sagitta = FLATTEN_SAGITTA_MM / mm_per_unit
        for loop in _mined(name, [edges[k] for k in chaining.tangled], gap, where):
            try:
                polyline = edgesmith.lwpolyline_from_chain(loop, max_sagitta=sagitta)
                points = np.array(list(polyline.get_points("xyb")), dtype=np.float64)
            except _DXF_FAILURES as exc:
                raise OutlineError(name, f"{_label(loop[0].payload)}: cannot be read "
                                   f"({_said(exc)})") from None
            _keep(found, points.reshape(-1, 3), mm_per_unit, len(loop))
    return found


def _sagitta(entity: Any, mm_per_unit: float) -> float:
    """How far (drawing units) the lines *entity* is flattened into may stray from it:
    :data:`FLATTEN_SAGITTA_MM`, or :data:`FLATTEN_SHARE` of a large curve's size."""
    sagitta = FLATTEN_SAGITTA_MM / mm_per_unit
    if entity.dxftype() not in ("SPLINE", "ELLIPSE", "ARC", "CIRCLE"):
        return sagitta
    points = _NUMBERS[entity.dxftype()](entity)[0]
    size = float(np.max(np.ptp(points, axis=0))) if len(points) else 0.0
    return max(sagitta, FLATTEN_SHARE * size)


def _piece(name: str, edge: Any, sagitta: float) -> Array:
    """(k + 1, 3) x, y and bulge of the open entity of *edge*, from its start to its end (the
    last bulge unused): a LINE or a plain ARC directly, anything else through ezdxf."""
    from ezdxf import edgesmith
    from ezdxf.math import Z_AXIS, arc_angle_span_deg, bulge_from_arc_angle

    entity = edge.payload
    start, end = edge.start, edge.end
    kind = entity.dxftype()
    if kind == "LINE":
        return np.array([[start.x, start.y, 0.0], [end.x, end.y, 0.0]])
    try:
        flat = Z_AXIS.isclose(entity.dxf.extrusion)
        if kind == "ARC" and flat:
            span = arc_angle_span_deg(entity.dxf.start_angle, entity.dxf.end_angle)
            bulge = bulge_from_arc_angle(math.radians(span)) if span > 1e-9 else 0.0
            return np.array([[start.x, start.y, bulge], [end.x, end.y, 0.0]])
        if kind == "LWPOLYLINE" and flat:
            return np.asarray(entity.lwpoints.values, dtype=np.float64).reshape(-1, 5)[:, [0, 1, 4]]
        polyline = edgesmith.lwpolyline_from_chain([edge], max_sagitta=sagitta)
        points = np.array(list(polyline.get_points("xyb")), dtype=np.float64).reshape(-1, 3)
    except _DXF_FAILURES as exc:
        raise OutlineError(name, f"{_label(entity)}: cannot be read ({_said(exc)})") from None
    if len(points) < 2:
        return np.array([[start.x, start.y, 0.0], [end.x, end.y, 0.0]])
    return points


def _joined(pieces: list[Array], order: Any, backwards: Any) -> Array:
    """(N, 3) x, y and bulge of the closed loop through *pieces* in *order*, each reversed
    where *backwards* says (its points in reverse, its bulges reversed and negated); each
    piece's last point is the next one's first."""
    chained = []
    for k, reverse in zip(order.tolist(), backwards.tolist(), strict=True):
        piece = pieces[k]
        if reverse:
            turned = piece[::-1].copy()
            turned[:, 2] = -np.roll(piece[::-1, 2], -1)
            piece = turned
        chained.append(piece[:-1])
    return np.concatenate(chained)


def _mined(name: str, edges: list[Any], gap: float, where: str) -> list[Any]:
    """The loops ezdxf's edge miner finds among *edges* (which meet three or more at a point),
    within :data:`CHAIN_TIMEOUT_S`."""
    from ezdxf import edgeminer

    refusal = (f"has entities {where} that meet three or more at a point and whose loops "
               "cannot be sorted out quickly; choose the outline's layer with --layer or join "
               "it into one polyline")
    if len(edges) > MAX_TANGLED_PIECES:
        raise OutlineError(name, refusal)
    # numbered for this read, as camfab.export.dxf.layer_loops does: the same loops every time
    numbered = [edge._replace(id=number) for number, edge in enumerate(edges, start=1)]
    try:
        return list(edgeminer.find_all_loops(edgeminer.Deposit(numbered, gap_tol=gap),
                                             timeout=CHAIN_TIMEOUT_S))
    except (edgeminer.TimeoutError, TimeoutError):
        raise OutlineError(name, refusal) from None


def _keep(found: list[tuple[Profile, int]], points: Array, mm_per_unit: float,
          count: int) -> None:
    try:
        profile = Profile.from_points(points[:, :2] * mm_per_unit, points[:, 2])
    except ValueError:
        return
    if len(profile.vertices) >= 2 and profile.area > 0.0:
        found.append((profile, count))


def _closed_points(entity: Any, sagitta: float, gap: float) -> Array | None:
    """(N, 3) x, y, bulge of a closed entity (a contour by itself: a closed one, or an open
    polyline whose ends meet within *gap*), or None for an open one. A circle of radius 0 has
    no points."""
    kind = entity.dxftype()
    if kind == "CIRCLE":
        cx, cy = entity.dxf.center.x, entity.dxf.center.y
        r = entity.dxf.radius
        if r == 0.0:
            return np.zeros((0, 3))
        return np.array([[cx + r, cy, 1.0], [cx - r, cy, 1.0]])
    if kind == "LWPOLYLINE":
        values = np.asarray(entity.lwpoints.values, dtype=np.float64).reshape(-1, 5)
        if entity.closed or _ends_meet(values[:, :2], gap):
            return values[:, [0, 1, 4]]
        return None
    if kind == "POLYLINE" and entity.is_2d_polyline:
        points = np.array([(v.dxf.location.x, v.dxf.location.y, v.dxf.bulge)
                           for v in entity.vertices], dtype=np.float64).reshape(-1, 3)
        if entity.is_closed or _ends_meet(points[:, :2], gap):
            return points
        return None
    if kind == "SPLINE" and entity.closed:
        return _flat(entity.flattening(sagitta))
    if kind == "ELLIPSE" and _full_turn(entity):
        return _flat(entity.flattening(sagitta))
    return None


def _ends_meet(points: Array, gap: float) -> bool:
    """True when the open chain *points* (more than two of them) ends where it starts."""
    return len(points) > 2 and bool(np.hypot(*(points[-1] - points[0])) <= gap)


def _full_turn(ellipse: Any) -> bool:
    span = (ellipse.dxf.end_param - ellipse.dxf.start_param) % (2 * math.pi)
    return span < 1e-9 or span > 2 * math.pi - 1e-9


def _flat(points: Any) -> Array:
    xy = np.array([(p.x, p.y) for p in points], dtype=np.float64).reshape(-1, 2)
    return np.column_stack((xy, np.zeros(len(xy))))


def _kerf_note(msp: Any) -> KerfNote | None:
    """camfab's note (in any TEXT or MTEXT) that the CUT layer is offset for a kerf."""
    for text in msp:
        kind = text.dxftype()
        if kind not in ("TEXT", "MTEXT"):
            continue
        content = str((text.dxf.text if kind == "TEXT" else text.text) or "")
        if "CUT offset for a kerf" in content:
            return KerfNote(content, _label(text))
    return None
