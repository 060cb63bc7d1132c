"""Every worked example of the source notes that has a motion program, against its published
answers. Textbooks round ω and intermediate values: comparisons allow about 0.3 %."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from camfab.motion.program import build_program
from camfab.pipeline import analyse, load_design

from .conftest import DESIGNS

PUBLISHED_REL = 3e-3


def stats(name: str):
    return analyse(load_design(DESIGNS / f"{name}.yaml"))


def test_seed_10_4_offset_roller_shm_and_uniform_acceleration() -> None:
    """10.4: v_o = 3.14 m/s, a_o = 493.47 m/s², v_R = 6 m/s, a_R = 900 m/s² at 1000 rpm."""
    a = stats("seed-10-4")
    rise, ret = a.segments[0], a.segments[2]
    assert (rise.kind, rise.law, ret.kind, ret.law) == (
        "rise", "harmonic", "return", "uniform-acceleration")
    assert rise.max_si[0] == pytest.approx(3.14, rel=PUBLISHED_REL)
    assert rise.max_si[1] == pytest.approx(493.47, rel=PUBLISHED_REL)
    assert ret.max_si[0] == pytest.approx(6.0, rel=PUBLISHED_REL)
    assert ret.max_si[1] == pytest.approx(900.0, rel=PUBLISHED_REL)
    assert rise.max_si[2] is None and ret.max_si[2] is None  # acceleration steps: jerk unbounded


def test_seed_shm_outstroke_and_uniform_acceleration_return_at_360_rpm() -> None:
    """Notes p. 11: 1.50 m/s, 113.69 m/s², 2.8799 m/s, 207.35 m/s² (ω rounded to 37.69)."""
    a = stats("seed-c11-shm-ua")
    rise, ret = a.segments[0], a.segments[2]
    assert rise.max_si[0] == pytest.approx(1.50, abs=0.01)  # the notes truncate 1.5076 to 1.50
    assert rise.max_si[1] == pytest.approx(113.69, rel=PUBLISHED_REL)
    assert ret.max_si[0] == pytest.approx(2.8799, rel=PUBLISHED_REL)
    assert ret.max_si[1] == pytest.approx(207.35, rel=PUBLISHED_REL)


def test_seed_10_3_oscillating_swing_and_arc() -> None:
    """10.3: the arm of 45 mm swings 28°, so the roller centre travels S = 45 × 28° ≈ 22 mm."""
    design = load_design(DESIGNS / "seed-10-3-oscillating.yaml")
    program = build_program(design.motion)
    assert math.degrees(program.max_lift) == pytest.approx(28.0)
    arc = design.follower.arm_length * program.max_lift
    assert arc == pytest.approx(22.0, rel=PUBLISHED_REL)
    a = analyse(design)
    assert a.units.lift_key == "lift_deg"
    assert a.segments[0].lift == pytest.approx(28.0)


def test_seed_2_3_polynomial_slopes_per_degree() -> None:
    """2-3 D-R-D cam, 30 mm over 90°: |dy/dθ| = 0.5e-3 m/° at 45°,
    d²y/dθ² = 2.222e-5 m/°² at 90°."""
    design = load_design(DESIGNS / "seed-poly-23.yaml")
    program = build_program(design.motion)
    per_deg = math.pi / 180
    # the fall of the seed starts at 180° here
    fall = program.segments[2]
    values = fall.evaluate_local(np.radians([45.0, 90.0]))
    assert values[1, 0] * per_deg == pytest.approx(-0.5, rel=1e-12)  # mm/° = 0.5e-3 m/°
    assert values[2, 1] * per_deg**2 == pytest.approx(0.02222, rel=PUBLISHED_REL)  # mm/°²
    # the seed's closed form y = 0.03 - 0.09 (θ/90)² + 0.06 (θ/90)³ (metres)
    theta = np.linspace(0, 90, 91)
    y = 30 - 90 * (theta / 90) ** 2 + 60 * (theta / 90) ** 3
    np.testing.assert_allclose(fall.evaluate_local(np.radians(theta))[0], y, atol=1e-12)
    a = analyse(design)
    assert a.segments[2].max_per_rad[0] * per_deg == pytest.approx(0.5)


def test_seed_3_4_5_from_boundary_conditions() -> None:
    """The six-condition derivation gives y = 1 − 10θ³ + 15θ⁴ − 6θ⁵ for the fall."""
    design = load_design(DESIGNS / "seed-poly-345.yaml")
    program = build_program(design.motion)
    u = np.linspace(0, 1, 101)
    rise, fall = program.segments[0], program.segments[2]
    np.testing.assert_allclose(rise.evaluate_local(u * rise.span)[0],
                               25 * (10 * u**3 - 15 * u**4 + 6 * u**5), atol=1e-9)
    np.testing.assert_allclose(fall.evaluate_local(u * fall.span)[0] / 25,
                               1 - 10 * u**3 + 15 * u**4 - 6 * u**5, atol=1e-12)


def test_seed_eccentric_cam_motion_and_its_jump_speed() -> None:
    """y = e(1 − cos θ) with e = 37.5 mm; with THEORY §E's jump formula and the seed's data the
    motion gives ω_j = 197.78 rad/s (1888.7 rpm), as published."""
    design = load_design(DESIGNS / "seed-jump-eccentric.yaml")
    program = build_program(design.motion)
    theta = np.linspace(0, 2 * math.pi, 721)
    s, _, s2, _ = program.evaluate(theta)
    e = 37.5
    np.testing.assert_allclose(s, e * (1 - np.cos(theta)), atol=1e-10)
    np.testing.assert_allclose(s2, e * np.cos(theta), atol=1e-10)
    spring = design.spring
    m, k, delta0 = design.follower.mass, spring.rate * 1000, spring.initial_compression / 1000
    preload = k * delta0 + m * 9.81  # N
    falling = s2 < 0
    omega_j2 = np.min((preload + k * s[falling] / 1000) / (-m * s2[falling] / 1000))
    assert math.sqrt(omega_j2) == pytest.approx(197.78, rel=1e-4)
    assert math.sqrt(omega_j2) * 60 / (2 * math.pi) == pytest.approx(1888.7, rel=1e-4)
    # a full-cycle harmonic is smooth everywhere: no continuity finding fails
    assert all(f.ok for f in analyse(design).findings)


# ---- the notes' pressure-angle formula and its conclusions ----------------------------------

def _with(text: str, **changes: str) -> str:
    for old, new in changes.items():
        text = text.replace(old, new)
    return text


def _rise_and_return_pressure(text: str) -> tuple[float, float]:
    from camfab.pipeline import design_from_text

    analysis = analyse(design_from_text(text))
    assert analysis.numbers is not None
    per_segment = analysis.numbers.segment_pressure
    rise = next(i for i, s in enumerate(analysis.program.segments) if s.kind == "rise")
    ret = next(i for i, s in enumerate(analysis.program.segments) if s.kind == "return")
    return per_segment[rise].value or 0.0, per_segment[ret].value or 0.0


def test_pressure_angle_formula_of_the_notes() -> None:
    """tan φ = (dy/dθ − e)/(√(r_b² − e²) + y), r_b the prime radius (ccw cam, offset e)."""
    design = load_design(DESIGNS / "seed-10-4.yaml")
    analysis = analyse(design)
    assert analysis.geometry is not None
    theta = np.linspace(0, 2 * math.pi, 3600, endpoint=False)
    m = design.program.evaluate(theta)
    e, rp = 10.0, 27.0
    notes = np.degrees(np.arctan((m[1] - e) / (math.sqrt(rp**2 - e**2) + m[0])))
    ours = np.degrees(analysis.geometry.cam.pressure_angle(theta, m))
    assert np.max(np.abs(ours - notes)) < 1e-9
    rise = analysis.numbers.segment_pressure[0] if analysis.numbers else None
    assert rise is not None and rise.value == pytest.approx(25.47, abs=0.01)


def test_offset_lowers_the_rise_pressure_angle_and_raises_the_return() -> None:
    """Conclusion ②: increasing e lowers φ on the outstroke and raises it on the return.

    Only while s′ > e where the rise is steepest: at e = 15 mm the start of the rise, where
    s′ = 0, has |φ| = atan(e/√(Rp² − e²)) = 33.7° and becomes the worst point.
    """
    text = (DESIGNS / "seed-10-4.yaml").read_text()
    angles = [_rise_and_return_pressure(_with(text, **{"offset: 10": f"offset: {e}"}))
              for e in (0, 5, 10)]
    rises, returns = zip(*angles, strict=True)
    assert all(a > b for a, b in itertools.pairwise(rises))
    assert all(a < b for a, b in itertools.pairwise(returns))
    # on a clockwise cam the same offset acts the other way round (SPEC §2)
    cw = [_rise_and_return_pressure(_with(text, **{"offset: 10": f"offset: {e}",
                                                   "rotation: ccw": "rotation: cw"}))
          for e in (-10, 0, 10)]
    assert cw[0][0] < cw[1][0] < cw[2][0]


def test_larger_base_circle_lowers_the_pressure_angle() -> None:
    """Conclusion ③: with e = 0, tan φ = (dy/dθ)/(r_b + y), so a larger r_b lowers φ."""
    text = _with((DESIGNS / "seed-10-4.yaml").read_text(), **{"offset: 10": "offset: 0"})
    rises = [_rise_and_return_pressure(_with(text, **{"base_radius: 20": f"base_radius: {rb}"}))[0]
             for rb in (20, 30, 45)]
    assert rises[0] > rises[1] > rises[2]
    # and for e = 0 the largest rise angle is atan(max over θ of s′/(Rp + s))
    design = load_design(DESIGNS / "seed-10-4.yaml")
    theta = np.linspace(0, 2 * math.pi / 3, 20001)
    m = design.program.evaluate(theta)
    expected = math.degrees(math.atan(float(np.max(m[1] / (27.0 + m[0])))))
    assert rises[0] == pytest.approx(expected, abs=1e-4)
