"""Groove (face-groove, positive-drive) cams against the definition of the groove: both walls lie
one roller radius (plus half the clearance) from the pitch curve, which THEORY §B's closed forms
give here independently of camfab's curves; the groove is twice that wide along the normal; the
``groove`` check fails where the pitch curve bends more sharply (measured here by finite
differences); contact changes walls at the zeros of s″ of the laws' closed forms; the STL read
back from disk has the plate's volume less the bore and the pocket (areas from shapely)."""

from __future__ import annotations

import io
import json
import math
import re
from pathlib import Path

import ezdxf
import numpy as np
import pytest
import shapely
import trimesh

from camfab.design import Design
from camfab.geometry.groove import wall_contact
from camfab.pipeline import analyse, design_from_text, load_design, render

from .conftest import DESIGNS, run_cli
from .dxf_loops import loop_sizes, loops

GOOD = DESIGNS / "demo-groove-roller.yaml"
SWING = DESIGNS / "demo-groove-oscillating.yaml"

#: ezdxf flattens the arcs read back within this (mm): far below the tolerance.
SAGITTA = 1e-6


# ---- independent references ------------------------------------------------------------------

def half_width(design: Design) -> float:
    fol = design.follower
    assert fol.roller_radius is not None
    return fol.roller_radius + fol.groove_clearance / 2


def pitch_curve(design: Design, theta: np.ndarray) -> np.ndarray:
    """The roller centre in the cam frame (THEORY §B): the trace point in the frame — on the
    line x = e at height √(Rp² − e²) + s, or on the arm at Ψ = ψ₀ + ψ — turned by Rot(−σθ)."""
    cam, fol = design.cam, design.follower
    assert cam.base_radius is not None
    rp = cam.base_radius + half_width(design)
    s = design.program.evaluate(theta)[0]
    if fol.oscillating:
        a, arm = fol.pivot_distance or 0.0, fol.arm_length or 0.0
        psi = math.acos((a * a + arm * arm - rp * rp) / (2 * a * arm)) + s
        fx, fy = a - arm * np.cos(psi), arm * np.sin(psi)
    else:
        fx, fy = np.full_like(s, fol.offset), math.sqrt(rp * rp - fol.offset**2) + s
    c, sn = np.cos(cam.sigma * theta), np.sin(cam.sigma * theta)
    return np.stack((c * fx + sn * fy, -sn * fx + c * fy), axis=-1)


def outward_normals(design: Design, theta: np.ndarray) -> np.ndarray:
    """Unit normals of the pitch curve pointing away from the cam, by central differences."""
    h = 1e-6
    tangent = (pitch_curve(design, theta + h) - pitch_curve(design, theta - h)) / (2 * h)
    tangent /= np.hypot(*tangent.T)[:, None]
    right = np.stack((tangent[:, 1], -tangent[:, 0]), axis=-1)
    # the cam-frame curve of a ccw cam runs clockwise: its right normal points inward
    return -design.cam.sigma * right


def pitch_radius(design: Design, theta: np.ndarray) -> np.ndarray:
    """Signed radius of curvature of the pitch curve (convex positive), by central differences:
    −σ·|P′|³/(P′ × P″) (THEORY §B, generic definitions)."""
    h = 1e-4
    p0, p1, p2 = (pitch_curve(design, theta + k * h) for k in (-1, 0, 1))
    d1, d2 = (p2 - p0) / (2 * h), (p2 - 2 * p1 + p0) / h**2
    cross = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
    return -design.cam.sigma * np.hypot(*d1.T) ** 3 / cross


def chain_distance(points: np.ndarray, chain: np.ndarray) -> np.ndarray:
    """Distance of each of *points* from the closed polyline *chain* (a nearest-segment search:
    the chain cut into pieces of at most 0.02 mm by shapely, the pieces next to the nearest
    vertices (scipy's KD-tree) measured exactly) — shapely's own distance to a ring of thousands
    of vertices takes seconds here."""
    from scipy.spatial import cKDTree

    ring = np.asarray(shapely.segmentize(shapely.LinearRing(chain), 0.02).coords)[:-1]
    _, near = cKDTree(ring).query(points, k=8)
    best = np.full(len(points), np.inf)
    for shift in (0, -1):
        a = ring[(near + shift) % len(ring)]
        b = ring[(near + shift + 1) % len(ring)]
        d = b - a
        rel = points[:, None, :] - a
        t = np.clip(np.einsum("nkj,nkj->nk", rel, d) / np.einsum("nkj,nkj->nk", d, d), 0, 1)
        gap = np.hypot(*np.moveaxis(rel - t[..., None] * d, -1, 0))
        best = np.minimum(best, gap.min(axis=1))
    return best


def exact_walls(design: Design, step_deg: float = 0.02) -> tuple[np.ndarray, np.ndarray]:
    """The outer and inner walls: the pitch curve moved R along its normals, densely."""
    theta = np.radians(np.arange(0.0, 360.0, step_deg))
    centre, normal = pitch_curve(design, theta), outward_normals(design, theta)
    radius = half_width(design)
    return centre + radius * normal, centre - radius * normal


# ---- builds ----------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Both example groove designs built once by the command line, into one folder."""
    folder = tmp_path_factory.mktemp("groove")
    for design in (GOOD, SWING):
        result = run_cli("build", str(design), "-o", str(folder))
        assert result.exit_code == 0, result.output + result.stderr
    return folder


def test_cli_build_writes_every_file(built: Path) -> None:
    for name in (GOOD.stem, SWING.stem):
        assert sorted(p.name for p in built.glob(f"{name}*")) == sorted(
            f"{name}{suffix}" for suffix in (".dxf", ".svg", ".stl", "-report.html",
                                             "-report.json", "-motion.csv"))
        report = json.loads((built / f"{name}-report.json").read_text())
        assert report["cam_type"] == "groove" and report["status"]["exit_code"] == 0
        assert report["verification"]["max_lift_error_mm"] <= 0.002


@pytest.mark.parametrize("path", [GOOD, SWING], ids=["translating", "oscillating"])
def test_walls_read_back_lie_one_radius_from_the_exact_pitch_curve(built: Path,
                                                                   path: Path) -> None:
    design = load_design(path)
    radius, tolerance = half_width(design), design.manufacturing.tolerance
    doc = ezdxf.readfile(built / f"{design.name}.dxf")
    walls = loops(doc, "POCKET", SAGITTA)
    assert len(walls) == 2
    # from the exact pitch point at many cam angles to each wall: R
    theta = np.radians(np.arange(0.0, 360.0, 0.1))
    centres = pitch_curve(design, theta)
    for wall in walls:
        gap = chain_distance(centres, wall) - radius
        assert np.max(np.abs(gap)) <= tolerance
    # and every point of each wall R from the densely sampled pitch polyline
    pitch = pitch_curve(design, np.radians(np.arange(0.0, 360.0, 0.01)))
    for wall in walls:
        gap = chain_distance(wall, pitch) - radius
        assert np.max(np.abs(gap)) <= tolerance


def test_groove_is_twice_the_radius_wide_along_the_normal(built: Path) -> None:
    design = load_design(GOOD)
    radius, tolerance = half_width(design), design.manufacturing.tolerance
    outer, inner = loops(ezdxf.readfile(built / f"{design.name}.dxf"), "POCKET", SAGITTA)
    theta = np.radians(np.arange(0.0, 360.0, 0.5))
    centre, normal = pitch_curve(design, theta), outward_normals(design, theta)
    across = shapely.linestrings(np.stack((centre - 2 * radius * normal,
                                           centre + 2 * radius * normal), axis=1))
    reach = {}
    for name, wall in (("outer", outer), ("inner", inner)):
        hits, index = shapely.get_coordinates(shapely.intersection(across, shapely.LinearRing(
            wall)), return_index=True)
        along = np.einsum("ij,ij->i", hits - centre[index], normal[index])
        signed = np.full(theta.size, np.nan)
        signed[index] = along  # one crossing per wall along each normal
        assert np.bincount(index, minlength=theta.size).max() == 1
        reach[name] = signed
    assert np.all(np.abs(reach["outer"] - radius) <= tolerance)
    assert np.all(np.abs(reach["inner"] + radius) <= tolerance)
    assert np.all(np.abs(reach["outer"] - reach["inner"] - 2 * radius) <= 2 * tolerance)


def test_dxf_layers_entities_and_notes(built: Path) -> None:
    design = load_design(GOOD)
    report = json.loads((built / f"{design.name}-report.json").read_text())
    doc = ezdxf.readfile(built / f"{design.name}.dxf")
    assert doc.header["$INSUNITS"] == 4
    msp = doc.modelspace()
    assert len(msp.query("SPLINE")) == 0
    assert {e.dxftype() for e in msp.query('*[layer=="POCKET"]')} <= {"LINE", "ARC"}
    count, sizes = loop_sizes(doc, "POCKET")
    assert len(sizes) == 2 and sum(sizes) == count  # two closed walls, nothing loose
    # CUT: the plate's circle and the bore with its keyway, one closed chain
    circles = [c.dxf.radius for c in msp.query('CIRCLE[layer=="CUT"]')]
    outer_radius = report["geometry"]["outer_radius_mm"]
    assert circles == [pytest.approx(outer_radius, abs=1e-9)]
    # the default plate: the outer wall's largest radius plus a rim of the roller radius (at
    # least 3 mm), rounded up to a whole mm
    reach = float(np.max(np.hypot(*exact_walls(design)[0].T)))
    assert outer_radius == math.ceil(reach + max(3.0, design.follower.roller_radius or 0.0))
    _, bore = loop_sizes(doc, "CUT")
    assert len(bore) == 1
    notes = " ".join(t.dxf.text for t in msp.query('TEXT[layer=="NOTE"]'))
    assert "groove depth 8 mm" in notes and "groove width 16.1 mm" in notes
    assert {"PITCH", "BASE", "PRIME", "MARK"} <= {e.dxf.layer for e in msp}
    # a tick across the groove at every wall change
    assert len(msp.query('LINE[layer=="MARK"]')) == 3 + len(report["geometry"]["wall_changes_deg"])


def test_stl_is_watertight_with_the_plate_less_bore_and_pocket(built: Path) -> None:
    design = load_design(GOOD)
    cam = design.cam
    assert cam.thickness is not None and cam.groove_depth is not None and cam.bore is not None
    assert cam.keyway is not None
    mesh = trimesh.load(built / f"{design.name}.stl", file_type="stl")
    assert mesh.is_watertight and mesh.is_winding_consistent
    t, depth = cam.thickness, cam.groove_depth
    assert sorted({round(float(z), 4) for z in mesh.vertices[:, 2]}) == [0.0, t - depth, t]
    report = json.loads((built / f"{design.name}-report.json").read_text())
    r_o = report["geometry"]["outer_radius_mm"]
    r, key = cam.bore / 2, cam.keyway
    bore = shapely.Point(0, 0).buffer(r, quad_segs=2048).union(
        shapely.box(-key.width / 2, 0.0, key.width / 2, r + key.depth))
    outer, inner = (shapely.Polygon(w) for w in exact_walls(design))
    pocket = outer.area - inner.area
    expected = (math.pi * r_o**2 - bore.area) * t - pocket * depth
    # the tolerance along every contour through its height
    allowance = design.manufacturing.tolerance * (
        (2 * math.pi * r_o + bore.length) * t + (outer.length + inner.length) * depth)
    assert abs(mesh.volume - expected) <= allowance


def test_toolpath_runs_the_cutter_along_each_wall(built: Path) -> None:
    design = load_design(SWING)
    cutter = design.manufacturing.cutter_radius
    radius, tolerance = half_width(design), design.manufacturing.tolerance
    paths = loops(ezdxf.readfile(built / f"{design.name}.dxf"), "TOOLPATH", SAGITTA)
    assert len(paths) == 4  # round the plate, two groove passes, inside the bore
    pitch = pitch_curve(design, np.radians(np.arange(0.0, 360.0, 0.01)))
    for path in paths[1:3]:
        gap = chain_distance(path, pitch) - (radius - cutter)
        assert np.max(np.abs(gap)) <= tolerance


def test_kerf_moves_the_cut_not_the_pocket_in_an_inch_design() -> None:
    text = """\
name: groove-inch
units: in
cam: {type: groove, base_radius: 1.5, thickness: 0.5, groove_depth: 0.3, bore: 0.5}
follower: {type: roller, roller_radius: 0.3125, groove_clearance: 0.004}
motion:
  - rise: {angle: 150, lift: 0.6, law: cycloidal}
  - dwell: {angle: 30}
  - return: {angle: 150, law: cycloidal}
  - dwell: {angle: 30}
manufacturing: {tolerance: 0.005, kerf: 0.008}
outputs: [dxf]
"""
    design = design_from_text(text, "inch.yaml")
    artifacts = render(analyse(design))
    assert list(artifacts.files) == ["groove-inch.dxf"]
    doc = ezdxf.read(io.StringIO(artifacts.files["groove-inch.dxf"].decode()))
    assert doc.header["$INSUNITS"] == 1
    analysis = artifacts.analysis
    assert analysis is not None and analysis.groove is not None
    half_kerf = 0.004 * 25.4
    radii = sorted(c.dxf.radius * 25.4 for c in doc.modelspace().query('CIRCLE[layer=="CUT"]'))
    assert radii == [pytest.approx(0.25 * 25.4 - half_kerf, abs=1e-9),
                     pytest.approx(analysis.groove.outer_radius + half_kerf, abs=1e-9)]
    walls = [w * 25.4 for w in loops(doc, "POCKET", SAGITTA)]
    centres = pitch_curve(design, np.radians(np.arange(0.0, 360.0, 0.25)))
    for wall in walls:  # milled: no kerf
        gap = chain_distance(centres, wall) - half_width(design)
        assert np.max(np.abs(gap)) <= design.manufacturing.tolerance


# ---- the groove check ------------------------------------------------------------------------

GROOVE = """\
name: groove-check
cam: {{type: groove, base_radius: {base}, thickness: 14, groove_depth: 8}}
follower: {{type: roller, roller_radius: {roller}, groove_clearance: 0.2}}
motion:
  - rise: {{angle: 60, lift: {lift}, law: harmonic}}
  - dwell: {{angle: 40}}
  - return: {{angle: 60, law: harmonic}}
  - dwell: {{angle: 200}}
manufacturing: {{tolerance: 0.01}}
"""


@pytest.mark.parametrize(("base", "roller", "lift", "folds"), [
    (18.0, 11.9, 30.0, "outer"),   # prime 30: concave radius down to 8.6 mm < R = 12 < convex
    (14.0, 25.9, 20.0, "inner"),   # prime 40: convex radius down to 24 mm < R = 26 < concave
    (30.0, 9.9, 20.0, None),       # prime 40: R = 10 below both
])
def test_groove_check_fails_where_either_wall_folds(base: float, roller: float, lift: float,
                                                    folds: str | None) -> None:
    design = design_from_text(GROOVE.format(base=base, roller=roller, lift=lift), "g.yaml")
    radius = half_width(design)
    theta = np.radians(np.arange(0.0, 360.0, 0.05))
    rho = pitch_radius(design, theta)
    convex, concave = rho[rho > 0].min(), (-rho[rho < 0]).min()
    expect_outer, expect_inner = concave < radius, convex < radius
    assert (expect_outer, expect_inner) == (folds == "outer", folds == "inner")
    analysis = analyse(design)
    finding = next(f for f in analysis.findings if f.id == "groove")
    assert finding.severity == "error" and finding.ok == (folds is None)
    assert finding.limit == pytest.approx(radius)
    assert finding.value == pytest.approx(min(convex, concave), rel=1e-3)
    assert "undercut" not in {f.id for f in analysis.findings}  # the groove check says it
    if folds is None:
        return
    assert f"the {folds} wall folds over" in finding.message
    other = "inner" if folds == "outer" else "outer"
    assert f"the {other} wall folds over" not in finding.message
    # the ranges hold the angle where the pitch curve bends most sharply
    worst = float(np.degrees(theta[np.argmin(np.abs(rho))]))
    assert any(a - 0.1 <= worst <= b + 0.1 for a, b in finding.ranges_deg)


# ---- wall changes ----------------------------------------------------------------------------

WALLS = """\
name: walls
cam: {{type: groove, base_radius: 40, thickness: 14, groove_depth: 8}}
follower: {{type: roller, roller_radius: 8}}
motion:
{motion}
"""


@pytest.mark.parametrize(("motion", "changes", "onto"), [
    # harmonic: s″ = h·π²/(2β²)·cos(πθ/β) changes sign at β/2 (a return's: mirrored)
    (["rise: {angle: 100, lift: 10, law: harmonic}", "dwell: {angle: 80}",
      "return: {angle: 100, law: harmonic}", "dwell: {angle: 80}"], [50.0, 230.0], [-1, 1]),
    # cycloidal: s″ = 2πh/β²·sin(2πθ/β), zero at the ends (no change across the dwells)
    (["rise: {angle: 120, lift: 10, law: cycloidal}", "dwell: {angle: 40}",
      "return: {angle: 90, law: cycloidal}", "dwell: {angle: 110}"], [60.0, 205.0], [-1, 1]),
    # uniform acceleration: s″ steps from +4h/β² to −4h/β² at β/2
    (["rise: {angle: 90, lift: 10, law: uniform-acceleration}", "dwell: {angle: 90}",
      "return: {angle: 90, law: uniform-acceleration}", "dwell: {angle: 90}"],
     [45.0, 225.0], [-1, 1]),
    # two rises: the outer wall holds the first's end, the inner wall takes the second's start
    # (a harmonic rise starts with s″ > 0) after the dwell
    (["rise: {angle: 90, lift: 10, law: cycloidal}", "dwell: {angle: 60}",
      "rise: {angle: 90, lift: 10, law: harmonic}", "return: {angle: 90, law: cycloidal}",
      "dwell: {angle: 30}"], [45.0, 150.0, 195.0, 285.0], [-1, 1, -1, 1]),
])
def test_contact_changes_walls_at_the_zeros_of_the_acceleration(
        motion: list[str], changes: list[float], onto: list[int]) -> None:
    design = design_from_text(WALLS.format(motion="\n".join(f"  - {m}" for m in motion)),
                              "w.yaml")
    contact = wall_contact(design.program)
    assert contact.changes_deg == pytest.approx(changes, abs=1e-7)
    assert contact.onto.tolist() == onto


def test_report_and_summary_say_where_contact_changes_walls(built: Path) -> None:
    page = (built / f"{GOOD.stem}-report.html").read_text()
    table = page[page.index('id="wall-changes"'):page.index('id="numbers"')]
    rows = re.findall(r'<tr><td class="num">([\d.]+)</td><td>(\w+) wall</td><td>(\w+) wall</td>',
                      table)
    assert rows == [("55", "inner", "outer"), ("215", "outer", "inner")]
    assert "reverses its spin" in table
    result = run_cli("check", str(GOOD))
    assert result.exit_code == 0
    summary = " ".join(result.output.split())
    assert "16.1 mm wide" in summary and "8 mm deep" in summary
    assert "reverses its spin) at 55°, 215°" in summary


def test_inspect_measures_a_groove_drawing_s_two_walls(built: Path, tmp_path: Path) -> None:
    """The groove's own drawing, inspected against its design, gives the design's motion: the
    roller run between its two walls (DXF arcs within the build's tolerance) departs from it by
    a fraction of the tolerance, and the play is the design's clearance."""
    import json

    result = run_cli("inspect", str(built / f"{GOOD.stem}.dxf"), "--design", str(GOOD), "-o",
                     str(tmp_path / "out"))
    assert result.exit_code == 0, result.stderr
    report = json.loads((tmp_path / "out" / f"{GOOD.stem}-inspection.json").read_text())
    tolerance = load_design(GOOD).manufacturing.tolerance
    assert report["motion"]["max_error_mm"] < 2 * tolerance  # the walls within it, over cos φ
    assert report["scan"]["on_flanks"] == report["scan"]["points"]
    clearance = load_design(GOOD).follower.groove_clearance
    assert report["motion"]["backlash"]["min_mm"] == pytest.approx(clearance, abs=2 * tolerance)
    assert report["motion"]["backlash"]["max_mm"] == pytest.approx(clearance, abs=2 * tolerance)


def test_wall_forces_are_the_follower_inertia() -> None:
    design = load_design(GOOD)
    walls = analyse(design).groove
    assert walls is not None
    omega = design.cam.omega
    mass = design.follower.mass
    assert omega is not None and mass is not None
    # cycloidal rise and return of 20 mm over 110°: |s″| ≤ 2π·h/β²
    peak = mass * omega**2 * 2 * math.pi * 20.0 / math.radians(110.0) ** 2 / 1000.0
    numbers = walls.report_geometry()
    assert numbers["max_inner_wall_force_N"] == pytest.approx(peak, rel=1e-6)
    assert numbers["max_outer_wall_force_N"] == pytest.approx(peak, rel=1e-6)
    assert numbers["wall_changes_deg"] == pytest.approx([55.0, 215.0], abs=1e-7)


# ---- refused designs -------------------------------------------------------------------------

BASE = GOOD.read_text()


@pytest.mark.parametrize(("old", "new", "field", "words"), [
    ("  groove_depth: 8", "  groove_depth: 13.5", "cam.groove_depth", "floor"),
    ("  bore: 12", "  outer_radius: 70\n  bore: 12", "cam.outer_radius",
     "outer wall reaches 76.05"),
    ("  - dwell:  {angle: 90}", "  - dwell:  {angle: 90}\nspring: {rate: 5, preload: 10}",
     "spring", "positive drive"),
    ("  type: roller\n  motion: translating\n  offset: 4\n  roller_radius: 8",
     "  type: knife\n  motion: translating\n  offset: 4", "follower.type",
     "takes a roller follower"),
])
def test_bad_groove_design_exits_2_with_one_located_line(tmp_path: Path, old: str, new: str,
                                                          field: str, words: str) -> None:
    assert old in BASE
    text = BASE.replace(old, new, 1)
    (tmp_path / "design.yaml").write_text(text)
    result = run_cli("build", "design.yaml", cwd=tmp_path)
    assert result.exit_code == 2, result.output
    message = result.stderr.strip()
    assert "\n" not in message and "Traceback" not in message
    key = field.split(".")[-1] + ":"  # the line of the key the message names
    at = BASE.index(old) if key in old or key in new else 0
    line = text[:text.index(key, at)].count("\n") + 1
    assert message.startswith(f"design.yaml:{line}: {field}: "), message
    assert words in message, message
    assert not (tmp_path / "exports").exists()
