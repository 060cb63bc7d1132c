"""The DXF a build writes: structure a shop's software expects, accuracy measured with ezdxf's own
flattening (independent of camfab's arc code), and the follower run over the outline as written."""

from __future__ import annotations

import io
import json
from pathlib import Path

import ezdxf
import numpy as np
import pytest
import shapely

from camfab.pipeline import analyse, design_from_text, load_design, render

from .conftest import DESIGN_FILES, DESIGNS, run_cli
from .dxf_loops import loop_sizes, loops

DISC = [p for p in DESIGN_FILES if load_design(p).cam.type == "disc"]


def hole_area(bore: float, keyway: tuple[float, float] | None) -> float:
    """Exact area of a bore of diameter *bore* with a keyway (width, depth above the bore's top):
    the circle plus the strip |x| ≤ w/2 between the circle and y = r + depth."""
    r = bore / 2
    area = np.pi * r * r
    if keyway is not None:
        half, top = keyway[0] / 2, r + keyway[1]
        area += 2 * half * top - (half * np.sqrt(r * r - half * half) + r * r * np.arcsin(half / r))
    return float(area)


def kerf_curve(design, geom) -> np.ndarray:  # type: ignore[no-untyped-def]
    """The exact working curve moved kerf/2 outward along its normal (itself without a kerf)."""
    working = geom.dense.working
    outward = geom.cam.sigma * np.stack((-working.tangent[:, 1], working.tangent[:, 0]), -1)
    return working.xy + design.manufacturing.kerf / 2 * outward


def built(path: Path):  # type: ignore[no-untyped-def]
    design = load_design(path)
    artifacts = render(analyse(design))
    doc = ezdxf.read(io.StringIO(artifacts.files[f"{design.name}.dxf"].decode()))
    report = json.loads(artifacts.files[f"{design.name}-report.json"])
    return design, artifacts, doc, report


@pytest.mark.parametrize("path", DISC, ids=[p.stem for p in DISC])
def test_dxf_structure_and_accuracy(path: Path) -> None:
    design, _artifacts, doc, report = built(path)
    assert doc.dxfversion >= "AC1015"  # R2000 or newer
    assert doc.header["$INSUNITS"] == (4 if design.units == "mm" else 1)
    assert len(doc.audit().errors) == 0
    names = {layer.dxf.name for layer in doc.layers}
    assert {"CUT", "PITCH", "BASE", "PRIME", "MARK", "NOTE"} <= names
    msp = doc.modelspace()
    assert len(msp.query("SPLINE")) == 0
    cut = msp.query('*[layer=="CUT"]')
    assert {e.dxftype() for e in cut} <= {"LWPOLYLINE", "CIRCLE", "LINE", "ARC"}
    # every line and arc is part of a closed contour
    count, sizes = loop_sizes(doc, "CUT")
    assert sum(sizes) == count
    # few entities: arcs, not thousands of tiny segments
    # the verification read every entity of the outline back
    assert report["verification"]["cut_outline_entities"] == sizes[0] < 120
    # flattened by ezdxf to 1e-5 of the file unit: simple, and within the tolerance of the exact
    # working curve
    scale = design.mm_per_unit
    ring = shapely.LinearRing(loops(doc, "CUT", 1e-5 / scale)[0] * scale)
    assert ring.is_simple
    analysis = analyse(design)
    geom = analysis.geometry
    assert geom is not None
    tolerance = design.manufacturing.tolerance
    verification = report["verification"]
    assert verification["checked_on"].startswith("CUT outline read back")
    if not geom.undercut:
        exact = shapely.points(kerf_curve(design, geom))
        assert float(np.max(shapely.distance(ring, exact))) <= tolerance
        assert verification["max_lift_error_mm"] <= tolerance
        assert verification["cut_outline_max_deviation_mm"] <= tolerance
    else:
        assert verification["max_lift_error_mm"] > tolerance  # the undercut's motion error


def test_same_design_same_bytes() -> None:
    design = load_design(DESIGNS / "seed-10-4.yaml")
    first = render(analyse(design)).files["seed-10-4.dxf"]
    second = render(analyse(design)).files["seed-10-4.dxf"]
    assert first == second


def test_inch_design_is_drawn_in_inches() -> None:
    _design, _, doc, report = built(DESIGNS / "demo-inch-flat.yaml")
    outer = loops(doc, "CUT")[0]
    radius = float(np.max(np.hypot(*outer.T)))
    assert radius == pytest.approx(report["geometry"]["max_radius_mm"] / 25.4, abs=1e-3)


def test_bore_with_keyway_is_one_closed_contour() -> None:
    text = (DESIGNS / "seed-10-4.yaml").read_text().replace(
        "  bore: 10", "  bore: 10\n  keyway: {width: 3, depth: 1.4}")
    design = design_from_text(text)
    doc = ezdxf.read(io.StringIO(render(analyse(design)).files["seed-10-4.dxf"].decode()))
    hole = loops(doc, "CUT")[-1]
    polygon = shapely.Polygon(hole)
    assert polygon.is_valid
    # the bore's circle (r = 5) with the keyway up to r + 1.4 on +Y, 3 wide
    assert float(hole[:, 1].max()) == pytest.approx(6.4, abs=1e-6)
    assert float(hole[:, 1].min()) == pytest.approx(-5.0, abs=1e-4)
    assert float(hole[hole[:, 1] > 5.5][:, 0].max()) == pytest.approx(1.5, abs=1e-9)
    assert polygon.area == pytest.approx(hole_area(10.0, (3.0, 1.4)), rel=1e-5)


def test_build_writes_the_dxf(tmp_path: Path) -> None:
    result = run_cli("build", str(DESIGNS / "seed-poly-345.yaml"), cwd=tmp_path)
    assert result.exit_code == 0
    data = (tmp_path / "exports/seed-poly-345/seed-poly-345.dxf").read_bytes()
    assert b"\n  0\nSPLINE\n" not in data and b"$INSUNITS" in data


def test_arc_fit_on_a_circle_and_a_square() -> None:
    from camfab.geometry.arcfit import fit_arcs

    angle = np.linspace(0, 2 * np.pi, 3000, endpoint=False)
    circle = fit_arcs(np.stack((20 * np.cos(angle), 20 * np.sin(angle)), -1), 1e-6)
    assert len(circle.vertices) <= 5 and np.all(np.abs(circle.bulges) <= np.tan(np.pi / 8) + 1e-9)
    assert circle.signed_area == pytest.approx(np.pi * 400, rel=1e-9)
    side = np.linspace(0, 1, 50, endpoint=False)
    zero, one = 0 * side, 1 + 0 * side
    square = np.concatenate([np.stack((side, zero), -1), np.stack((one, side), -1),
                             np.stack((1 - side, one), -1), np.stack((zero, 1 - side), -1)])
    lines = fit_arcs(square, 1e-9)
    assert len(lines.vertices) == 4 and not lines.bulges.any()


# ---- SVG -------------------------------------------------------------------------------------

@pytest.mark.parametrize("path", DISC, ids=[p.stem for p in DISC])
def test_svg_outline_at_true_size(path: Path) -> None:
    import xml.etree.ElementTree as ET

    from svgelements import Path as SvgPath

    design = load_design(path)
    analysis = analyse(design)
    data = render(analysis).files[f"{design.name}.svg"]
    root = ET.fromstring(data)
    unit = design.units
    assert root.get("width", "").endswith(unit) and root.get("height", "").endswith(unit)
    ns = "{http://www.w3.org/2000/svg}"
    outlines = root.findall(f".//{ns}path")
    d = outlines[0].get("d", "")
    assert " A" in d or d.count("A") > 0  # arcs as arcs
    # read the outline back with svgelements, flip y back and compare with the exact curve
    svg_path = SvgPath(d)
    points = np.array(svg_path.npoint(np.linspace(0.0, 1.0, 8001)))
    xy = np.stack((points[:, 0], -points[:, 1]), -1) * design.mm_per_unit
    ring = shapely.LinearRing(xy[:-1])
    assert ring.is_simple
    geom = analysis.geometry
    assert geom is not None
    if not geom.undercut:
        exact = shapely.points(kerf_curve(design, geom))
        # the reader samples its arcs: allow for that sampling on top of the tolerance
        assert float(np.max(shapely.distance(ring, exact))) <= design.manufacturing.tolerance * 1.2
    if design.cam.bore is not None and design.cam.keyway is None:
        circle = root.find(f".//{ns}circle")
        assert circle is not None
        assert float(circle.get("r", "0")) * design.mm_per_unit == pytest.approx(
            design.cam.bore / 2, abs=1e-6)


# ---- STL -------------------------------------------------------------------------------------

@pytest.mark.parametrize("path", DISC, ids=[p.stem for p in DISC])
def test_stl_plate_is_watertight_with_the_right_volume(path: Path) -> None:
    import struct

    import trimesh

    design = load_design(path)
    analysis = analyse(design)
    data = render(analysis).files[f"{design.name}.stl"]
    count = struct.unpack("<I", data[80:84])[0]
    assert len(data) == 84 + 50 * count  # binary STL
    mesh = trimesh.load(io.BytesIO(data), file_type="stl")
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.volume > 0
    thickness = design.cam.thickness
    assert thickness is not None
    assert mesh.bounds[0][2] == pytest.approx(0.0, abs=1e-6)
    assert mesh.bounds[1][2] == pytest.approx(thickness, rel=1e-6)  # mm, also for inch designs
    geom = analysis.geometry
    assert geom is not None
    # the exact plate: the dense exact profile's area less the bore's
    area = shapely.Polygon(geom.dense.working.xy).area if not geom.undercut else shapely.Polygon(
        geom.profile.vertices).area
    if design.cam.bore is not None:
        key = design.cam.keyway
        area -= hole_area(design.cam.bore, None if key is None else (key.width, key.depth))
    assert mesh.volume == pytest.approx(area * thickness, rel=1e-4)
