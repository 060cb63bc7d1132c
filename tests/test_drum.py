"""Drum (cylindrical) cams against the definition of the groove: every wall point lies on the
roller's surface at its own cam angle and no roller position reaches past it; the solid read back
from the STL has the roller-centre path in empty space and material just beyond the roller;
pressure angle and developed curvature from independent finite differences."""

from __future__ import annotations

import io
import json
import math

import ezdxf
import manifold3d
import numpy as np
import pytest
import shapely
import trimesh

from camfab.geometry.drum import drum, polar_to_xy
from camfab.pipeline import analyse, load_design, render

from .conftest import DESIGNS
from .dxf_loops import loop_sizes, loops

GOOD = DESIGNS / "demo-cylindrical.yaml"
STEEP = DESIGNS / "demo-drum-steep.yaml"


def axis_distance(points: np.ndarray, d, program, theta: np.ndarray) -> np.ndarray:  # type: ignore[no-untyped-def]
    """Distance of each 3-D point from the roller's axis at each cam angle: (points, angles).
    The axis at θ: the radial half-line at polar angle −σθ from +Y, at height start + s(θ) —
    the mechanism, not camfab's wall formula."""
    alpha = -d.sigma * theta
    direction = np.stack((-np.sin(alpha), np.cos(alpha)), -1)
    height = d.start + program.evaluate(theta)[0]
    along = points[:, None, 0] * direction[None, :, 0] + points[:, None, 1] * direction[None, :, 1]
    t = np.maximum(along, 0.0)
    dx = points[:, None, 0] - t * direction[None, :, 0]
    dy = points[:, None, 1] - t * direction[None, :, 1]
    dz = points[:, None, 2] - height[None, :]
    return np.sqrt(dx * dx + dy * dy + dz * dz)


@pytest.mark.parametrize("which", ["root", "pitch", "radius"])
def test_walls_are_the_envelope_of_the_roller(which: str) -> None:
    design = load_design(GOOD)
    d = drum(design)
    program = design.program
    r = getattr(d, which)
    theta = np.linspace(0.013, 2 * math.pi - 0.013, 240)
    m = program.evaluate(theta)
    walls = d.walls(theta, m[0], m[1], r)
    fine = np.linspace(0.0, 2 * math.pi, 60_001)
    for phi, z in ((walls.phi_lower, walls.z_lower), (walls.phi_upper, walls.z_upper)):
        points = np.concatenate((polar_to_xy(r, phi), z[:, None]), -1)
        # on the roller at its own angle ...
        own = np.diag(axis_distance(points, d, program, theta))
        assert np.max(np.abs(own - d.roller)) < 1e-9
        # ... and no roller position comes closer: the groove is 2R wide across the path
        nearest = axis_distance(points, d, program, fine).min(axis=1)
        assert np.max(np.abs(nearest - d.roller)) < 2e-6


def test_the_developed_offset_is_not_the_groove() -> None:
    """The naive walls at s ± R along the axis (the developed-plane offset) are narrower across
    the path on a steep flank: points there lie inside the roller."""
    design = load_design(GOOD)
    d = drum(design)
    program = design.program
    theta = np.radians(np.arange(10.0, 140.0, 2.0))
    s = program.evaluate(theta)[0]
    alpha = -d.sigma * theta
    naive = np.concatenate((polar_to_xy(d.pitch, alpha), (d.start + s + d.roller)[:, None]), -1)
    nearest = axis_distance(naive, d, program, np.linspace(0, 2 * math.pi, 20_001)).min(axis=1)
    # the groove is only 2R·cos φ wide across the path where the flank is steepest
    steepest = math.atan(float(np.max(np.abs(program.evaluate(theta)[1]))) / d.pitch)
    assert nearest.min() == pytest.approx(d.roller * math.cos(steepest), rel=2e-3)


def solid_from_stl(data: bytes) -> manifold3d.Manifold:
    mesh = trimesh.load(io.BytesIO(data), file_type="stl")
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.volume > 0
    return manifold3d.Manifold(manifold3d.Mesh(
        vert_properties=np.ascontiguousarray(mesh.vertices, dtype=np.float32),
        tri_verts=np.ascontiguousarray(mesh.faces, dtype=np.uint32)))


def inside(solid: manifold3d.Manifold, points: np.ndarray) -> np.ndarray:
    """Whether each point lies in the solid: the solid sliced at the point's height."""
    out = []
    for x, y, z in points:
        polygons = solid.slice(float(z)).to_polygons()
        # even-odd over the slice's loops
        count = sum(shapely.Polygon(p).contains(shapely.Point(x, y)) for p in polygons)
        out.append(count % 2 == 1)
    return np.array(out)


def test_stl_has_the_roller_path_in_empty_space_and_material_beyond_the_roller() -> None:
    design = load_design(GOOD)
    artifacts = render(analyse(design))
    solid = solid_from_stl(artifacts.files["demo-cylindrical.stl"])
    d = drum(design)
    program = design.program
    theta = np.radians(np.arange(3.0, 360.0, 7.0))
    m = program.evaluate(theta)
    alpha = -d.sigma * theta
    for r in (d.root + 0.3, d.pitch, d.radius - 0.3):
        centre = np.concatenate((polar_to_xy(r, alpha), (d.start + m[0])[:, None]), -1)
        assert not inside(solid, centre).any()
        walls = d.walls(theta, m[0], m[1], r)
        for phi, z in ((walls.phi_lower, walls.z_lower), (walls.phi_upper, walls.z_upper)):
            wall = np.concatenate((polar_to_xy(r, phi), z[:, None]), -1)
            # the wall's normal: from the nearest point of the roller's axis out to the wall
            axis_point = np.concatenate((polar_to_xy(r * np.cos(phi - alpha), alpha),
                                         (d.start + m[0])[:, None]), -1)
            normal = (wall - axis_point) / np.linalg.norm(wall - axis_point, axis=1)[:, None]
            assert inside(solid, wall + 0.02 * normal).all()
            assert not inside(solid, wall - 0.02 * normal).any()


def test_stl_volume_is_the_drum_less_bore_and_groove() -> None:
    design = load_design(GOOD)
    data = render(analyse(design)).files["demo-cylindrical.stl"]
    mesh = trimesh.load(io.BytesIO(data), file_type="stl")
    d = drum(design)
    assert mesh.bounds[0][2] == pytest.approx(0.0, abs=1e-5)
    assert mesh.bounds[1][2] == pytest.approx(d.length, abs=1e-5)
    # the groove: at each radius a band 2R wide across the path, as long as the path there
    theta = np.linspace(0.0, 2 * math.pi, 20_001)
    ds = design.program.evaluate(theta)[1]
    radii = np.linspace(d.root, d.radius, 201)
    band = [np.trapezoid(2 * d.roller * np.hypot(r, ds), theta) for r in radii]
    groove = float(np.trapezoid(band, radii))
    drum_volume = math.pi * (d.radius**2 - d.bore**2) * d.length
    assert mesh.volume == pytest.approx(drum_volume - groove, rel=2e-3)


def test_pressure_angles_follow_tan_phi_is_s_prime_over_r() -> None:
    design = load_design(GOOD)
    files = render(analyse(design)).files
    report = json.loads(files["demo-cylindrical-report.json"])
    geometry = report["geometry"]
    d = drum(design)
    theta = np.radians(np.arange(0.0, 360.0, 0.01))
    ds = np.abs(np.gradient(design.program.evaluate(theta)[0], theta))
    for key, r in (("root", d.root), ("pitch", d.pitch), ("outer", d.radius)):
        expected = math.degrees(math.atan(float(ds.max()) / r))
        assert geometry[f"{key}_pressure_angle_max_deg"] == pytest.approx(expected, abs=1e-3)
    assert geometry["groove_width_mm"] == pytest.approx(2 * 6 + 0.1)
    assert geometry["pitch_radius_mm"] == pytest.approx(50 - 8 / 2)


def test_steep_drum_is_reported_where_it_binds_and_folds() -> None:
    design = load_design(STEEP)
    artifacts = render(analyse(design))
    assert artifacts.analysis is not None and artifacts.analysis.exit_code == 1
    report = json.loads(artifacts.files["demo-drum-steep-report.json"])
    checks = {c["id"]: c for c in report["checks"] if c["id"] in ("pressure_angle", "groove")}
    assert not checks["pressure_angle"]["ok"] and not checks["groove"]["ok"]
    d = drum(design)
    theta = np.radians(np.arange(0.005, 360.0, 0.01))
    s = design.program.evaluate(theta)[0]
    h = 1e-5
    # independent: finite differences of the pitch curve developed at the floor, (rθ, s)
    s1 = (design.program.evaluate(theta + h)[0] - design.program.evaluate(theta - h)[0]) / (2 * h)
    s2 = (design.program.evaluate(theta + h)[0] - 2 * s
          + design.program.evaluate(theta - h)[0]) / h**2
    with np.errstate(divide="ignore"):  # straight where s″ = 0
        rho = (d.root**2 + s1**2) ** 1.5 / np.abs(d.root * s2)
    tight = np.degrees(theta[rho < d.roller * 0.98])

    def covered(angle: float, ranges: list[list[float]]) -> bool:
        return any((a - 0.05 <= angle <= b + 0.05) if a <= b else (angle >= a or angle <= b)
                   for a, b in ranges)

    assert tight.size and all(covered(a, checks["groove"]["ranges_deg"]) for a in tight)
    steep = np.degrees(theta[np.degrees(np.arctan(np.abs(s1) / d.root)) > 30.5])
    assert all(covered(a, checks["pressure_angle"]["ranges_deg"]) for a in steep)
    # the folded groove has no solid: no STL, and the build says why
    assert "demo-drum-steep.stl" not in artifacts.files
    assert any(item.startswith("stl (the groove folds") for item in artifacts.not_produced)


def test_development_holds_the_walls_within_the_tolerance() -> None:
    design = load_design(GOOD)
    files = render(analyse(design)).files
    doc = ezdxf.read(io.StringIO(files["demo-cylindrical.dxf"].decode()))
    assert doc.header["$INSUNITS"] == 4
    assert len(doc.audit().errors) == 0
    assert len(doc.modelspace().query("SPLINE")) == 0
    count, sizes = loop_sizes(doc, "CUT")
    assert len(sizes) == 1 and sizes[0] == count  # one closed contour: the groove, cut at the seam
    band = loops(doc, "CUT", 1e-6)[0]
    d = drum(design)
    theta = np.linspace(0.0, 2 * math.pi, 7201)
    m = design.program.evaluate(theta)
    walls = d.walls(theta, m[0], m[1], d.radius)
    shift = 2 * math.pi if d.sigma > 0 else 0.0
    exact = np.concatenate([np.stack((d.radius * (phi + shift), z), -1) for phi, z in
                            ((walls.phi_lower, walls.z_lower), (walls.phi_upper, walls.z_upper))])
    gap = shapely.distance(shapely.points(exact), shapely.LinearRing(band))
    assert float(gap.max()) <= design.manufacturing.tolerance
    # the developed surface is 2πR long
    assert np.ptp(band[:, 0]) == pytest.approx(2 * math.pi * d.radius, abs=1e-3)
    report = json.loads(files["demo-cylindrical-report.json"])
    assert report["verification"]["max_lift_error_mm"] <= design.manufacturing.tolerance
    assert report["verification"]["stl"]["watertight"]
