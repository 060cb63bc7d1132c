"""Circular-arc and tangent cams: the seeds' published answers, THEORY §D's closed forms, the
follower simulated on the exact outline, the files, and the clear refusals of impossible shapes.

Textbooks round ω and intermediate lengths and angles, so their answers are compared within
0.3 %; the closed forms, computed here from their own formulas, agree to rounding error.
"""

from __future__ import annotations

import io
import json
import math
from pathlib import Path

import numpy as np
import pytest

from camfab.curves.follower import FollowerGeometry
from camfab.curves.shaped import ShapedCam
from camfab.geometry.simulate import simulate
from camfab.pipeline import Analysis, analyse, design_from_text, load_design, render

from .conftest import DESIGNS, rad, run_cli

TEXTBOOK = 3e-3


def agrees(value: float, published: float) -> bool:
    """Within 0.3 %, or within the rounding of the published figure (half a unit of its last
    digit: 10.7 mm stands for 10.65…10.75 mm)."""
    text = repr(published)
    decimals = len(text.split(".")[1]) if "." in text else 0
    return abs(value - published) <= max(TEXTBOOK * abs(published), 0.5 * 10.0**-decimals)

#: design -> (published dimensions, published accelerations (m/s²) at the start of lift, the
#: end of the flank, the start of the nose and the apex)
SEEDS = {
    "seed-20-15-circular-arc": (
        {"flank_radius": 82.4, "nose_centre_distance": 45.0, "flank_end_deg": 34.2},
        (206.93, 171.13, -134.52, -177.7)),
    "seed-7-11-circular-arc": (
        {"flank_radius": 100.3, "flank_centre_distance": 60.3, "pq": 92.3,
         "nose_centre_distance": 56.0, "flank_end_deg": 35.9},
        (116.74, 94.565, -84.136, -108.416)),
    "seed-7-10-circular-arc": (
        {"nose_radius": 10.7, "flank_radius": 52.6, "nose_centre_distance": 21.3,
         "flank_end_deg": 30.0},
        (89.37, 77.41, -37.54, -58.4)),
    "seed-7-12-exhaust-valve": (
        {"flank_radius": 92.2, "flank_centre_distance": 67.2, "nose_centre_distance": 34.0,
         "flank_end_deg": 19.27},
        (1658.09, None, None, -838.92)),
}


def _analysis(name: str) -> Analysis:
    return analyse(load_design(DESIGNS / f"{name}.yaml"))


@pytest.mark.parametrize("name", sorted(SEEDS))
def test_seed_dimensions_and_accelerations(name: str) -> None:
    dims, accelerations = SEEDS[name]
    analysis = _analysis(name)
    shape = analysis.shape
    assert shape is not None and analysis.exit_code == 0
    got = {"flank_radius": shape.flank_radius, "nose_radius": shape.nose_radius,
           "nose_centre_distance": shape.nose_centre_distance,
           "flank_centre_distance": shape.flank_centre_distance,
           "pq": (shape.flank_radius or 0.0) - shape.nose_radius,
           "flank_end_deg": math.degrees(shape.flank_end_angle)}
    for key, published in dims.items():
        assert agrees(got[key], published), (key, got[key], published)
    omega = analysis.design.cam.omega
    assert omega is not None
    names = [p.name for p in shape.points]
    assert names == ["start of lift", "end of flank", "start of nose", "apex"]
    for point, published in zip(shape.points, accelerations, strict=True):
        if published is not None:
            si = point.motion[2] * omega**2 / 1000.0
            assert agrees(si, published), (point.name, si, published)


def test_exhaust_valve_velocity_and_spring_force() -> None:
    analysis = _analysis("seed-7-12-exhaust-valve")
    fastest = max(s.max_si[0] for s in analysis.segments if s.max_si and s.max_si[0])
    assert fastest == pytest.approx(3.48, rel=TEXTBOOK)
    dyn = analysis.dynamics
    assert dyn is not None and dyn.required_spring_force_N is not None
    assert dyn.required_spring_force_N == pytest.approx(251.7, rel=TEXTBOOK)
    assert dyn.required_spring_force_at_deg == pytest.approx(60.0, abs=0.05)  # the apex
    report = json.loads(render(analysis).files["seed-7-12-exhaust-valve-report.json"])
    assert report["dynamics"]["required_spring_force_N"] == pytest.approx(251.7, rel=TEXTBOOK)


def test_circular_arc_motion_is_theory_closed_form() -> None:
    """x = OP(1 − cos θ) on the flank, x = OQ cos(α − θ) + rn − r1 on the nose, and their
    derivatives, over the rise; the return mirrors it."""
    design = load_design(DESIGNS / "seed-20-15-circular-arc.yaml")
    r1, h, rn, alpha = 30.0, 20.0, 5.0, rad(75)
    oq, c = r1 + h - rn, r1 - rn
    op = (oq**2 - c**2) / (2 * (c - oq * math.cos(alpha)))
    phi = math.asin(oq * math.sin(alpha) / (r1 + op - rn))
    theta = np.linspace(0.0, alpha, 2001)
    flank = theta < phi
    t1 = alpha - theta
    x = np.where(flank, op * (1 - np.cos(theta)), oq * np.cos(t1) + rn - r1)
    v = np.where(flank, op * np.sin(theta), oq * np.sin(t1))
    a = np.where(flank, op * np.cos(theta), -oq * np.cos(t1))
    m = design.program.evaluate(theta)
    np.testing.assert_allclose(m[0], x, atol=1e-10)
    np.testing.assert_allclose(m[1], v, atol=1e-10)
    np.testing.assert_allclose(m[2], a, atol=1e-10)
    back = design.program.evaluate(2 * alpha - theta)
    np.testing.assert_allclose(back[0], x, atol=1e-10)
    np.testing.assert_allclose(back[1], -v, atol=1e-10)


def _tangent_text(extra: str = "", follower: str = "{type: roller, roller_radius: 10}") -> str:
    return (f"name: t\ncam:\n  type: tangent\n  speed_rpm: 500\n  base_radius: 30\n"
            f"  lift: 12\n  lift_angle: 60\n  thickness: 8\n{extra}follower: {follower}\n")


def test_tangent_roller_is_theory_closed_form() -> None:
    """Flank: x = (r1 + Rr)(1 − cos θ)/cos θ, a = (r1 + Rr)(2 − cos²θ)/cos³θ per rad²; nose
    (exact): x = OQ cos θ₁ + √(L² − OQ² sin²θ₁) − (r1 + Rr), its acceleration by central
    differences; flank contact ends at tan φ = OQ sin α/(r1 + Rr)."""
    design = design_from_text(_tangent_text())
    r1, h, rr, alpha = 30.0, 12.0, 10.0, rad(60)
    rn = (r1 - (r1 + h) * math.cos(alpha)) / (1 - math.cos(alpha))
    assert rn == pytest.approx(18.0, rel=1e-12)
    oq, big = r1 + h - rn, rr + rn
    phi = math.atan(oq * math.sin(alpha) / (r1 + rr))
    program = design.program
    assert program.segments[1].start == pytest.approx(phi, abs=1e-12)
    theta = np.linspace(0.0, phi, 500, endpoint=False)
    m = program.evaluate(theta)
    np.testing.assert_allclose(m[0], (r1 + rr) * (1 - np.cos(theta)) / np.cos(theta),
                               atol=1e-10)
    np.testing.assert_allclose(m[2], (r1 + rr) * (2 - np.cos(theta) ** 2) / np.cos(theta) ** 3,
                               rtol=1e-10)

    def nose(t: np.ndarray) -> np.ndarray:
        t1 = alpha - t
        return oq * np.cos(t1) + np.sqrt(big**2 - (oq * np.sin(t1)) ** 2) - (r1 + rr)

    theta = np.linspace(phi + 1e-3, alpha - 1e-3, 300)
    step = 1e-4
    m = program.evaluate(theta)
    np.testing.assert_allclose(m[0], nose(theta), atol=1e-10)
    second = (nose(theta + step) - 2 * nose(theta) + nose(theta - step)) / step**2
    np.testing.assert_allclose(m[2], second, rtol=1e-5, atol=1e-5)
    # at the apex (θ₁ = 0) the nose acceleration is −OQ(1 + OQ/L) per rad²
    apex = program.evaluate(np.array([alpha - 1e-12]))[2, 0]
    assert apex == pytest.approx(-oq * (1 + oq / big), rel=1e-9)


@pytest.mark.parametrize("kind", ["circular-arc", "tangent"])
@pytest.mark.parametrize("follower", ["flat", "knife", "roller", "mushroom"])
@pytest.mark.parametrize("rotation", ["ccw", "cw"])
def test_motion_equals_the_follower_simulated_on_the_exact_outline(
        kind: str, follower: str, rotation: str) -> None:
    """The closed-form motion and an independent run of the follower over the outline of true
    arcs and lines (the contact found by the largest of every piece's candidates) agree."""
    size = {"roller": "roller_radius: 7", "mushroom": "face_radius: 40"}.get(follower, "")
    shape = ("nose_radius: 5\n  lift_angle: 75" if kind == "circular-arc" else "lift_angle: 60")
    design = design_from_text(
        f"name: s\ncam:\n  type: {kind}\n  rotation: {rotation}\n  base_radius: 30\n  lift: 15\n"
        f"  {shape}\n  top_dwell: 25\nfollower: {{type: {follower}, {size}}}\n")
    fol = FollowerGeometry.from_design(design)
    profile = design.shape.profile(design.cam.sigma)
    theta = np.linspace(0.0, 2 * math.pi, 7200, endpoint=False)
    lift = simulate(profile, fol, theta, design.cam.sigma) - fol.rest_position(30.0)
    np.testing.assert_allclose(lift, design.program.evaluate(theta)[0], atol=1e-9)
    kinds = [(s.kind, s.law_name) for s in design.program.segments]
    assert ("dwell", "dwell") in kinds and kinds[-1] == ("dwell", "dwell")
    top = next(s for s in design.program.segments if s.kind == "dwell" and s.s0 > 0)
    assert top.s0 == pytest.approx(15.0, abs=1e-12) and math.degrees(top.span) == pytest.approx(25)


@pytest.mark.parametrize("sigma", [1, -1])
def test_outline_is_convex_tangent_continuous_and_dimensioned(sigma: int) -> None:
    import shapely

    cam = ShapedCam.circular_arc(30.0, 20.0, rad(75), nose_radius=5.0, top_dwell=rad(10))
    profile = cam.profile(sigma)
    points = profile.points(1e-4)
    radius = np.hypot(points[:, 0], points[:, 1])
    assert radius.min() == pytest.approx(30.0, abs=1e-9)
    assert radius.max() == pytest.approx(50.0, abs=1e-9)
    polygon = shapely.Polygon(points)
    assert polygon.convex_hull.area == pytest.approx(polygon.area, rel=1e-9)
    profile.offset(1.0)  # raises at a corner: the pieces meet tangentially
    arcs = profile.arcs()
    assert sorted({round(float(r), 6) for r in arcs.radius}) == [
        5.0, 30.0, 50.0, round(cam.flank_radius or 0.0, 6)]
    # the nose apex of the rise lies under the follower at the end of the rise
    apex = (45.0 + 5.0) * np.array([sigma * math.sin(rad(75)), math.cos(rad(75))])
    assert profile.distance(apex[None])[0] < 1e-12


def test_dxf_cut_is_true_arcs_and_lines(tmp_path: Path) -> None:
    import ezdxf

    files = render(analyse(design_from_text(_tangent_text(extra="  bore: 10\n")))).files
    doc = ezdxf.read(io.StringIO(files["t.dxf"].decode()))
    cut = [e for e in doc.modelspace() if e.dxf.layer == "CUT"]
    kinds = sorted(e.dxftype() for e in cut)
    assert kinds == ["ARC", "ARC", "ARC", "ARC", "CIRCLE", "LINE", "LINE"]  # base in two halves
    radii = sorted(round(e.dxf.radius, 9) for e in cut if e.dxftype() == "ARC")
    assert radii == [18.0, 18.0, 30.0, 30.0]


@pytest.mark.parametrize(("extra", "follower", "message"), [
    ("  nose_radius: 5\n", None, "cam.nose_radius: give either lift_angle or nose_radius"),
    ("", "{type: roller, roller_radius: 10, offset: 3}", "follower.offset: a tangent cam's "
     "follower moves along a line through the cam centre"),
    ("", "{type: roller, roller_radius: 10, motion: oscillating, pivot_distance: 80, "
     "arm_length: 60}", "follower.motion: a tangent cam drives a translating follower"),
    ("  flank_angle: 20\n", None, "cam.flank_angle: unknown key in a tangent cam"),
])
def test_tangent_refusals(tmp_path: Path, extra: str, follower: str | None,
                          message: str) -> None:
    text = _tangent_text(extra) if follower is None else _tangent_text(extra, follower)
    (tmp_path / "t.yaml").write_text(text)
    result = run_cli("build", "t.yaml", cwd=tmp_path)
    assert result.exit_code == 2
    assert message in result.stderr
    assert not (tmp_path / "exports").exists()


@pytest.mark.parametrize(("cam", "field", "message"), [
    ("type: tangent\n  base_radius: 30\n  lift: 12\n  lift_angle: 20", "cam.lift_angle",
     "must lie between 44.4153°"),
    ("type: tangent\n  base_radius: 30\n  lift: 12\n  nose_radius: 35", "cam.nose_radius",
     "must be smaller than the base radius"),
    ("type: circular-arc\n  base_radius: 30\n  lift: 20\n  lift_angle: 30\n  nose_radius: 5",
     "cam.nose_radius", "leaves no convex circular-arc flank"),
    ("type: circular-arc\n  base_radius: 30\n  lift: 20\n  lift_angle: 75", "cam.nose_radius",
     "required for a circular-arc cam (or flank_angle)"),
    ("type: circular-arc\n  base_radius: 30\n  lift: 20\n  lift_angle: 75\n  flank_angle: 80",
     "cam.flank_angle", "must lie between 0 and the lift angle"),
    ("type: circular-arc\n  base_radius: 30\n  lift: 20\n  lift_angle: 150\n  nose_radius: 5\n"
     "  top_dwell: 70", "cam.top_dwell", "leaves no base circle"),
])
def test_impossible_shapes_are_refused_on_their_line(tmp_path: Path, cam: str, field: str,
                                                     message: str) -> None:
    (tmp_path / "d.yaml").write_text(f"name: d\ncam:\n  {cam}\nfollower: {{type: flat}}\n")
    result = run_cli("check", "d.yaml", cwd=tmp_path)
    assert result.exit_code == 2
    line = result.stderr.strip()
    assert "\n" not in line and f": {field}: " in line and message in line, line


def test_a_shaped_cam_takes_no_motion_list(tmp_path: Path) -> None:
    (tmp_path / "d.yaml").write_text(_tangent_text() + "motion:\n  - dwell: {angle: 360}\n")
    result = run_cli("check", "d.yaml", cwd=tmp_path)
    assert result.exit_code == 2
    assert "motion: a tangent cam's shape defines the motion" in result.stderr


def test_flat_face_on_a_tangent_cam_meets_the_nose_at_once() -> None:
    """A flat face lies on a straight flank at one instant only: it leaves the base circle
    straight onto the nose with a velocity step (infinite acceleration), which the continuity
    check reports as an error."""
    analysis = analyse(design_from_text(_tangent_text(follower="{type: flat}")))
    first = analysis.program.segments[0]
    assert (first.kind, first.law_name, first.start) == ("rise", "nose", 0.0)
    oq = 30 + 12 - 18.0
    assert first.end_values()[0][1] == pytest.approx(oq * math.sin(rad(60)), rel=1e-12)
    velocity = [f for f in analysis.findings if f.id == "continuity" and not f.ok
                and f.severity == "error"]
    assert velocity and "velocity steps at 0°" in velocity[0].message
    assert analysis.shape is not None and analysis.shape.flank_end_angle == 0.0
    assert [p.name for p in analysis.shape.points] == ["start of lift", "start of nose", "apex"]


def test_a_nose_almost_a_corner_keeps_the_velocity_continuous() -> None:
    """A roller rounding a nose of 1 nm: the joint angles come from the flanks' normals, not from
    the direction out of the tiny nose's centre, which rounding turns by 1e-7 rad."""
    analysis = analyse(design_from_text(
        "name: n\ncam:\n  type: circular-arc\n  base_radius: 30\n  lift: 20\n  lift_angle: 75\n"
        "  nose_radius: 1e-6\nfollower: {type: roller, roller_radius: 5}\n"))
    velocity = next(f for f in analysis.findings if f.id == "continuity"
                    and f.quantity == "velocity")
    assert velocity.ok, velocity.message


def test_a_lift_of_nanometres_is_a_cam_that_barely_moves() -> None:
    analysis = analyse(design_from_text(
        "name: n\ncam:\n  type: circular-arc\n  base_radius: 30\n  lift: 1e-9\n"
        "  lift_angle: 170\n  nose_radius: 29.99\nfollower: {type: roller, roller_radius: 5}\n"))
    assert analysis.program.max_lift == pytest.approx(1e-9, rel=1e-5)
    assert analysis.exit_code in (0, 1)
