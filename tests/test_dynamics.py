"""Dynamics of force-closed cams against the seed's jump example and THEORY §E's formulas,
computed independently (finite differences of the lift, the eccentric cam's closed form)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from camfab.pipeline import analyse, design_from_text, load_design, render

from .conftest import DESIGNS

SEED = DESIGNS / "seed-jump-eccentric.yaml"


def test_seed_jump_speed() -> None:
    """Published: ω_j = √((P + 2ke)/(m e)) = 197.784 rad/s, 1888.70 rpm (g = 9.81)."""
    analysis = analyse(load_design(SEED))
    dyn = analysis.dynamics
    assert dyn is not None
    assert dyn.jump_speed_rad_s == pytest.approx(197.784, rel=2e-5)
    assert dyn.jump_speed_rpm == pytest.approx(1888.70, rel=2e-5)
    assert dyn.jump_at_deg == pytest.approx(180.0, abs=0.06)
    report = json.loads(render(analysis).files["seed-jump-eccentric-report.json"])
    assert report["dynamics"]["jump_speed_rpm"] == pytest.approx(1888.70, rel=2e-5)
    jump = next(c for c in report["checks"] if c["id"] == "jump")
    assert jump["ok"]  # 1500 rpm is below the jump speed


def test_eccentric_contact_force_closed_form() -> None:
    """F = P + k e + (m e ω² − k e) cos θ (the seed's derivation), P = m g + k δᵢ."""
    analysis = analyse(load_design(SEED))
    dyn = analysis.dynamics
    assert dyn is not None and dyn.force_N is not None
    m, k, e, omega = 1.75, 24000.0, 0.0375, 1500 * math.pi / 30
    p = m * 9.80665 + k * 0.03125
    expected = p + k * e + (m * e * omega**2 - k * e) * np.cos(dyn.theta)
    assert np.max(np.abs(dyn.force_N - expected)) < 1e-6 * np.max(np.abs(expected))
    # torque T = F s′ with s′ = e sin θ per radian
    assert np.max(np.abs(dyn.torque_N_m - expected * e * np.sin(dyn.theta))) < 1e-6


def test_above_the_jump_speed_the_follower_leaves_the_cam() -> None:
    text = SEED.read_text().replace("speed_rpm: 1500", "speed_rpm: 2000")
    analysis = analyse(design_from_text(text))
    jump = next(f for f in analysis.findings if f.id == "jump")
    assert not jump.ok and analysis.exit_code == 1
    # the seed's θ = 180°, where the cam pulls away fastest
    assert any(a <= 180.0 <= b for a, b in jump.ranges_deg)
    dyn = analysis.dynamics
    assert dyn is not None and dyn.required_preload_N is not None
    # with exactly the required preload, the smallest force is zero
    fixed = text.replace("initial_compression: 31.25", f"initial_compression: "
                         f"{dyn.required_preload_N / 24:.9f}")
    again = analyse(design_from_text(fixed)).dynamics
    assert again is not None and again.min_force_N == pytest.approx(0.0, abs=1e-6)


def test_general_program_with_damping_and_load() -> None:
    """A translating roller with a cycloidal rise and a 3-4-5 return, damping and an external
    load: F = m ω² s″ + c ω s′ + k(δ₀ + s) + F_ext + m g from finite differences of s."""
    text = """\
name: dyn-general
cam: {type: disc, base_radius: 30, speed_rpm: 900}
follower: {type: roller, roller_radius: 8, mass: 0.6}
motion:
  - rise:   {angle: 120, lift: 18, law: cycloidal}
  - dwell:  {angle: 40}
  - return: {angle: 110, law: polynomial-345}
  - dwell:  {angle: 90}
spring: {rate: 5, preload: 60, gravity: true, damping: 40, external_load: 15}
"""
    design = design_from_text(text)
    dyn = analyse(design).dynamics
    assert dyn is not None and dyn.force_N is not None
    theta = dyn.theta
    h = 1e-4  # the second difference: truncation ∝ h², roundoff of the laws ∝ 1/h²
    interior = np.min(np.abs(theta[:, None] - np.radians([0, 120, 160, 270, 360])), axis=1) > 2 * h

    def s(t: np.ndarray) -> np.ndarray:
        return design.program.evaluate(t)[0] / 1000.0  # m

    s1 = (s(theta + h) - s(theta - h)) / (2 * h)
    s2 = (s(theta + h) - 2 * s(theta) + s(theta - h)) / h**2
    omega = 900 * math.pi / 30
    force = 0.6 * omega**2 * s2 + 40 * omega * s1 + 5000 * s(theta) + 60 + 15 + 0.6 * 9.80665
    # the finite differences hold about 6 digits
    scale = float(np.max(np.abs(force)))
    assert np.max(np.abs(dyn.force_N - force)[interior]) < 1e-5 * scale
    assert np.max(np.abs(dyn.torque_N_m - force * s1)[interior]) < 1e-5 * scale * 0.02
    # jump: the smallest speed at which the same force (its damping too) reaches zero, by
    # bisection on the speed over the finite differences
    hold = 5000 * s(theta) + 60 + 15 + 0.6 * 9.80665
    low, high = 1.0, 1e4
    while high - low > 1e-9 * high:
        middle = 0.5 * (low + high)
        least = np.min((0.6 * middle**2 * s2 + 40 * middle * s1 + hold)[interior])
        low, high = (middle, high) if least >= 0.0 else (low, middle)
    assert dyn.jump_speed_rad_s == pytest.approx(low, rel=1e-5)


def test_no_spring_no_dynamics() -> None:
    analysis = analyse(load_design(DESIGNS / "seed-10-4.yaml"))
    assert analysis.dynamics is None
    report = json.loads(render(analysis).files["seed-10-4-report.json"])
    assert report["dynamics"]["jump_speed_rpm"] is None
