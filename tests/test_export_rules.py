"""Rules the DXF, SVG and STL of every example and starter keep for the programs that read them,
checked by reading the files back independently of camfab's own geometry code:

- SVG: the page (viewBox, width, height) holds every path's exact bounding box, arcs to their
  extremes (svgelements reads the paths), with a margin.
- DXF: ``$EXTMIN``/``$EXTMAX`` are the entities' bounding box (arcs to their extremes); the limits
  and the paper are the drawing's size in the drawing's units; no arc's radius is over 1,000
  times the part's size, and a single-precision reader puts every arc's ends where they are.
- STL: no edge under 1e-3 mm, no facet thinner than 1e-4 mm (its smallest altitude), closed and
  consistently wound, and the build's verification of the file passed.
"""

from __future__ import annotations

import math
import re
import struct
from pathlib import Path

import ezdxf
import numpy as np
import pytest
from ezdxf import bbox as ezdxf_bbox
from svgelements import Path as SvgPath

from .conftest import EVERY_DESIGN, Built

#: The shortest STL edge allowed (mm): FreeCAD's mesh module calls shorter ones too short.
MIN_EDGE_MM = 1e-3
#: The thinnest STL facet allowed (mm, its smallest altitude): some ten float32 roundings of a
#: coordinate of a part a few hundred millimetres across.
MIN_ALTITUDE_MM = 1e-4
#: The largest DXF arc radius, as a multiple of the part's size.
MAX_RADIUS_RATIO = 1000.0


# ---- SVG -------------------------------------------------------------------------------------

def svg_page(text: str) -> tuple[np.ndarray, np.ndarray, str]:
    """The viewBox's corners (file units, y down) and the page's unit."""
    x, y, w, h = (float(v) for v in re.search(r'viewBox="([^"]+)"', text).group(1).split())
    width = re.search(r'width="([\d.]+)(mm|in)"', text)
    height = re.search(r'height="([\d.]+)(mm|in)"', text)
    assert width is not None and height is not None
    # true size: the page's width and height are the viewBox's, in the design's units
    assert float(width.group(1)) == pytest.approx(w, abs=1e-5)
    assert float(height.group(1)) == pytest.approx(h, abs=1e-5)
    return np.array([x, y]), np.array([x + w, y + h]), width.group(2)


def svg_drawing_box(text: str) -> tuple[np.ndarray, np.ndarray]:
    """The exact bounding box (file units, y down) of every path and circle, read with
    svgelements."""
    boxes = [SvgPath(d).bbox() for d in re.findall(r' d="([^"]+)"', text)]
    boxes += [(float(cx) - float(r), float(cy) - float(r), float(cx) + float(r),
               float(cy) + float(r))
              for cx, cy, r in re.findall(r'<circle cx="([^"]+)" cy="([^"]+)" r="([^"]+)"', text)]
    assert boxes
    every = np.array(boxes, dtype=np.float64)
    return every[:, :2].min(axis=0), every[:, 2:].max(axis=0)


@pytest.mark.parametrize("name", EVERY_DESIGN)
def test_the_svg_page_holds_every_path_with_a_margin(every_build: dict[str, Built],
                                                     name: str) -> None:
    built = every_build[name]
    svgs = built.files(".svg")
    assert svgs
    for svg in svgs:
        text = svg.read_text()
        low, high, unit = svg_page(text)
        assert unit == built.design.units
        inked_low, inked_high = svg_drawing_box(text)
        size = float(np.max(inked_high - inked_low))
        # inside the page on every side, with room for the stroke (a thousandth of the size)
        margin = min(float(np.min(inked_low - low)), float(np.min(high - inked_high)))
        assert margin > 0.01 * size, f"{svg.name}: margin {margin:g} {unit}"


# ---- DXF -------------------------------------------------------------------------------------

def arc_box(centre: np.ndarray, radius: float, start_deg: float,
            end_deg: float) -> np.ndarray:
    """The corners of an ARC's exact bounding box: its ends, and the points at 0, 90, 180 and
    270° that lie on it (counter-clockwise from start to end)."""
    span = (end_deg - start_deg) % 360.0
    angles = [start_deg, start_deg + span]
    angles += [q for q in (0.0, 90.0, 180.0, 270.0, 360.0, 450.0, 540.0, 630.0)
               if start_deg % 360.0 <= q <= start_deg % 360.0 + span]
    rad = np.radians(angles)
    points = centre + radius * np.stack((np.cos(rad), np.sin(rad)), axis=-1)
    return np.array([points.min(axis=0), points.max(axis=0)])


def entity_box(entity) -> np.ndarray:  # type: ignore[no-untyped-def]
    """The corners of one entity's bounding box (file units). Text: a box as wide as a
    character is high per character, from 0.333 of its height below the baseline to its height
    above (ezdxf's monospaced stand-in for the reader's font, with which camfab writes the
    extents so that they do not depend on the fonts a machine has)."""
    kind = entity.dxftype()
    if kind == "LINE":
        points = np.array([entity.dxf.start.vec2, entity.dxf.end.vec2])
    elif kind == "CIRCLE":
        centre, r = np.array(entity.dxf.center.vec2), entity.dxf.radius
        points = np.array([centre - r, centre + r])
    elif kind == "ARC":
        points = arc_box(np.array(entity.dxf.center.vec2), entity.dxf.radius,
                         entity.dxf.start_angle, entity.dxf.end_angle)
    elif kind == "TEXT":
        assert entity.dxf.rotation == 0 and entity.dxf.halign == 0 and entity.dxf.valign == 0
        h = entity.dxf.height
        x, y = entity.dxf.insert.vec2
        points = np.array([[x, y - 0.333 * h], [x + len(entity.dxf.text) * h * entity.dxf.width,
                                            y + h]])
    else:
        raise AssertionError(f"unexpected {kind}")
    return np.array([points.min(axis=0), points.max(axis=0)])


def layer_box(msp, query: str = "*") -> np.ndarray:  # type: ignore[no-untyped-def]
    boxes = np.array([entity_box(e) for e in msp.query(query)])
    return np.array([boxes[:, 0].min(axis=0), boxes[:, 1].max(axis=0)])


def arc_radii(msp) -> np.ndarray:  # type: ignore[no-untyped-def]
    """The radius of every ARC and of every LWPOLYLINE bulge."""
    radii = [e.dxf.radius for e in msp.query("ARC")]
    for polyline in msp.query("LWPOLYLINE"):
        points = list(polyline.get_points("xyb"))
        ends = points[1:] + (points[:1] if polyline.closed else [])
        for (x0, y0, bulge), (x1, y1, _) in zip(points, ends, strict=False):
            if bulge:
                radii.append(math.dist((x0, y0), (x1, y1)) / (2 * abs(math.sin(
                    2 * math.atan(bulge)))))
    return np.array(radii, dtype=np.float64)


@pytest.mark.parametrize("name", EVERY_DESIGN)
def test_the_dxf_header_gives_the_extents_and_a_page_in_the_drawings_units(
        every_build: dict[str, Built], name: str) -> None:
    built = every_build[name]
    dxfs = built.files(".dxf")
    assert dxfs
    for path in dxfs:
        doc = ezdxf.readfile(path)
        msp = doc.modelspace()
        header = doc.header
        assert header["$INSUNITS"] == {"mm": 4, "in": 1}[built.design.units]
        low, high = layer_box(msp)
        size = float(np.max(high - low))
        extmin, extmax = np.array(header["$EXTMIN"][:2]), np.array(header["$EXTMAX"][:2])
        assert np.allclose(extmin, low, rtol=0, atol=1e-9 * size), (extmin, low)
        assert np.allclose(extmax, high, rtol=0, atol=1e-9 * size), (extmax, high)
        # ezdxf's own box of the geometry (arcs through Bézier curves, 2.7e-4 of the radius
        # off at most) lies within them
        geometry = ezdxf_bbox.extents(msp.query("LINE ARC CIRCLE LWPOLYLINE"), fast=False)
        slack = 3e-4 * size
        assert np.all(np.array(geometry.extmin)[:2] >= extmin - slack)
        assert np.all(np.array(geometry.extmax)[:2] <= extmax + slack)
        # the model's limits and the paper: the extents with a margin, in the drawing's units
        limmin, limmax = np.array(header["$LIMMIN"]), np.array(header["$LIMMAX"])
        assert np.all(limmin < extmin) and np.all(limmax > extmax)
        page = np.array(header["$PLIMMAX"]) - np.array(header["$PLIMMIN"])
        assert np.allclose(page, limmax - limmin, rtol=1e-12)
        assert np.all(page > extmax - extmin) and np.all(page < extmax - extmin + 0.2 * size)
        # the drawing's origin on the paper: the extents land inside the page
        base = np.array(header["$PINSBASE"][:2])
        assert np.all(base + extmin > 0) and np.all(base + extmax < page)
        assert header["$PSVPSCALE"] == 1.0


def test_the_inch_drawing_has_a_page_in_inches(every_build: dict[str, Built]) -> None:
    doc = ezdxf.readfile(every_build["demo-inch-flat"].files(".dxf")[0])
    page = np.array(doc.header["$PLIMMAX"]) - np.array(doc.header["$PLIMMIN"])
    # the cam is about 3 inches across: a page of a few inches, not A3's 420 × 297 as inches
    assert np.all(page > 3.0) and np.all(page < 5.0)


def arc_ends(arcs, kind: type) -> np.ndarray:  # type: ignore[no-untyped-def]
    """(N, 2, 2) start and end points of ARC entities computed in the float type *kind* from
    their centres, radii and angles in degrees, as a reader of that precision does."""
    centre = np.array([a.dxf.center.vec2 for a in arcs]).astype(kind)
    radius = np.array([a.dxf.radius for a in arcs]).astype(kind)
    turn = np.radians(np.array([[a.dxf.start_angle, a.dxf.end_angle] for a in arcs]).astype(kind))
    return (centre[:, None, :] + radius[:, None, None]
            * np.stack((np.cos(turn), np.sin(turn)), -1)).astype(np.float64)


@pytest.mark.parametrize("name", EVERY_DESIGN)
def test_no_dxf_arc_is_a_near_straight_giant_and_the_cut_holds_the_tolerance(
        every_build: dict[str, Built], name: str) -> None:
    built = every_build[name]
    for path in built.files(".dxf"):
        msp = ezdxf.readfile(path).modelspace()
        low, high = layer_box(msp, '*[layer=="CUT"]')
        part = float(np.max(high - low))
        radii = arc_radii(msp)
        assert radii.size == 0 or radii.max() <= MAX_RADIUS_RATIO * part, (
            f"{path.name}: radius {radii.max():g} for a part of {part:g}")
        # a reader in single precision (float32 centre, radius and angles in degrees) puts the
        # arcs' ends where they are, to a hundred-thousandth of the part's size
        arcs = msp.query("ARC")
        if len(arcs):
            single = arc_ends(arcs, np.float32)
            assert float(np.max(np.abs(single - arc_ends(arcs, np.float64)))) <= 1e-5 * part
    # the CUT outline as written, read back by the build, within the tolerance of the exact curve
    verification = built.report["verification"]
    tolerance = built.design.manufacturing.tolerance
    check = next(c for c in built.report["checks"] if c["id"] == "verification")
    # (an undercut plate's outline is trimmed on purpose and has none; a drum's groove that
    # folds over has walls that cross, which the development cannot follow, and no cam whose
    # motion its files could hold: its verification does not apply)
    folded = any(c["id"] == "groove" and c["ok"] is False for c in built.report["checks"])
    assert check["ok"] or (folded and check.get("applicable") is False), check["message"]
    if verification["cut_outline_max_deviation_mm"] is not None and not folded:
        assert verification["cut_outline_max_deviation_mm"] <= tolerance


# ---- STL -------------------------------------------------------------------------------------

def read_binary_stl(data: bytes) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (mm, the float32 of the file as doubles; equal coordinates are one vertex) and
    faces of a binary STL."""
    count = struct.unpack("<I", data[80:84])[0]
    assert len(data) == 84 + 50 * count
    record = np.dtype([("normal", "<f4", 3), ("corners", "<f4", (3, 3)), ("attribute", "<u2")])
    corners = np.frombuffer(data, dtype=record, count=count, offset=84)["corners"]
    vertices, index = np.unique(corners.reshape(-1, 3), axis=0, return_inverse=True)
    return vertices.astype(np.float64), index.reshape(-1, 3)


@pytest.mark.parametrize("name", EVERY_DESIGN)
def test_no_stl_has_short_edges_or_slivers(every_build: dict[str, Built], name: str) -> None:
    built = every_build[name]
    stls = built.files(".stl")
    if not stls:
        assert any(item.startswith("stl") for item in built.not_produced) or (
            built.design.cam.thickness is None and built.design.cam.type != "cylindrical")
        pytest.skip(f"{name} writes no STL: {built.not_produced}")
    for path in stls:
        vertices, faces = read_binary_stl(path.read_bytes())
        corners = vertices[faces]
        edges = np.linalg.norm(np.roll(corners, -1, axis=1) - corners, axis=2)
        twice_area = np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0],
                                             corners[:, 2] - corners[:, 0]), axis=1)
        altitude = twice_area / edges.max(axis=1)
        assert edges.min() >= MIN_EDGE_MM, f"{path.name}: edge {edges.min():.3g} mm"
        assert altitude.min() >= MIN_ALTITUDE_MM, f"{path.name}: facet {altitude.min():.3g} mm"
        # closed and consistently wound: every directed edge once, and its reverse once
        directed = np.concatenate((faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]))
        assert len(np.unique(directed, axis=0)) == len(directed)
        assert np.array_equal(np.unique(directed, axis=0), np.unique(directed[:, ::-1], axis=0))
    # the build's own verification: a drum's roller run through the groove read back from
    # the STL, a plate's STL read back closed and of the part's volume
    check = next(c for c in built.report["checks"] if c["id"] == "verification")
    assert check["ok"], check["message"]


def test_the_build_finds_a_short_edge_and_its_slivers_in_the_stl_it_reads_back() -> None:
    """A closed tetrahedron with one edge split 0.05 µm from its end: the read-back check counts
    the short edge (once per face along it) and the slivers beside it, and fails."""
    import trimesh

    from camfab.export.stl import check_stl

    corners = np.array([[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [0.0, 10.0, 0.0], [0.0, 0.0, 10.0],
                        [10.0 - 5e-5, 0.0, 0.0]])
    # the edge 0-1 split at vertex 4, next to vertex 1: faces (0, 2, 1) and (0, 1, 3) in two
    faces = np.array([[0, 2, 4], [4, 2, 1], [0, 4, 3], [4, 1, 3], [0, 3, 2], [1, 2, 3]])
    mesh = trimesh.Trimesh(corners, faces, process=False)
    assert mesh.is_watertight and mesh.volume > 0
    data = mesh.export(file_type="stl")
    check = check_stl(data, float(mesh.volume), 1e-6)
    assert check.watertight and check.short_edges == 2 and check.sliver_faces == 2
    assert not check.ok


def test_the_drum_rows_leave_the_surface_between_them() -> None:
    """The groove's tube has no row of vertices on the drum's surface (where the boolean would
    leave micrometre edges): the surface cuts its last wall piece halfway."""
    from camfab.geometry.drum import drum
    from camfab.geometry.drum_mesh import groove_tube
    from camfab.pipeline import load_design

    design = load_design(Path(__file__).resolve().parents[1] / "designs/demo-cylindrical.yaml")
    d = drum(design)
    tube = groove_tube(d, design.program, 0.5 * design.manufacturing.tolerance)
    step = float(tube.radii[1] - tube.radii[0])
    gaps = np.abs(tube.radii - d.radius)
    assert float(gaps.min()) == pytest.approx(step / 2, rel=1e-9)
    assert np.allclose(np.diff(tube.radii[:-1]), step)
