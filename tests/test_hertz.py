"""Hertz contact against published worked examples and an independent solution of the
elliptical contact (scipy's elliptic integrals, the eccentricity by a bracketing root-finder):
line contact of two cylinders, a sphere on a flat, a ball in a bearing race and a sphere on a
cylinder (a mushroom follower on a cam)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import optimize, special

from camfab.speed.hertz import (
    effective_modulus,
    elliptic_integrals,
    line_contact,
    point_contact,
)

#: Unit conversions of the published examples in inch-pound units.
LBF_N, IN_MM, PSI_MPA = 4.4482216152605, 25.4, 0.00689475729


def test_line_contact_norton_example_7_2() -> None:
    """Norton, *Machine Design* (4th ed.), Example 7-2: a 12 in steel crane wheel on a flat
    rail, 0.875 in of contact, 5000 lbf (E = 30e6 psi, ν = 0.28): half-width 0.0518 in, largest
    pressure 70 243 psi."""
    e = 30e6 * PSI_MPA
    modulus = effective_modulus(e, 0.28, e, 0.28)
    pressure, half = line_contact(5000 * LBF_N, 0.875 * IN_MM, 1.0 / (6.0 * IN_MM), modulus)
    assert float(pressure) / PSI_MPA == pytest.approx(70243, rel=2e-5)
    assert float(half) / IN_MM == pytest.approx(0.0518, abs=6e-5)


def test_line_contact_marks_railway_wheel_in_si() -> None:
    """*Marks' Calculation for Machine Design*, ch. 3, Example 2: a 1 m wheel on a flat rail,
    0.1 m long, 147.5 kN, steel (210 GPa, ν = 0.3): b² = 8.14e-6 m²."""
    modulus = effective_modulus(210e3, 0.3, 210e3, 0.3)
    _, half = line_contact(147.5e3, 100.0, 1.0 / 500.0, modulus)
    assert (float(half) / 1000.0) ** 2 == pytest.approx(8.14e-6, rel=1e-3)


def test_line_contact_on_a_concave_surface_and_unloaded() -> None:
    """A roller in a concave surface bears on the difference of the curvatures; no force, no
    stress; surfaces that conform or cross have none to give."""
    modulus = effective_modulus(206e3, 0.3, 206e3, 0.3)
    pressure, _ = line_contact(np.array([1000.0, 0.0, 1000.0]), 10.0,
                               np.array([1 / 8 - 1 / 40, 1 / 8, -0.01]), modulus)
    expected = math.sqrt(1000.0 * modulus * (1 / 8 - 1 / 40) / (math.pi * 10.0))
    assert pressure[0] == pytest.approx(expected, rel=1e-12)
    assert pressure[1] == 0.0
    assert np.isnan(pressure[2])


def test_elliptic_integrals_match_scipy() -> None:
    m = np.array([0.0, 1e-12, 1e-6, 0.1, 0.5, 0.9, 0.999, 1 - 1e-9])
    k, e = elliptic_integrals(m)
    np.testing.assert_allclose(k, special.ellipk(m), rtol=2e-15)
    np.testing.assert_allclose(e, special.ellipe(m), rtol=2e-15)


def _reference(force: float, rx: float, ry: float, modulus: float) -> tuple[float, float,
                                                                            float]:
    """Hertz's elliptical contact solved independently: K and E from scipy's (Cephes), the
    eccentricity by Brent's method on B/A = ((a/b)² E − K)/(K − E) (Johnson §4.2)."""
    a_, b_ = sorted((0.5 * rx, 0.5 * ry))

    def kk(m: float) -> float:
        return float(special.ellipk(m))

    def ee(m: float) -> float:
        return float(special.ellipe(m))

    def ratio(m: float) -> float:
        return (ee(m) / (1 - m) - kk(m)) / (kk(m) - ee(m))

    if b_ / a_ - 1 < 1e-12:
        a = (3 * force / (4 * modulus) / (2 * a_)) ** (1 / 3)
        return 3 * force / (2 * math.pi * a * a), a, a
    m = optimize.brentq(lambda m: ratio(m) - b_ / a_, 1e-12, 1 - 1e-12, xtol=1e-15,
                        rtol=1e-15)
    a = (3 * force * (kk(m) - ee(m)) / (2 * math.pi * a_ * modulus * m)) ** (1 / 3)
    b = a * math.sqrt(1 - m)
    return 3 * force / (2 * math.pi * a * b), a, b


def test_sphere_on_a_flat_is_hertz_circle() -> None:
    """a³ = 3FR/(4E*), p₀ = 3F/(2πa²)."""
    modulus = effective_modulus(206e3, 0.3, 206e3, 0.3)
    pressure, a, b = point_contact(1000.0, 1 / 10, 1 / 10, modulus)
    radius = (3 * 1000.0 * 10.0 / (4 * modulus)) ** (1 / 3)
    assert float(a) == pytest.approx(radius, rel=1e-12)
    assert float(b) == pytest.approx(radius, rel=1e-12)
    assert float(pressure) == pytest.approx(3 * 1000.0 / (2 * math.pi * radius**2), rel=1e-12)


@pytest.mark.parametrize(("rx", "ry"), [(0.3, 0.2), (0.25, 0.0125), (1.0, 0.001),
                                        (0.2441, 0.004082), (0.05, 0.0499)])
def test_point_contact_against_the_elliptic_solution(rx: float, ry: float) -> None:
    modulus = effective_modulus(206e3, 0.3, 110e3, 0.33)
    pressure, a, b = point_contact(800.0, rx, ry, modulus)
    expected = _reference(800.0, rx, ry, modulus)
    np.testing.assert_allclose([float(pressure), float(a), float(b)], expected, rtol=1e-8)


def test_a_nearly_circular_contact_is_the_circle() -> None:
    """An ellipse of B/A = 1 + 1e-9 is the circle to that: the quotients (K − E)/m near m = 0
    are taken from their series, not from a difference that cancels."""
    modulus = effective_modulus(206e3, 0.3, 206e3, 0.3)
    circle = point_contact(500.0, 0.1, 0.1, modulus)
    near = point_contact(500.0, 0.1 * (1 + 1e-9), 0.1, modulus)
    np.testing.assert_allclose(np.array(near, dtype=float), np.array(circle, dtype=float),
                               rtol=1e-8)


def test_ball_in_a_race_amesweb_example() -> None:
    """A ball of 4.90 mm radius in a race groove of 5 mm on a race of 25 mm radius, 1500 N,
    steel (210 GPa, ν = 0.29): published a = 2.101 mm, b = 0.156 mm, p = 2193.6 MPa (from
    tabulated coefficients, within 0.4 %)."""
    modulus = effective_modulus(210e3, 0.29, 210e3, 0.29)
    pressure, a, b = point_contact(1500.0, 1 / 4.9 + 1 / 25, 1 / 4.9 - 1 / 5, modulus)
    assert float(a) == pytest.approx(2.101, rel=5e-3)
    assert float(b) == pytest.approx(0.156, rel=5e-3)
    assert float(pressure) == pytest.approx(2193.6, rel=5e-3)


def test_sphere_on_a_cylinder_norton_problem_7_20() -> None:
    """Norton, *Machine Design* (4th ed.), problem 7-20: a 20 mm steel ball on a 40 mm steel
    cylinder, 10 kN (E = 206.8 GPa, ν = 0.28), solved with curve-fitted coefficients: a =
    0.947 mm, b = 0.710 mm, p = 7097 MPa. The exact solution is within 2 % of those — a
    mushroom follower of 10 mm face radius on a cam of 20 mm radius of curvature."""
    modulus = effective_modulus(206.8e3, 0.28, 206.8e3, 0.28)
    pressure, a, b = point_contact(10e3, 1 / 10 + 1 / 20, 1 / 10, modulus)
    assert float(a) == pytest.approx(0.947, rel=0.02)
    assert float(b) == pytest.approx(0.710, rel=0.02)
    assert float(pressure) == pytest.approx(7097, rel=0.02)
    expected = _reference(10e3, 1 / 10 + 1 / 20, 1 / 10, modulus)
    np.testing.assert_allclose([float(pressure), float(a), float(b)], expected, rtol=1e-8)
