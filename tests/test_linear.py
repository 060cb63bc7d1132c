"""Linear (translating) cams against independent references: the motion laws' closed forms in
travel (s(x), ds/dx, d²s/dx²) written out here, the pitch curve densely sampled, the roller's
distance from it, the plate's area by the trapezoid rule, shapely's distances for the follower
on a cut plate, the DXF read back by ezdxf's edge miner and the STL read back by trimesh."""

from __future__ import annotations

import csv
import io
import json
import math
import re
import subprocess
from pathlib import Path

import ezdxf
import numpy as np
import pytest
import shapely
import trimesh
from scipy.spatial import cKDTree

from camfab.curves.profile import Profile
from camfab.geometry.linear import follower_heights, linear_cam
from camfab.pipeline import Analysis, Artifacts, analyse, design_from_text, load_design, render

from .conftest import DESIGNS, run_cli
from .dxf_loops import loops

ROLLER = DESIGNS / "demo-linear-roller.yaml"
KNIFE = DESIGNS / "demo-linear-knife.yaml"

#: demo-linear-roller: stroke 240; cycloidal rise of 20 over 0–80; dwell to 120; harmonic
#: return of 20 over 120–200; dwell to 240; base height 30, roller 8, thickness 8.
STROKE, H0, R, LIFT, THICKNESS = 240.0, 30.0, 8.0, 20.0, 8.0


def motion_of_demo(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """s, ds/dx and d²s/dx² of demo-linear-roller at travels *x* (mm, periodic), from the laws'
    closed forms in travel: cycloidal s = h(u − sin 2πu/2π), harmonic return s = h/2(1 + cos πu).
    """
    x = np.mod(x, STROKE)
    s, sx, sxx = np.zeros_like(x), np.zeros_like(x), np.zeros_like(x)
    rise = x < 80.0
    u = x[rise] / 80.0
    s[rise] = LIFT * (u - np.sin(2 * np.pi * u) / (2 * np.pi))
    sx[rise] = LIFT / 80.0 * (1 - np.cos(2 * np.pi * u))
    sxx[rise] = LIFT / 80.0**2 * 2 * np.pi * np.sin(2 * np.pi * u)
    top = (x >= 80.0) & (x < 120.0)
    s[top] = LIFT
    back = (x >= 120.0) & (x < 200.0)
    u = (x[back] - 120.0) / 80.0
    s[back] = LIFT / 2 * (1 + np.cos(np.pi * u))
    sx[back] = -LIFT / 2 * np.pi / 80.0 * np.sin(np.pi * u)
    sxx[back] = -LIFT / 2 * (np.pi / 80.0) ** 2 * np.cos(np.pi * u)
    return s, sx, sxx


def exact_working(x: np.ndarray) -> np.ndarray:
    """The roller's envelope of demo-linear-roller from the closed forms: the pitch point
    (x, h0 + s) moved R toward the plate along the curve's normal (−s_x, 1)/√(1 + s_x²)."""
    s, sx, _ = motion_of_demo(x)
    root = np.sqrt(1 + sx * sx)
    return np.stack((x + R * sx / root, H0 + s - R / root), axis=-1)


@pytest.fixture(scope="module")
def built() -> Artifacts:
    return render(analyse(load_design(ROLLER)))


@pytest.fixture
def roller(built: Artifacts) -> Analysis:
    assert built.analysis is not None
    return built.analysis


@pytest.fixture
def roller_files(built: Artifacts) -> dict[str, bytes]:
    return built.files


def harmonic_design(rise_mm: float, travel_mm: float, stroke: float = 300.0,
                    roller: str = "{type: roller, roller_radius: 6}") -> str:
    rest = stroke - 2 * travel_mm
    return (f"name: h\ncam: {{type: linear, stroke: {stroke}, base_height: 40}}\n"
            f"follower: {roller}\nmotion:\n"
            f"  - rise: {{travel: {travel_mm}, lift: {rise_mm}, law: harmonic}}\n"
            f"  - dwell: {{travel: {rest / 2}}}\n"
            f"  - return: {{travel: {travel_mm}, law: harmonic}}\n"
            f"  - dwell: {{travel: {rest / 2}}}\n")


# -- the exact curves ---------------------------------------------------------------------------

def test_pressure_angle_is_atan_of_the_slope_on_rise_and_return() -> None:
    h, length, stroke = 25.0, 90.0, 300.0
    design = design_from_text(harmonic_design(h, length, stroke))
    cam = linear_cam(design)
    program = design.program
    dwell = (stroke - 2 * length) / 2
    x = np.linspace(0.0, length, 997)[1:-1]
    expected = np.arctan(h * np.pi / (2 * length) * np.sin(np.pi * x / length))
    phi = cam.pressure_angle(program.evaluate(2 * np.pi * x / stroke))
    assert np.max(np.abs(phi - expected)) < 1e-9
    assert phi.min() > 0  # a rise: the normal leans forward, counter-clockwise from +Y
    back = length + dwell + x
    phi_back = cam.pressure_angle(program.evaluate(2 * np.pi * back / stroke))
    assert np.max(np.abs(phi_back + expected)) < 1e-9
    # the analysis grid says the same
    analysis = analyse(design)
    assert analysis.linear is not None
    dense = analysis.linear.dense
    rise = dense.travel < length
    ref = np.arctan(h * np.pi / (2 * length) * np.sin(np.pi * dense.travel[rise] / length))
    assert np.max(np.abs(dense.pressure_angle[rise] - ref)) < 1e-9
    worst = h * np.pi / (2 * length)
    assert analysis.numbers is not None
    assert analysis.numbers.pressure_angle.value == pytest.approx(math.degrees(math.atan(worst)),
                                                                  abs=1e-9)


def test_pitch_radius_of_curvature_against_the_closed_form() -> None:
    h, length = 25.0, 90.0
    design = design_from_text(harmonic_design(h, length))
    cam = linear_cam(design)
    k = 2 * np.pi / 300.0
    # s = h/2 (1 − cos πx/L): s_x = hπ/2L sin, s_xx = hπ²/2L² cos, ρ = −(1 + s_x²)^1.5 / s_xx
    x = np.array([length / 4, length / 3, 0.75 * length, 0.9 * length])
    sx = h * np.pi / (2 * length) * np.sin(np.pi * x / length)
    sxx = h * np.pi**2 / (2 * length**2) * np.cos(np.pi * x / length)
    rho = cam.pitch(x, design.program.evaluate(k * x)).radius
    np.testing.assert_allclose(rho, -((1 + sx * sx) ** 1.5) / sxx, rtol=1e-10)
    # at the foot of the rise a hollow of radius 2L²/(hπ²), at its top a crest of that radius
    ends = np.array([1e-9, length - 1e-9])
    rho_ends = cam.pitch(ends, design.program.evaluate(k * ends)).radius
    np.testing.assert_allclose(rho_ends, [-2 * length**2 / (h * np.pi**2),
                                          2 * length**2 / (h * np.pi**2)], rtol=1e-6)
    # and the circle through three nearby points of the pitch curve (a generic definition)
    xs = np.linspace(5.0, 85.0, 33)
    d = 1e-3
    pts = [np.stack((xx, 40 + design.program.evaluate(k * xx)[0]), -1)
           for xx in (xs - d, xs, xs + d)]
    a, b, c = (np.hypot(*(p - q).T) for p, q in ((pts[1], pts[2]), (pts[0], pts[2]),
                                                 (pts[0], pts[1])))
    e1, e2 = pts[1] - pts[0], pts[2] - pts[1]
    turn = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    circum = a * b * c / (2 * np.abs(turn)) * -np.sign(turn)  # turning clockwise: convex
    rho_mid = cam.pitch(xs, design.program.evaluate(k * xs)).radius
    finite = np.abs(rho_mid) < 1e4
    np.testing.assert_allclose(rho_mid[finite], circum[finite], rtol=1e-4)


def test_every_working_point_is_one_roller_radius_from_the_pitch_curve(roller: Analysis) -> None:
    geom = roller.linear
    assert geom is not None
    # the pitch curve every 1.4 µm: the nearest sample is within (h/2)²/2R = 3e-8 mm of the
    # nearest point of the curve
    dense_x = np.linspace(-20.0, STROKE + 20.0, 200_001)
    s, _, _ = motion_of_demo(dense_x)
    tree = cKDTree(np.stack((dense_x, H0 + s), -1))
    working = geom.dense.working.xy
    distance, _ = tree.query(working)
    assert np.max(np.abs(distance - R)) < 1e-7
    # and it is the closed form's envelope
    assert np.max(np.hypot(*(working - exact_working(geom.dense.travel)).T)) < 1e-9


def test_the_dxf_cut_contour_lies_within_the_tolerance_of_the_exact_curve(
        roller_files: dict[str, bytes]) -> None:
    doc = ezdxf.read(io.StringIO(roller_files["demo-linear-roller.dxf"].decode()))
    assert doc.header["$INSUNITS"] == 4
    msp = doc.modelspace()
    assert not msp.query("SPLINE")
    cut = loops(doc, "CUT", sagitta=1e-5)
    assert len(cut) == 1
    ring = shapely.LinearRing(cut[0])
    assert ring.is_simple
    tolerance = 0.001
    x = np.linspace(0.0, STROKE, 4_801)
    exact = exact_working(x)
    assert float(np.max(shapely.distance(ring, shapely.points(exact)))) < tolerance
    # the plate runs a roller radius beyond the stroke at both ends, down to the base line
    low, high = cut[0].min(axis=0), cut[0].max(axis=0)
    assert low == pytest.approx([-R, 0.0], abs=1e-9)
    assert high[0] == pytest.approx(STROKE + R, abs=1e-9)
    assert high[1] == pytest.approx(H0 + LIFT - R, abs=tolerance)
    layers = {e.dxf.layer for e in msp}
    assert {"CUT", "PITCH", "PRIME", "BASE", "MARK", "NOTE"} <= layers
    note = " ".join(e.dxf.text for e in msp.query('TEXT[layer=="NOTE"]'))
    assert "linear cam" in note and "-X" in note


def test_the_follower_on_the_dxf_read_back_follows_the_design(roller: Analysis) -> None:
    check = roller.verification
    assert check is not None and "read back" in check.source
    theta = check.lift.theta
    assert np.max(np.diff(theta)) * STROKE / (2 * np.pi) <= 0.1 + 1e-12
    assert check.lift.max_mm < 0.001
    assert check.deviation_mm is not None and check.deviation_mm < 0.001


def test_simulated_roller_on_a_line_and_an_arc() -> None:
    """A plate whose top is the line y = a + b·x up to x = 45, then a step down onto a convex arc
    of radius ρ about (c, 0): a roller's centre over the line is at a + b·u + R√(1 + b²), over
    the arc at √((ρ + R)² − (u − c)²) while its contact point lies on the arc."""
    a, b, rho, c, r = 10.0, 0.2, 20.0, 60.0, 4.0
    foot = math.sqrt(rho**2 - (c - 45.0) ** 2)
    sweep = math.acos((45.0 - c) / rho)  # from the arc's right end (angle 0) over the top
    # counter-clockwise: base line, the arc, up the step, the line back to the left, down
    vertices = np.array([[0.0, 0.0], [c + rho, 0.0], [45.0, foot], [45.0, a + b * 45.0],
                         [0.0, a]])
    bulges = np.array([0.0, math.tan(sweep / 4), 0.0, 0.0, 0.0])
    profile = Profile.from_points(vertices, bulges)
    u = np.linspace(2.0, 30.0, 50)
    np.testing.assert_allclose(follower_heights(profile, r, u),
                               a + b * u + r * math.sqrt(1 + b * b), atol=1e-12)
    u = np.linspace(52.0, 72.0, 50)  # contact on the arc's span
    np.testing.assert_allclose(follower_heights(profile, r, u),
                               np.sqrt((rho + r) ** 2 - (u - c) ** 2), atol=1e-12)
    # a knife on the line is on the line, on the arc on the arc
    u = np.linspace(1.0, 44.0, 20)
    np.testing.assert_allclose(follower_heights(profile, 0.0, u), a + b * u, atol=1e-12)
    u = np.linspace(46.0, 79.0, 20)
    np.testing.assert_allclose(follower_heights(profile, 0.0, u),
                               np.sqrt(rho**2 - (u - c) ** 2), atol=1e-12)


def brute_force_heights(polygon: shapely.Polygon, r: float, u: np.ndarray,
                        top: float) -> np.ndarray:
    """The highest centre on x = u whose circle touches *polygon*: bisection on the distance."""
    lo, hi = np.zeros_like(u), np.full_like(u, top)
    for _ in range(48):
        mid = 0.5 * (lo + hi)
        clear = shapely.distance(polygon, shapely.points(np.stack((u, mid), -1))) >= r
        hi, lo = np.where(clear, mid, hi), np.where(clear, lo, mid)
    return 0.5 * (lo + hi)


def test_the_simulation_on_an_undercut_plate_against_brute_force() -> None:
    text = harmonic_design(20.0, 30.0, roller="{type: roller, roller_radius: 14}")
    analysis = analyse(design_from_text(text))
    geom = analysis.linear
    assert geom is not None and geom.undercut
    polygon = shapely.Polygon(geom.outline.points(1e-5))
    u = np.linspace(0.0, 299.0, 300)
    simulated = follower_heights(geom.outline, 14.0, u)
    reference = brute_force_heights(polygon, 14.0, u, 200.0)
    assert np.max(np.abs(simulated - reference)) < 2e-5
    # it rides below the design where the crests were cut away, never above it
    design = 40.0 + analysis.program.evaluate(2 * np.pi * u / 300.0)[0]
    assert np.max(simulated - design) < 0.001 and np.max(design - simulated) > 0.01


def test_undercut_design_fails_with_exit_1(tmp_path: Path) -> None:
    (tmp_path / "u.yaml").write_text(harmonic_design(20.0, 30.0,
                                                     roller="{type: roller, roller_radius: 14}"))
    result = run_cli("build", "u.yaml", "-o", "out", cwd=tmp_path)
    assert result.exit_code == 1
    report = json.loads((tmp_path / "out" / "h-report.json").read_text())
    check = next(c for c in report["checks"] if c["id"] == "undercut")
    assert not check["ok"] and check["ranges_deg"]
    assert "travel" in check["message"] and "off the design" in check["message"]
    assert report["geometry"]["undercut"] is True
    # the smallest convex pitch radius at the top of the rise: 2L²/(hπ²)
    assert report["geometry"]["pitch_min_radius_of_curvature_mm"] == pytest.approx(
        2 * 30.0**2 / (20.0 * math.pi**2), rel=1e-6)


def test_the_stl_read_back_has_the_plates_volume(tmp_path: Path,
                                                 roller_files: dict[str, bytes]) -> None:
    path = tmp_path / "plate.stl"
    path.write_bytes(roller_files["demo-linear-roller.stl"])
    mesh = trimesh.load(path, force="mesh")
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.volume > 0
    # the plate's area: the working curve from x = −R to stroke + R, by the trapezoid rule
    t = np.linspace(-2 * R, STROKE + 2 * R, 400_001)
    w = exact_working(t)
    inside = (w[:, 0] >= -R) & (w[:, 0] <= STROKE + R)
    xs = np.concatenate(([-R], w[inside, 0], [STROKE + R]))
    ys = np.interp(xs, w[:, 0], w[:, 1])
    area = float(np.sum(0.5 * (ys[1:] + ys[:-1]) * np.diff(xs)))
    perimeter = 2 * (STROKE + 2 * R) + 2 * 30.0 + 2 * LIFT
    assert mesh.volume == pytest.approx(area * THICKNESS, abs=0.001 * perimeter * THICKNESS)
    assert np.ptp(mesh.vertices[:, 2]) == pytest.approx(THICKNESS)


def test_a_laser_cut_knife_plate_is_kerf_half_outside_and_verified() -> None:
    analysis = render(analyse(load_design(KNIFE))).analysis
    assert analysis is not None and analysis.exit_code == 0
    check = analysis.verification
    assert check is not None and "kerf" in check.source
    assert check.lift.max_mm < 0.002 and check.deviation_mm is not None
    assert check.deviation_mm < 0.002


def test_an_inch_design_is_drawn_in_inches() -> None:
    text = harmonic_design(1.0, 4.0, 12.0, "{type: roller, roller_radius: 0.25}")
    text = text.replace("name: h\n", "name: h\nunits: in\n").replace("base_height: 40",
                                                                      "base_height: 1.5")
    artifacts = render(analyse(design_from_text(text)))
    assert artifacts.analysis is not None and artifacts.analysis.exit_code == 0
    doc = ezdxf.read(io.StringIO(artifacts.files["h.dxf"].decode()))
    assert doc.header["$INSUNITS"] == 1
    cut = loops(doc, "CUT")[0]
    assert cut.max(axis=0) == pytest.approx([12.25, 1.5 - 0.25 + 1.0], abs=1e-3)


# -- refused designs ----------------------------------------------------------------------------

GOOD = """\
name: bad
cam:
  type: linear
  stroke: 200
  base_height: 30
follower:
  type: roller
  roller_radius: 8
motion:
  - rise:   {travel: 80, lift: 20, law: cycloidal}
  - dwell:  {travel: 20}
  - return: {travel: 80, law: cycloidal}
  - dwell:  {travel: 20}
"""


@pytest.mark.parametrize(("old", "new", "where", "words"), [
    ("{travel: 20}\n", "{travel: 30}\n", "bad.yaml:9: motion:", "sum to the stroke 200"),
    ("{travel: 80, lift: 20,", "{angle: 80, lift: 20,", "bad.yaml:10: motion[0].angle:",
     "travel"),
    ("type: roller\n  roller_radius: 8", "type: flat", "bad.yaml:7: follower.type:",
     "roller or knife"),
    ("base_height: 30", "base_height: 8.5", "bad.yaml:5: cam.base_height:", "at least 1 mm"),
], ids=["travels-not-stroke", "angle-not-travel", "flat-follower", "base-height-too-small"])
def test_bad_linear_designs_exit_2_with_one_located_line(tmp_path: Path, old: str, new: str,
                                                         where: str, words: str) -> None:
    assert old in GOOD
    (tmp_path / "bad.yaml").write_text(GOOD.replace(old, new, 1))
    result = run_cli("build", "bad.yaml", cwd=tmp_path)
    assert result.exit_code == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(where), result.stderr
    assert words in lines[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.yaml"]


# -- the build ----------------------------------------------------------------------------------

def test_build_writes_every_file_with_the_linear_keys(tmp_path: Path) -> None:
    result = run_cli("build", str(ROLLER), "-o", "tmp", cwd=tmp_path)
    assert result.exit_code == 0, result.output
    name = "demo-linear-roller"
    folder = tmp_path / "tmp"
    assert sorted(p.name for p in folder.iterdir()) == sorted(
        f"{name}{suffix}" for suffix in (".dxf", ".svg", ".stl", "-report.html",
                                         "-report.json", "-motion.csv"))
    report = json.loads((folder / f"{name}-report.json").read_text())
    assert report["cam_type"] == "linear"
    geometry = report["geometry"]
    for key in ("stroke_mm", "base_height_mm", "max_height_mm", "plate_length_mm",
                "pitch_min_radius_of_curvature_mm", "pitch_min_radius_of_curvature_at_deg",
                "pitch_min_radius_of_curvature_at_mm", "profile_min_radius_of_curvature_mm",
                "profile_min_concave_radius_mm", "pressure_angle_max_deg",
                "pressure_angle_max_at_deg", "pressure_angle_max_at_mm",
                "pressure_angle_limit_deg", "undercut", "undercut_ranges_deg", "profile_points",
                "sampling_tolerance_mm", "traverse_speed_mm_s"):
        assert key in geometry, key
    assert geometry["traverse_speed_mm_s"] == pytest.approx(STROKE * 30 / 60)
    assert geometry["plate_length_mm"] == pytest.approx(STROKE + 2 * R)
    # the cycloidal rise is steepest mid-way: tan φ = 2h/L
    assert geometry["pressure_angle_max_deg"] == pytest.approx(
        math.degrees(math.atan(2 * LIFT / 80.0)), abs=1e-9)
    assert geometry["pressure_angle_max_at_mm"] == pytest.approx(40.0, abs=0.1)
    assert report["verification"]["max_lift_error_mm"] < 0.001
    assert report["segments"][0]["max_pressure_angle_deg"] == pytest.approx(
        geometry["pressure_angle_max_deg"])
    rows = list(csv.DictReader(io.StringIO((folder / f"{name}-motion.csv").read_text())))
    header = list(rows[0])
    assert header[:3] == ["cam_angle_deg", "cam_travel_mm", "displacement_mm"]
    at = {round(float(r["cam_travel_mm"]), 6): r for r in rows}
    x = 40.0  # 60° of the cycle
    row = at[x]
    assert float(row["cam_angle_deg"]) == pytest.approx(60.0)
    _, sx, sxx = motion_of_demo(np.array([x]))
    assert float(row["pressure_angle_deg"]) == pytest.approx(math.degrees(math.atan(sx[0])),
                                                             abs=1e-7)
    pitch_rho = -((1 + sx[0] ** 2) ** 1.5) / sxx[0]
    assert float(row["pitch_radius_of_curvature_mm"]) == pytest.approx(pitch_rho, rel=1e-8)
    assert float(row["profile_radius_of_curvature_mm"]) == pytest.approx(pitch_rho - R, rel=1e-8)
    assert float(row["velocity_m_s"]) == pytest.approx(sx[0] * STROKE * 30 / 60 / 1000,
                                                       rel=1e-8)
    html = (folder / f"{name}-report.html").read_text()
    assert "travel 0" in html and "<svg" in html


# -- real consumers (Debian's openscad and admesh; skipped when missing) ------------------------

def test_openscad_extrudes_the_cut_layer_and_admesh_finds_nothing_to_repair(
        tmp_path: Path, built: Artifacts) -> None:
    from .test_consumers import ADMESH_CLEAN, openscad, tool

    for name, data in built.files.items():
        (tmp_path / name).write_bytes(data)
    name = "demo-linear-roller"
    mesh, messages = openscad(tmp_path, (
        f'linear_extrude(height={THICKNESS!r}) '
        f'import(file="{name}.dxf", layer="CUT", $fa=0.2, $fs=0.01);\n'))
    assert "WARNING" not in messages and "ERROR" not in messages, messages
    assert mesh.is_watertight
    assert built.analysis is not None and built.analysis.verification is not None
    stl = built.analysis.verification.stl
    assert stl is not None
    assert abs(mesh.volume - stl.volume_mm3) <= stl.volume_allowance_mm3
    run = subprocess.run([tool("admesh"), str(tmp_path / f"{name}.stl")], capture_output=True,
                         text=True, timeout=120, check=False)
    assert run.returncode == 0, run.stderr
    for label in ("Number of parts", *ADMESH_CLEAN):
        found = re.search(re.escape(label) + r"\s*:\s*(\d+)(?:[ \t]+(\d+))?", run.stdout)
        assert found is not None, run.stdout
        assert int(found.group(2) or found.group(1)) == (1 if label == "Number of parts" else 0)


KNIFE_STEP = """\
name: beam
cam: {type: linear, stroke: 200, base_height: 25, thickness: 6}
follower: {type: knife}
motion:
  - rise:   {travel: RISE, lift: 15, law: uniform-velocity}
  - dwell:  {travel: 30}
  - return: {travel: 70, law: modified-sine}
  - dwell:  {travel: REST}
manufacturing: {tolerance: 0.002, kerf: 0.4}
"""


@pytest.mark.parametrize("rise", [70, 20])
def test_a_beam_rounds_a_knifes_sharp_hollow_and_the_files_hold_the_plate_as_cut(
        rise: int) -> None:
    """The foot of a uniform-velocity rise is a sharp hollow of the plate's edge; a beam of
    radius r = kerf/2 rounds it with a fillet tangent to the dwell's line and the ramp, whose
    height above the corner (where the knife stands) is r − √(r² − t²), t = r / tan(β/2), β the
    hollow's included angle (180° less the ramp's slope angle). A gentle ramp leaves the knife
    within the tolerance (the check passes), a steep one does not (it fails, saying by how
    much); the CUT contour read back is held to the beam's exact path either way, and the
    verification to the plate as the beam cuts it."""
    text = KNIFE_STEP.replace("RISE", str(rise)).replace("REST", str(100 - rise))
    analysis = render(analyse(design_from_text(text))).analysis
    assert analysis is not None
    r, slope = 0.2, 15.0 / rise
    half = (math.pi - math.atan(slope)) / 2.0
    t = r / math.tan(half)
    sits = r - math.sqrt(r * r - t * t)
    kerf = next(f for f in analysis.findings if f.id == "kerf")
    verification = next(f for f in analysis.findings if f.id == "verification")
    assert verification.ok, verification.message
    assert analysis.verification is not None
    assert analysis.verification.deviation_mm is not None
    assert analysis.verification.deviation_mm < 0.002
    if sits < 0.002:
        assert kerf.ok, kerf.message
    else:
        assert not kerf.ok and "sharp hollow" in kerf.message
        off = float(re.search(r"moves the follower up to ([0-9.e-]+) mm", kerf.message)[1])
        assert off == pytest.approx(sits, abs=0.1 * 0.002)


def test_velocity_steps_give_a_knife_plate_with_sharp_hollows_a_cutter_cannot_reach() -> None:
    text = (GOOD.replace("type: roller\n  roller_radius: 8", "type: knife")
            .replace("law: cycloidal", "law: uniform-velocity")
            + "manufacturing: {cutter_radius: 3}\n")
    analysis = render(analyse(design_from_text(text))).analysis
    assert analysis is not None
    failed = {f.id for f in analysis.findings if f.failed_error}
    assert failed == {"continuity", "cutter"}
    cutter = next(f for f in analysis.findings if f.id == "cutter")
    # the feet of the ramps: travel 0 (dwell into the rise) and 180 mm (the return into a dwell)
    assert cutter.ranges_deg == ((0.0, 0.0), (324.0, 324.0))
    # a knife rides the plate's straight flanks and corners exactly
    assert analysis.verification is not None and analysis.verification.lift.max_mm < 1e-9
