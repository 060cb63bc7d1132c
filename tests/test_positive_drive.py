"""Conjugate and constant-breadth cams: the cams that hold their follower without a spring.

The references are independent of camfab's construction: the follower's positions written out
from the design (the trace points in the frame, turned onto the cam by Rot(−σθ)), the outlines
read back from the files, and a brute-force follower — a roller resting on or hanging under the
outline's points, or the outline's extent between two parallel faces — at every angle.
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest
import shapely

from camfab.curves.profile import Profile
from camfab.export.dxf import read_cut_outline
from camfab.motion.mirror import opposite
from camfab.motion.program import build_program
from camfab.pipeline import analyse, design_from_text, load_design, render

from .conftest import DESIGNS, run_cli

CONJUGATE = DESIGNS / "demo-conjugate.yaml"
BREADTH = DESIGNS / "demo-constant-breadth.yaml"
DIAMETER = DESIGNS / "demo-constant-diameter.yaml"


def conjugate_text(rotation: str = "ccw", offset: float = 0.0, spacing: float = 110.0) -> str:
    return f"""
name: pair
cam: {{type: conjugate, rotation: {rotation}, base_radius: 35, thickness: 10, bore: 16,
      keyway: {{width: 5, depth: 2.3}}}}
follower: {{type: roller, offset: {offset}, roller_radius: 8, roller_spacing: {spacing}}}
motion:
  - rise:   {{angle: 110, lift: 18, law: cycloidal}}
  - dwell:  {{angle: 70}}
  - return: {{angle: 110, law: polynomial-345}}
  - dwell:  {{angle: 70}}
"""


def turn(points: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """(N, 2) points turned counter-clockwise by each of (K,) angles: (K, N, 2)."""
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    x, y = points[:, 0], points[:, 1]
    return np.stack((c * x - s * y, s * x + c * y), axis=-1)


def roller_on(points: np.ndarray, x: float, radius: float, below: bool) -> np.ndarray:
    """For (K, N, 2) cam points in the frame: the height of a roller of *radius* on the line
    *x* resting on them from above (or, *below*, pressed up against them from underneath)."""
    dx = points[..., 0] - x
    near = np.abs(dx) <= radius
    rise = np.sqrt(np.clip(radius * radius - dx * dx, 0.0, None))
    if below:
        return np.min(np.where(near, points[..., 1] - rise, np.inf), axis=1)
    return np.max(np.where(near, points[..., 1] + rise, -np.inf), axis=1)


def built(text_or_path: str | Path, tmp_path: Path) -> tuple[dict[str, bytes], object]:
    design = load_design(text_or_path) if isinstance(text_or_path, Path) else \
        design_from_text(text_or_path)
    artifacts = render(analyse(design))
    return artifacts.files, artifacts.analysis


# -- the motions ------------------------------------------------------------------------------


def test_the_opposite_motion_is_the_lift_less_the_motion() -> None:
    design = load_design(CONJUGATE)
    program = design.program
    theta = np.linspace(0.0, 2 * math.pi, 3001)
    mine, theirs = program.evaluate(theta), opposite(program).evaluate(theta)
    assert np.allclose(theirs[0], program.max_lift - mine[0], atol=1e-12)
    assert np.allclose(theirs[1:], -mine[1:], atol=1e-9)


def test_a_half_turn_is_completed_into_the_motion_written_out_in_full() -> None:
    half = load_design(BREADTH)
    written = """
  - rise:   {angle: 150, lift: 20, law: cycloidal}
  - dwell:  {angle: 30}
  - return: {angle: 150, lift: 20, law: cycloidal}
  - dwell:  {angle: 30}
"""
    full = design_from_text(BREADTH.read_text().split("motion:")[0] + "motion:" + written)
    theta = np.linspace(0.0, 2 * math.pi, 3001)
    assert np.allclose(half.program.evaluate(theta), full.program.evaluate(theta), atol=1e-9)
    s = half.program.evaluate(theta[:1500])[0]
    assert np.allclose(s + half.program.evaluate(theta[:1500] + math.pi)[0], 20.0, atol=1e-12)


def test_a_half_turn_with_an_asymmetric_law_keeps_its_law_in_the_second_half() -> None:
    text = BREADTH.read_text().split("motion:")[0] + """motion:
  - rise:  {angle: 150, lift: 20, law: double-harmonic}
  - dwell: {angle: 30}
"""
    program = design_from_text(text).program
    theta = np.linspace(0.0, math.pi, 1001)
    assert np.allclose(program.evaluate(theta)[0] + program.evaluate(theta + math.pi)[0], 20.0,
                       atol=1e-12)
    # the double-harmonic rise written out on its own, as a reference
    disc = BREADTH.read_text().split("motion:")[0].replace("constant-breadth", "disc")
    rise = build_program(design_from_text(disc + """motion:
  - rise:   {angle: 150, lift: 20, law: double-harmonic}
  - dwell:  {angle: 30}
  - return: {angle: 150, lift: 20, law: cycloidal}
  - dwell:  {angle: 30}
""").motion or ())
    assert np.allclose(program.evaluate(theta)[0], rise.evaluate(theta)[0], atol=1e-12)


# -- conjugate pairs --------------------------------------------------------------------------


@pytest.mark.parametrize(("rotation", "offset"), [("ccw", 0.0), ("cw", 6.0), ("ccw", -4.0)])
def test_each_plate_lies_one_roller_radius_from_its_rollers_path(
        tmp_path: Path, rotation: str, offset: float) -> None:
    """Roller a's centre at (e, y₀ + s) and roller b's at (e, y₀ + s − L) in the frame, turned
    onto the cam: each is exactly one roller radius from its plate as written."""
    files, analysis = built(conjugate_text(rotation, offset), tmp_path)
    design = analysis.design  # type: ignore[attr-defined]
    sigma = design.cam.sigma
    y0 = math.sqrt((35 + 8) ** 2 - offset**2)
    theta = np.linspace(0.0, 2 * math.pi, 721)[:-1]
    s = design.program.evaluate(theta)[0]
    for plate, height in (("a", y0 + s), ("b", y0 + s - 110.0)):
        outline = read_cut_outline(files[f"pair-{plate}.dxf"], 1.0)
        centre = np.stack((np.full_like(s, offset), height), axis=-1)
        on_cam = np.einsum("kij,kj->ki", np.stack((
            np.stack((np.cos(-sigma * theta), -np.sin(-sigma * theta)), axis=-1),
            np.stack((np.sin(-sigma * theta), np.cos(-sigma * theta)), axis=-1)), axis=1),
            centre)
        distance = outline.distance(on_cam)
        assert np.abs(distance - 8.0).max() < 1e-3, plate
    # cam b's base radius: its roller's lowest trace point L − y₀ − h from the centre, less Rr
    report = json.loads(files["pair-report.json"])
    assert report["geometry"]["cam_b_base_radius_mm"] == pytest.approx(
        math.hypot(110 - y0 - 18, offset) - 8, abs=1e-9)


def test_a_bell_crank_pair_puts_each_plate_one_roller_radius_from_its_arm(
        tmp_path: Path) -> None:
    """The bell-crank's arms at Ψa = Ψ₀ + s above the line of centres and Ψb = γ − Ψa below it
    (pivot (a, 0), arms l): each roller centre, turned onto the cam, is one roller radius from
    its plate as written; the report's hold passes."""
    path = DESIGNS / "demo-conjugate-oscillating.yaml"
    files, analysis = built(path, tmp_path)
    design = analysis.design  # type: ignore[attr-defined]
    a, arm, radius = 90.0, 80.0, 8.0
    psi0 = math.acos((a * a + arm * arm - (30 + radius) ** 2) / (2 * a * arm))
    theta = np.linspace(0.0, 2 * math.pi, 721)[:-1]
    psi_a = psi0 + design.program.evaluate(theta)[0]
    psi_b = math.radians(67.0) - psi_a
    sigma = design.cam.sigma
    for plate, psi, side in (("a", psi_a, 1.0), ("b", psi_b, -1.0)):
        centre = np.stack((a - arm * np.cos(psi), side * arm * np.sin(psi)), axis=-1)
        c, s = np.cos(-sigma * theta), np.sin(-sigma * theta)
        on_cam = np.stack((c * centre[:, 0] - s * centre[:, 1],
                           s * centre[:, 0] + c * centre[:, 1]), axis=-1)
        outline = read_cut_outline(files[f"demo-conjugate-oscillating-{plate}.dxf"], 1.0)
        assert np.abs(outline.distance(on_cam) - radius).max() < 1e-3, plate
    report = json.loads(files["demo-conjugate-oscillating-report.json"])
    assert report["geometry"]["arm_angle_deg"] == pytest.approx(67.0)
    assert next(c for c in report["checks"] if c["id"] == "hold")["ok"]
    assert report["status"]["exit_code"] == 0


def test_the_pair_holds_the_follower_without_gap_or_interference(tmp_path: Path) -> None:
    """Brute force over the outlines as written: roller a resting on cam a and roller b pressed
    up under cam b are the roller spacing apart at every angle, within the two cams'
    tolerances."""
    files, analysis = built(CONJUGATE, tmp_path)
    design = analysis.design  # type: ignore[attr-defined]
    tolerance = design.manufacturing.tolerance
    theta = np.radians(np.arange(0.0, 360.0, 0.5))
    a = read_cut_outline(files["demo-conjugate-a.dxf"], 1.0).points(tolerance / 50)
    b = read_cut_outline(files["demo-conjugate-b.dxf"], 1.0).points(tolerance / 50)
    # a point of the cam at angle θ is where the cam has turned it: Rot(σθ)
    ya = roller_on(turn(a, design.cam.sigma * theta), 0.0, 8.0, below=False)
    yb = roller_on(turn(b, design.cam.sigma * theta), 0.0, 8.0, below=True)
    gap = (yb + 110.0) - ya
    assert np.abs(gap).max() < 2 * tolerance
    # and the follower follows the design
    assert np.abs(ya - 43.0 - design.program.evaluate(theta)[0]).max() < tolerance
    report = json.loads(files["demo-conjugate-report.json"])
    hold = next(c for c in report["checks"] if c["id"] == "hold")
    assert hold["ok"] and "read back" in hold["message"]
    assert {c["id"] for c in report["checks"]} >= {"pressure_angle", "pressure_angle_b",
                                                    "undercut", "undercut_b", "verification"}


def test_a_pair_whose_cam_b_is_undercut_does_not_hold(tmp_path: Path) -> None:
    """A small cam b (rollers close together) with a steep return folds cam b's envelope: the
    cam that is cut lets the follower go."""
    text = conjugate_text(spacing=78.0).replace("bore: 16", "bore: 8").replace(
        "keyway: {width: 5, depth: 2.3}", "keyway: {width: 3, depth: 1}").replace(
        "{angle: 110, law: polynomial-345}", "{angle: 40, law: polynomial-345}").replace(
        "- dwell:  {angle: 70}\n", "- dwell:  {angle: 140}\n", 1).replace(
        "- dwell:  {angle: 70}\n", "- dwell:  {angle: 70}\n")
    analysis = analyse(design_from_text(text))
    checks = {f.id: f for f in analysis.findings}
    assert not checks["undercut_b"].ok
    assert not checks["hold"].ok
    assert analysis.exit_code == 1


def test_a_conjugate_build_writes_a_file_per_plate_and_one_stacked_solid(tmp_path: Path) -> None:
    import trimesh

    result = run_cli("build", str(CONJUGATE), "-o", str(tmp_path / "out"))
    assert result.exit_code == 0, result.stderr
    out = tmp_path / "out"
    names = {p.name for p in out.iterdir()}
    assert names == {"demo-conjugate-a.dxf", "demo-conjugate-b.dxf", "demo-conjugate-a.svg",
                     "demo-conjugate-b.svg", "demo-conjugate.stl", "demo-conjugate-report.html",
                     "demo-conjugate-report.json", "demo-conjugate-motion.csv"}
    mesh = trimesh.load(out / "demo-conjugate.stl")
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert mesh.bounds[0][2] == pytest.approx(0.0) and mesh.bounds[1][2] == pytest.approx(20.0)
    # volume: both plates' areas (shapely, from the DXF outlines) less the bore, × thickness
    area = 0.0
    for plate in "ab":
        outline = read_cut_outline((out / f"demo-conjugate-{plate}.dxf").read_bytes(), 1.0)
        area += shapely.Polygon(outline.points(1e-4)).area
    bore = math.pi * 8.0**2 + 5.0 * 2.3  # the keyway, nearly: its foot is on the circle
    assert mesh.volume == pytest.approx((area - 2 * bore) * 10.0, rel=2e-3)
    # cam b's columns in the motion table, and where the load passes from one cam to the other:
    # where s″ changes sign, mid-rise and mid-return for the cycloidal and 3-4-5 laws
    report = json.loads((out / "demo-conjugate-report.json").read_text())
    with (out / "demo-conjugate-motion.csv").open() as stream:
        rows = list(csv.DictReader(stream))
    worst_b = max(abs(float(r["pressure_angle_b_deg"])) for r in rows)
    assert worst_b == pytest.approx(report["geometry"]["cam_b_pressure_angle_max_deg"], abs=0.05)
    changes = report["geometry"]["load_changes"]
    assert [c["cam_angle_deg"] for c in changes] == pytest.approx([55.0, 235.0], abs=1e-6)
    assert [c["onto"] for c in changes] == ["cam b", "cam a"]
    # the keyways line up: the phase relation of the two plates is that of the drawings
    for plate in "ab":
        hole = _bore(out / f"demo-conjugate-{plate}.dxf")
        assert hole[:, 1].max() == pytest.approx(8.0 + 2.3, abs=1e-9)
        top = hole[hole[:, 1] > 10.0]
        assert np.allclose(np.sort(top[:, 0])[[0, -1]], [-2.5, 2.5], atol=1e-9)


def _bore(path: Path) -> np.ndarray:
    """The vertices of the bore's contour on CUT (the smaller of the two)."""
    import ezdxf
    from ezdxf import edgeminer, edgesmith

    doc = ezdxf.readfile(path)
    entities = doc.modelspace().query('LINE ARC[layer=="CUT"]')
    loops = edgeminer.find_all_loops(edgeminer.Deposit(
        list(edgesmith.edges_from_entities_2d(entities, gap_tol=1e-6)), gap_tol=1e-6))
    profiles = [Profile.from_points(np.array(list(
        edgesmith.lwpolyline_from_chain(loop).get_points("xyb")))[:, :2]) for loop in loops]
    return min(profiles, key=lambda p: p.area).vertices


# -- constant breadth and constant diameter ---------------------------------------------------


def test_a_yoke_stays_its_breadth_around_the_cam(tmp_path: Path) -> None:
    """The outline as written spans exactly 2·Rb + h between two parallel faces at every angle,
    and its top follows the design."""
    files, analysis = built(BREADTH, tmp_path)
    design = analysis.design  # type: ignore[attr-defined]
    tolerance = design.manufacturing.tolerance
    outline = read_cut_outline(files["demo-constant-breadth.dxf"], 1.0).points(tolerance / 50)
    theta = np.radians(np.arange(0.0, 360.0, 0.5))
    y = turn(outline, theta)[..., 1]
    top, bottom = y.max(axis=1), y.min(axis=1)
    assert np.abs((top - bottom) - (2 * 40 + 20)).max() < 2 * tolerance
    assert np.abs(top - 40 - design.program.evaluate(theta)[0]).max() < tolerance
    report = json.loads(files["demo-constant-breadth-report.json"])
    assert report["geometry"]["breadth_mm"] == pytest.approx(100.0)
    assert next(c for c in report["checks"] if c["id"] == "hold")["ok"]
    assert report["status"]["exit_code"] == 0


def test_two_rollers_stay_their_distance_around_a_constant_diameter_cam(tmp_path: Path) -> None:
    files, analysis = built(DIAMETER, tmp_path)
    design = analysis.design  # type: ignore[attr-defined]
    tolerance = design.manufacturing.tolerance
    outline = read_cut_outline(files["demo-constant-diameter.dxf"], 1.0).points(tolerance / 50)
    theta = np.radians(np.arange(0.0, 360.0, 0.5))
    points = turn(outline, design.cam.sigma * theta)
    upper = roller_on(points, 0.0, 6.0, below=False)
    lower = roller_on(points, 0.0, 6.0, below=True)
    assert np.abs((upper - lower) - (2 * 36 + 14)).max() < 2 * tolerance
    report = json.loads(files["demo-constant-diameter-report.json"])
    assert report["geometry"]["breadth_mm"] == pytest.approx(86.0)


# -- refusals ---------------------------------------------------------------------------------


REFUSALS = [
    ("conjugate-no-spacing", conjugate_text().replace(", roller_spacing: 110.0", ""),
     "follower.roller_spacing: required"),
    ("conjugate-close-rollers", conjugate_text(spacing=60.0),
     "follower.roller_spacing: leaves cam b no base circle"),
    ("conjugate-flat", conjugate_text().replace("type: roller", "type: flat").replace(
        " roller_radius: 8,", ""),
     "follower.type: a conjugate cam takes a roller follower"),
    ("conjugate-oscillating", conjugate_text().replace(
        "type: roller, offset: 0.0,",
        "type: roller, motion: oscillating, pivot_distance: 90, arm_length: 60,").replace(
        ", roller_spacing: 110.0", ""),
     "follower.arm_angle: required for an oscillating conjugate cam"),
    ("bell-crank-closed", (DESIGNS / "demo-conjugate-oscillating.yaml").read_text().replace(
        "arm_angle: 67", "arm_angle: 38"), "follower.arm_angle: leaves cam b no base circle"),
    # cam b is checked once arm a's own rules hold: an arm too short for the prime circle is
    # reported as such, not as the arithmetic error cam b's geometry would raise
    ("bell-crank-short-arm", (DESIGNS / "demo-conjugate-oscillating.yaml").read_text().replace(
        "arm_length: 80", "arm_length: 5"),
     "follower.arm_length: the arm cannot reach the prime circle"),
    ("breadth-broken", BREADTH.read_text().replace(
        "  - dwell: {angle: 30}\n",
        "  - dwell: {angle: 30}\n  - return: {angle: 150, lift: 20, law: harmonic}\n"
        "  - dwell: {angle: 30}\n"), "motion[2]: a constant-breadth cam's two faces"),
    ("breadth-spring", BREADTH.read_text() + "spring: {rate: 5, preload: 20}\n",
     "spring: a constant-breadth cam drives its follower both ways"),
    ("conjugate-spring", conjugate_text() + "spring: {rate: 5, preload: 20}\n",
     "spring: a conjugate cam drives its follower both ways"),
    ("diameter-offset", DIAMETER.read_text().replace("roller_radius: 6",
                                                      "roller_radius: 6\n  offset: 3"),
     "follower.offset: the two rollers"),
]


@pytest.mark.parametrize(("text", "expected"), [r[1:] for r in REFUSALS],
                         ids=[r[0] for r in REFUSALS])
def test_bad_positive_drive_designs_are_refused_on_their_line(tmp_path: Path, text: str,
                                                              expected: str) -> None:
    (tmp_path / "d.yaml").write_text(text)
    result = run_cli("build", "d.yaml", "-o", "out", cwd=tmp_path)
    assert result.exit_code == 2
    line = result.stderr.strip()
    assert "\n" not in line and line.startswith("d.yaml:")
    assert expected in line, line
    assert not (tmp_path / "out").exists()
