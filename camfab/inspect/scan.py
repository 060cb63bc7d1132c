"""Read a 3-D scan of a made cam (a drum, a globoid, a groove plate) into points, for inspection.

Formats, by the file's suffix:

- ``.stl``: a mesh, binary (read by :func:`camfab.export.stl.read_stl`, its coincident corners
  merged) or ASCII (``facet`` / ``vertex x y z`` lines).
- ``.ply``: a point cloud or a mesh, ASCII or binary (little or big endian): the ``vertex``
  element's ``x``, ``y``, ``z`` and, when present, ``nx``, ``ny``, ``nz``; the ``face``
  element's ``vertex_indices`` (triangles only). Other elements of fixed size are skipped.
- anything else: a CSV of points as coordinate measuring machines export them, one point a row:
  ``x, y, z`` and optionally the probe's normal ``nx, ny, nz``, in that order, or in any order
  under a header row naming the columns (``i, j, k`` name a normal too). Commas, semicolons,
  tabs or spaces separate the values (with semicolons or tabs a comma may be the decimal mark);
  ``#`` starts a comment. It is read with numpy a block of lines at a time, never a row at a
  time: a million points read in a second or two.

Units: the file's coordinates are in *units* when given (``mm`` or ``in``), else in
*default_units*, since none of these formats says; :attr:`Scan.units` tells which. Points are
returned in millimetres.

Limits, so that a bad file is refused at once: a regular file of at most :data:`MAX_BYTES`
bytes, holding between :data:`MIN_POINTS` and :data:`MAX_POINTS` points (checked before the
points are read), every coordinate finite and within :data:`MAX_COORDINATE_MM` of the origin,
every normal of unit length within :data:`NORMAL_TOLERANCE` (then made exactly one), every face
naming vertices that exist. A refusal is a :class:`~camfab.errors.ScanError`, one line naming the
file (and the line of a CSV or ASCII PLY when one is at fault).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from camfab.arrays import Array
from camfab.errors import ScanError
from camfab.export.outline import MAX_COORDINATE_MM, UNITS_MM

#: Largest scan file (bytes): a million points with normals as CSV are some 60 MB, as binary
#: PLY 24 MB.
MAX_BYTES = 200_000_000

#: Most points of a scan: a dense scan of a large drum; 20 million points with normals take
#: some 1 GB as float64.
MAX_POINTS = 20_000_000

#: Fewest points of a scan: fewer cannot measure a cam's surface.
MIN_POINTS = 100

#: Largest departure of a normal's length from one: a CMM writes its probe's normal to six
#: decimals or so; a larger departure is a column that is not a normal.
NORMAL_TOLERANCE = 1e-3

#: Most bytes of a PLY header (its lines up to ``end_header``).
MAX_PLY_HEADER = 65_536

#: Bytes of CSV text parsed at once (cut at a line's end): bounds the working memory.
CSV_BLOCK_BYTES = 8_000_000

_WHAT = "a scan (CSV, PLY or STL)"

#: Bytes that separate values once a CSV's separators are made spaces.
_SPACE = np.zeros(256, dtype=bool)
_SPACE[[9, 10, 11, 12, 13, 32]] = True

#: Names of a CSV's columns (lowercase) -> which of x, y, z, nx, ny, nz they are.
_COLUMN_NAMES = {"x": 0, "y": 1, "z": 2, "nx": 3, "ny": 4, "nz": 5, "i": 3, "j": 4, "k": 5}

#: PLY property types -> numpy type codes (byte order added).
_PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2",
              "int16": "i2", "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4",
              "uint": "u4", "uint32": "u4", "float": "f4", "float32": "f4", "double": "f8",
              "float64": "f8"}
_PLY_FORMATS = {"ascii": "", "binary_little_endian": "<", "binary_big_endian": ">"}
_PLY_FACE_LISTS = ("vertex_indices", "vertex_index")

_STL_VERTEX = re.compile(rb"vertex[ \t]+(\S+)[ \t]+(\S+)[ \t]+(\S+)")
_STL_FACET = re.compile(rb"\bfacet\b")


@dataclass(frozen=True)
class Scan:
    """A scan as read, in millimetres in the scanner's frame.

    Attributes
    ----------
    points
        (N, 3) float64 points (mm).
    normals
        (N, 3) unit normals of the points, or None when the file has none.
    faces
        (F, 3) vertex indices of a mesh's triangles, or None for a point cloud.
    source
        What was read, for the report ("1,000,000 points with normals from a CSV").
    units
        How the unit was chosen ("mm (the default: a scan file does not say)", "in (--units)").
    """

    points: Array
    normals: Array | None
    faces: np.ndarray | None
    source: str
    units: str


def read_scan(path: Path, *, units: str | None = None, default_units: str = "mm") -> Scan:
    """The scan in the CSV, PLY or STL file *path* (by its suffix; anything but ``.ply`` and
    ``.stl`` is read as CSV).

    Parameters
    ----------
    units
        ``mm`` or ``in``: the unit of the file's coordinates.
    default_units
        The unit when *units* is not given.

    Raises
    ------
    InputFileError
        The file is missing, not a regular file, or larger than :data:`MAX_BYTES`.
    ScanError
        The file is unreadable, over a limit, or holds bad numbers (see the module's text).
    """
    from camfab.files import read_bounded

    name = str(path)
    unit = units or default_units
    if unit not in UNITS_MM:
        raise ScanError(name, f"unknown unit {unit!r}; allowed: {', '.join(UNITS_MM)}")
    said = f"{unit} (--units)" if units else f"{unit} (the default: a scan file does not say)"
    data = read_bounded(path, MAX_BYTES, _WHAT)
    suffix = path.suffix.lower()
    if suffix == ".stl":
        points, normals, faces, source = _read_stl(name, data)
    elif suffix == ".ply":
        points, normals, faces, source = _read_ply(name, data)
    else:
        points, normals, faces, source = _read_csv(name, data)
    points = _checked_points(name, points, UNITS_MM[unit])
    if faces is not None:
        faces = _checked_faces(name, faces, len(points))
    return Scan(points, normals, faces, source, said)


# -- checks -------------------------------------------------------------------------------------

def _check_count(name: str, count: int) -> None:
    """Refuse *count* points outside :data:`MIN_POINTS` .. :data:`MAX_POINTS` (before reading
    them)."""
    if count > MAX_POINTS:
        raise ScanError(name, f"holds {count:,} points; a scan holds at most {MAX_POINTS:,}")
    if count < MIN_POINTS:
        raise ScanError(name, f"holds {count:,} points; a scan holds at least {MIN_POINTS:,}")


def _checked_points(name: str, points: Array, mm_per_unit: float) -> Array:
    """*points* (file units) as float64 millimetres, when finite and near the origin."""
    _check_count(name, len(points))
    points = np.asarray(points, dtype=np.float64) * mm_per_unit
    bad = ~np.isfinite(points).all(axis=1)
    if bad.any():
        first = int(np.argmax(bad))
        raise ScanError(name, f"point {first + 1:,} has a coordinate that is not a finite "
                        f"number ({_row(points[first])})")
    far = float(np.abs(points).max())
    if far > MAX_COORDINATE_MM:
        raise ScanError(name, f"a point lies {far:.3g} mm from the origin; a scan lies within "
                        f"{MAX_COORDINATE_MM:,.0f} mm of it: is the unit right?")
    return points


def _unit(name: str, normals: Array, lines: Array | None) -> Array:
    """*normals* made unit vectors, when each is within :data:`NORMAL_TOLERANCE` of one long;
    a refusal names the point (or its line, from *lines*)."""
    normals = np.asarray(normals, dtype=np.float64)
    with np.errstate(invalid="ignore", over="ignore"):
        length = np.sqrt(np.einsum("ij,ij->i", normals, normals))
    bad = ~(np.abs(length - 1.0) <= NORMAL_TOLERANCE)  # NaN is bad too
    if bad.any():
        first = int(np.argmax(bad))
        where = f"point {first + 1:,}: " if lines is None else ""
        problem = ("is zero" if length[first] == 0.0 else f"is {length[first]:.6g} long"
                   if np.isfinite(length[first]) else "is not finite numbers")
        raise ScanError(name, f"{where}the normal ({_row(normals[first])}) {problem}; a "
                        f"normal is a unit vector (length 1 within {NORMAL_TOLERANCE:g})",
                        None if lines is None else int(lines[first]))
    return normals / length[:, None]


def _checked_faces(name: str, faces: np.ndarray, count: int) -> np.ndarray:
    """*faces* as int64 when every index names one of *count* vertices."""
    faces = np.asarray(faces).astype(np.int64).reshape(-1, 3)
    bad = ((faces < 0) | (faces >= count)).any(axis=1)
    if bad.any():
        first = int(np.argmax(bad))
        raise ScanError(name, f"face {first + 1:,} names vertex {_row(faces[first])}; the "
                        f"mesh has vertices 0 to {count - 1:,}")
    return faces


def _row(values: np.ndarray) -> str:
    return ", ".join(f"{v:g}" for v in values.tolist())


# -- CSV ----------------------------------------------------------------------------------------

def _read_csv(name: str, data: bytes) -> tuple[Array, Array | None, None, str]:
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ScanError(name, "is not a text file (expected a CSV of x, y, z points)",
                        data[:exc.start].count(b"\n") + 1) from None
    if "#" in text:
        text = re.sub(r"#[^\n]*", "", text)
    if text.count("\n") > MAX_POINTS + 1:
        raise ScanError(name, f"has more than {MAX_POINTS + 1:,} lines; a scan holds at most "
                        f"{MAX_POINTS:,} points")
    first = re.search(r"\S[^\n]*", text)
    if first is None:
        raise ScanError(name, "holds no points")
    head = first.group(0)
    if ";" in head:
        text = text.translate(str.maketrans(";,", " ."))
    elif "\t" in head:
        text = text.replace(",", ".")
    else:
        text = text.replace(",", " ")
    names = text[first.start():first.end()].split()
    columns, header = _csv_columns(name, names, text.count("\n", 0, first.start()) + 1)
    if header:
        body_at = first.end() + 1
        line = text.count("\n", 0, body_at) + 1
    else:
        body_at, line = 0, 1
    table, at = _table(name, text[body_at:].encode("utf-8"), len(columns), line)
    _check_count(name, len(table))
    bad = ~np.isfinite(table).all(axis=1)
    if bad.any():
        k = int(np.argmax(bad))
        raise ScanError(name, f"a value is not a finite number ({_row(table[k])})", int(at[k]))
    points = table[:, [columns.index(c) for c in (0, 1, 2)]]
    if 3 not in columns:
        return points, None, None, f"{len(points):,} points from a CSV"
    normals = _unit(name, table[:, [columns.index(c) for c in (3, 4, 5)]], at)
    return points, normals, None, f"{len(points):,} points with normals from a CSV"


def _csv_columns(name: str, names: list[str], line: int) -> tuple[list[int], bool]:
    """What each column of the CSV holds (0..5: x, y, z, nx, ny, nz; -1: unused), and whether
    the first line (*names*, numbered *line*) is a header."""
    try:
        [float(word) for word in names]
    except ValueError:
        pass
    else:  # no header: x y z, or x y z nx ny nz
        if len(names) not in (3, 6):
            raise ScanError(name, f"has {len(names)} values in a row; a scan CSV has 3 (x, y, "
                            "z) or 6 (x, y, z, nx, ny, nz), or a header row naming its "
                            "columns", line)
        return list(range(len(names))), False
    columns = [_COLUMN_NAMES.get(word.strip("\"'").lower(), -1) for word in names]
    known = sorted(c for c in columns if c >= 0)
    if known not in ([0, 1, 2], [0, 1, 2, 3, 4, 5]):
        raise ScanError(name, f"the header {' '.join(names)!r} does not name the columns x, "
                        "y, z once each (and nx, ny, nz, or i, j, k, for normals)", line)
    return columns, True


def _table(name: str, body: bytes, width: int, line: int) -> tuple[Array, Array]:
    """The (R, width) values of the rows of *body* (text whose separators are spaces, its first
    line numbered *line*; blank lines skipped) and each row's line number, read
    :data:`CSV_BLOCK_BYTES` at a time."""
    rows, lines = [], []
    offset = 0
    while offset < len(body):
        end = body.find(b"\n", min(offset + CSV_BLOCK_BYTES, len(body)))
        end = len(body) if end < 0 else end + 1
        block_rows, block_lines = _csv_block(name, body[offset:end], width, line)
        rows.append(block_rows)
        lines.append(block_lines)
        line += body.count(b"\n", offset, end)
        offset = end
    if not rows:
        return np.zeros((0, width)), np.zeros(0, dtype=np.int64)
    return np.concatenate(rows), np.concatenate(lines)


def _csv_block(name: str, block: bytes, width: int, line: int) -> tuple[Array, Array]:
    """The (R, width) values of the rows of *block* (CSV text, separators made spaces, whole
    lines, the first numbered *line*), and each row's line number."""
    b = np.frombuffer(block, dtype=np.uint8)
    space = _SPACE[b]
    starts = ~space
    starts[1:] &= space[:-1]
    line_of = np.cumsum(b == 10, dtype=np.int32)
    counts = np.bincount(line_of[starts], minlength=int(line_of[-1]) + 1 if len(b) else 0)
    wrong = (counts != 0) & (counts != width)
    if wrong.any():
        k = int(np.argmax(wrong))
        raise ScanError(name, f"has {counts[k]} values in a row; the file's rows have {width}",
                        line + k)
    try:
        values = np.fromstring(block.decode("utf-8"), sep=" ")  # type: ignore[call-overload]
    except (ValueError, DeprecationWarning):
        values = None
    if values is None or values.size != int(counts.sum()):
        _refuse_token(name, block, line)
    return values.reshape(-1, width), np.flatnonzero(counts) + line


def _refuse_token(name: str, block: bytes, line: int) -> None:
    """Name the first line of *block* with a value that is not a number (a refusal's path
    only: a line at a time)."""
    for number, raw in enumerate(block.decode("utf-8").split("\n"), start=line):
        for word in raw.split():
            try:
                float(word)
            except ValueError:
                raise ScanError(name, f"{word[:40]!r} is not a number", number) from None
    raise ScanError(name, "cannot be read as numbers", line)


# -- PLY ----------------------------------------------------------------------------------------

@dataclass(frozen=True)
class _Element:
    name: str
    count: int
    properties: list[tuple[str, str, str | None]]  # name, type, list count's type (or None)


def _read_ply(name: str, data: bytes) -> tuple[Array, Array | None, np.ndarray | None, str]:
    end = data.find(b"end_header", 0, MAX_PLY_HEADER)
    if not data.startswith(b"ply") or end < 0:
        raise ScanError(name, "is not a PLY file (no 'ply' ... 'end_header' header in its "
                        f"first {MAX_PLY_HEADER:,} bytes)")
    body_at = data.find(b"\n", end)
    body_at = len(data) if body_at < 0 else body_at + 1
    try:
        header = data[:body_at].decode("ascii").splitlines()
    except UnicodeDecodeError:
        raise ScanError(name, "has a PLY header that is not ASCII text") from None
    order, elements = _ply_header(name, header)
    vertex = next((e for e in elements if e.name == "vertex"), None)
    if vertex is None:
        raise ScanError(name, "has no 'element vertex' in its PLY header")
    _check_count(name, vertex.count)
    face = next((e for e in elements if e.name == "face"), None)
    if face is not None and face.count > 2 * MAX_POINTS:
        raise ScanError(name, f"has {face.count:,} faces; a scan has at most {2 * MAX_POINTS:,}")
    if order == "":
        read = _ply_ascii(name, data[body_at:], elements, len(header) + 1)
    else:
        read = _ply_binary(name, data[body_at:], elements, order)
    table = read["vertex"]
    props = [p[0] for p in vertex.properties]
    points = np.column_stack([table[props.index(c)] for c in ("x", "y", "z")])
    normals = None
    if all(c in props for c in ("nx", "ny", "nz")):
        normals = _unit(name, np.column_stack([table[props.index(c)]
                                               for c in ("nx", "ny", "nz")]), None)
    faces = read.get("face")
    kind = "binary" if order else "ASCII"
    with_normals = " with normals" if normals is not None else ""
    if faces is None:
        article = "a" if order else "an"
        return (points, normals, None,
                f"{len(points):,} points{with_normals} from {article} {kind} PLY")
    return (points, normals, faces, f"a {kind} PLY mesh of {len(faces):,} triangles "
            f"({len(points):,} vertices{with_normals})")


def _ply_header(name: str, header: list[str]) -> tuple[str, list[_Element]]:
    """The byte order ('' for ASCII) and the elements of a PLY header."""
    order: str | None = None
    elements: list[_Element] = []
    for number, raw in enumerate(header[1:], start=2):
        words = raw.split()
        if not words or words[0] in ("comment", "obj_info", "end_header"):
            continue
        if words[0] == "format" and len(words) == 3 and words[1] in _PLY_FORMATS:
            order = _PLY_FORMATS[words[1]]
        elif words[0] == "element" and len(words) == 3 and words[2].isdigit():
            elements.append(_Element(words[1], int(words[2]), []))
        elif (words[0] == "property" and elements and len(words) == 3
              and words[1] in _PLY_TYPES):
            elements[-1].properties.append((words[2], _PLY_TYPES[words[1]], None))
        elif (words[0] == "property" and elements and len(words) == 5 and words[1] == "list"
              and words[2] in _PLY_TYPES and words[3] in _PLY_TYPES):
            elements[-1].properties.append((words[4], _PLY_TYPES[words[3]], _PLY_TYPES[words[2]]))
        else:
            raise ScanError(name, f"the PLY header line {raw.strip()[:60]!r} is not a format, "
                            "element or property the PLY format defines", number)
    if order is None:
        raise ScanError(name, "has no 'format ascii|binary_little_endian|binary_big_endian "
                        "1.0' line in its PLY header")
    for element in elements:
        props = [p[0] for p in element.properties]
        lists = [p for p in element.properties if p[2] is not None]
        if element.name == "vertex" and not all(c in props for c in ("x", "y", "z")):
            raise ScanError(name, "the PLY's vertex element has no x, y and z properties")
        if element.name == "vertex" and any(c in props for c in ("nx", "ny", "nz")) and not all(
                c in props for c in ("nx", "ny", "nz")):
            raise ScanError(name, "the PLY's vertex element has some of nx, ny, nz, not all")
        if lists and (element.name != "face" or len(lists) != 1 or lists[0][0] not in
                      _PLY_FACE_LISTS):
            raise ScanError(name, f"the PLY's element {element.name!r} has a list property "
                            "other than a face's vertex_indices; it cannot be read")
        if element.name == "face" and not lists:
            raise ScanError(name, "the PLY's face element has no vertex_indices list")
    return order, elements


def _ply_binary(name: str, body: bytes, elements: list[_Element],
                order: str) -> dict[str, np.ndarray]:
    """Each element's columns (vertex: one array per property; face: (F, 3) indices) read from
    the binary *body*, whose length must be what the header says (faces all triangles)."""
    read: dict[str, np.ndarray] = {}
    offset = 0
    for element in elements:
        fields = []
        for prop, kind, count_kind in element.properties:
            if count_kind is None:
                fields.append((prop, order + kind))
            else:
                fields += [("count", order + count_kind), (prop, order + kind, (3,))]
        dtype = np.dtype(fields)
        size = dtype.itemsize * element.count
        if offset + size > len(body):
            raise ScanError(name, f"the PLY header says its body holds {element.count:,} "
                            f"{element.name} elements (at least {offset + size:,} bytes) but "
                            f"the body has {len(body):,} bytes"
                            + (" (or its faces are not all triangles)"
                               if element.name == "face" else ""))
        table = np.frombuffer(body, dtype=dtype, count=element.count, offset=offset)
        offset += size
        if element.name == "face":
            if element.count and not (table["count"] == 3).all():
                raise ScanError(name, "the PLY's faces are not all triangles; a scan's mesh "
                                "is read as triangles only")
            list_name = next(p[0] for p in element.properties if p[2] is not None)
            read["face"] = np.asarray(table[list_name])
        elif element.name == "vertex":
            read["vertex"] = np.stack([table[p[0]].astype(np.float64)
                                       for p in element.properties])
    if offset != len(body):
        raise ScanError(name, f"the PLY header says its body is {offset:,} bytes but it has "
                        f"{len(body):,}")
    return read


def _ply_ascii(name: str, body: bytes, elements: list[_Element],
               line: int) -> dict[str, np.ndarray]:
    """Each element's columns read from the ASCII *body* (its first line numbered *line*): one
    element a line, the faces all triangles."""
    ends = np.flatnonzero(np.frombuffer(body, dtype=np.uint8) == 10)
    if len(body) and body[-1:] != b"\n":
        ends = np.append(ends, len(body))
    read: dict[str, np.ndarray] = {}
    at = 0
    for element in elements:
        if element.count == 0:
            continue
        width = len(element.properties) + (3 if element.name == "face" else 0)
        if at + element.count > len(ends):
            raise ScanError(name, f"the PLY header says its body holds {element.count:,} "
                            f"{element.name} elements but it ends after {len(ends) - at:,} "
                            "of them", line + len(ends))
        start = int(ends[at - 1]) + 1 if at else 0
        table, _ = _table(name, body[start:int(ends[at + element.count - 1]) + 1], width,
                          line + at)
        if len(table) != element.count:
            raise ScanError(name, f"the PLY's {element.name} elements have a blank line",
                            line + at)
        at += element.count
        if element.name == "face":
            list_at = next(k for k, p in enumerate(element.properties) if p[2] is not None)
            if not (table[:, list_at] == 3).all():
                raise ScanError(name, "the PLY's faces are not all triangles; a scan's mesh "
                                "is read as triangles only")
            indices = table[:, list_at + 1:list_at + 4]
            if not (indices == np.round(indices)).all():
                raise ScanError(name, "the PLY's faces have vertex indices that are not "
                                "whole numbers")
            read["face"] = indices
        elif element.name == "vertex":
            read["vertex"] = table.T
    rest = body[int(ends[at - 1]) + 1 if at else 0:]
    if rest.strip():
        raise ScanError(name, "the PLY's body has more lines than its header says", line + at)
    return read


# -- STL ----------------------------------------------------------------------------------------

def _read_stl(name: str, data: bytes) -> tuple[Array, None, np.ndarray, str]:
    from camfab.export.stl import merged, read_stl

    if len(data) >= 84:
        count = int.from_bytes(data[80:84], "little")
        if len(data) == 84 + 50 * count:
            with np.errstate(invalid="ignore", over="ignore"):  # NaN is refused afterwards
                mesh = read_stl(data)
            return (mesh.vertices, None, mesh.faces,
                    f"a binary STL mesh of {len(mesh.faces):,} triangles")
    if not data.lstrip().startswith(b"solid"):
        raise ScanError(name, "is not an STL file: not a binary STL of the length its face "
                        "count gives, and not an ASCII one ('solid ...')")
    facets = len(_STL_FACET.findall(data))
    found = _STL_VERTEX.findall(data)
    if len(found) != 3 * facets:
        raise ScanError(name, f"is an ASCII STL of {facets:,} facets with {len(found):,} "
                        "vertex lines; each facet has three")
    try:
        corners = np.array(found, dtype=np.bytes_).astype(np.float64)
    except ValueError:
        raise ScanError(name, "is an ASCII STL with a vertex that is not three numbers") from None
    with np.errstate(invalid="ignore", over="ignore"):  # NaN is refused afterwards
        vertices, faces = merged(corners, np.arange(len(corners),
                                                    dtype=np.int64).reshape(-1, 3))
    return vertices, None, faces, f"an ASCII STL mesh of {len(faces):,} triangles"
