"""Motion laws against independent references: finite differences of f, the published peak
coefficients (THEORY §A table), the end values f(0) = 0, f(1) = 1, and special-case identities."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from camfab.motion.law import Law, Mirrored
from camfab.motion.laws import (
    LAW_NAMES,
    Cycloidal,
    DoubleHarmonic,
    Harmonic,
    ModifiedUniformVelocity,
    UniformAcceleration,
    canonical_law_name,
    standard_law,
)
from camfab.motion.polynomial import Condition, solve_polynomial
from camfab.motion.scca import SCCA
from camfab.motion.table import SplineLaw

PI = math.pi

# Published peak coefficients (Cv, Ca, Cj inside the law); None: unbounded inside.
PUBLISHED = {
    "uniform-velocity": (1.0, 0.0, 0.0),
    "uniform-acceleration": (2.0, 4.0, None),
    "harmonic": (PI / 2, PI**2 / 2, PI**3 / 2),
    "cycloidal": (2.0, 2 * PI, 4 * PI**2),
    "polynomial-23": (1.5, 6.0, 12.0),
    "polynomial-345": (15 / 8, 10 / math.sqrt(3), 60.0),
    "polynomial-4567": (35 / 16, 84 * math.sqrt(5) / 25, 52.5),
    "modified-trapezoid": (2.0, 4.888, 61.43),
    "modified-sine": (1.760, 5.528, 69.47),
    "double-harmonic": (2.040, PI**2, 42.41),
}
# THEORY gives some constants to 3-4 significant figures.
PUBLISHED_REL = {"modified-trapezoid": 2e-4, "modified-sine": 3e-4, "double-harmonic": 3e-4}


def all_laws() -> list[tuple[str, Law]]:
    laws = [(name, standard_law(name)) for name in PUBLISHED]
    laws += [
        ("modified-uniform-velocity(0.2)", ModifiedUniformVelocity(0.2)),
        ("modified-uniform-velocity(0.5)", ModifiedUniformVelocity(0.5)),
        ("double-harmonic mirrored", Mirrored(DoubleHarmonic())),
        ("general polynomial", solve_polynomial([Condition(0, 1, 0.3), Condition(1, 1, 0),
                                                 Condition(0.4, 0, 0.5)])),
        ("table", SplineLaw([0, 0.2, 0.5, 0.7, 1], [0, 0.05, 0.45, 0.8, 1])),
        ("scca(0.3,0.2,0.5)", SCCA(0.3, 0.2, 0.5)),
    ]
    return laws


LAWS = all_laws()
IDS = [name for name, _ in LAWS]


@pytest.mark.parametrize(("name", "law"), LAWS, ids=IDS)
def test_ends_are_zero_and_one(name: str, law: Law) -> None:
    f = law.evaluate(np.array([0.0, 1.0]))[0]
    assert f[0] == pytest.approx(0.0, abs=1e-12)
    assert f[1] == pytest.approx(1.0, abs=1e-12)


def _smooth_points(law: Law, h: float) -> np.ndarray:
    u = np.linspace(3 * h, 1 - 3 * h, 397)
    for b in law.breakpoints:
        u = u[np.abs(u - b) > 3 * h]
    return u


@pytest.mark.parametrize(("name", "law"), LAWS, ids=IDS)
def test_derivatives_match_finite_differences_of_f(name: str, law: Law) -> None:
    h = 1e-3
    u = _smooth_points(law, h)

    def f(x: np.ndarray) -> np.ndarray:
        return law.evaluate(x)[0]

    fd1 = (f(u - 2 * h) - 8 * f(u - h) + 8 * f(u + h) - f(u + 2 * h)) / (12 * h)
    fd2 = (-f(u - 2 * h) + 16 * f(u - h) - 30 * f(u) + 16 * f(u + h) - f(u + 2 * h)) / (12 * h * h)
    fd3 = (f(u + 2 * h) - 2 * f(u + h) + 2 * f(u - h) - f(u - 2 * h)) / (2 * h**3)
    exact = law.evaluate(u)
    for order, fd in ((1, fd1), (2, fd2), (3, fd3)):
        scale = max(1.0, float(np.max(np.abs(exact[order]))))
        np.testing.assert_allclose(exact[order], fd, atol=2e-4 * scale, rtol=0,
                                   err_msg=f"{name}: order {order}")


@pytest.mark.parametrize("name", list(PUBLISHED))
def test_peak_coefficients_match_published_values(name: str) -> None:
    law = standard_law(name)
    rel = PUBLISHED_REL.get(name, 1e-12)
    for order, expected in enumerate(PUBLISHED[name], start=1):
        if expected is None:
            assert math.isinf(law.peak(order))
        else:
            assert law.peak(order) == pytest.approx(expected, rel=rel, abs=1e-12)


@pytest.mark.parametrize(("name", "law"), LAWS, ids=IDS)
def test_peak_coefficients_match_dense_sampling(name: str, law: Law) -> None:
    u = np.linspace(0.0, 1.0, 400_001)
    values = law.evaluate(u)
    for order in (1, 2, 3):
        if math.isinf(law.peak(order)):
            continue
        assert law.peak(order) == pytest.approx(float(np.max(np.abs(values[order]))), rel=1e-6,
                                                abs=1e-9)


def test_scca_special_cases_are_the_classic_laws() -> None:
    u = np.linspace(0, 1, 1001)
    pairs = [
        (SCCA(0.5, 0.0, 0.5), Cycloidal()),
        (SCCA(0.0, 0.0, 1.0), Harmonic()),
        (SCCA(0.0, 1.0, 0.0), UniformAcceleration()),
    ]
    for scca, law in pairs:
        np.testing.assert_allclose(scca.evaluate(u)[:3], law.evaluate(u)[:3], atol=1e-12)


def test_modified_uniform_velocity_with_half_blend_is_uniform_acceleration() -> None:
    u = np.linspace(0, 1, 1001)
    np.testing.assert_allclose(ModifiedUniformVelocity(0.5).evaluate(u),
                               UniformAcceleration().evaluate(u), atol=1e-12)


def test_modified_uniform_velocity_coefficients() -> None:
    r = 0.2
    law = ModifiedUniformVelocity(r)
    assert law.peak(1) == pytest.approx(1 / (1 - r))
    assert law.peak(2) == pytest.approx(1 / (r * (1 - r)))
    assert math.isinf(law.peak(3))


def test_general_polynomial_reproduces_the_seed_derivations() -> None:
    """The seed's method: 2, 4, 6 and 8 conditions give uniform velocity, 2-3, 3-4-5, 4-5-6-7."""
    zero = lambda order: [Condition(0.0, order, 0.0), Condition(1.0, order, 0.0)]  # noqa: E731
    u = np.linspace(0, 1, 101)
    assert np.allclose(solve_polynomial([]).evaluate(u)[0], u)
    assert np.allclose(solve_polynomial(zero(1)).evaluate(u)[0], 3 * u**2 - 2 * u**3)
    p345 = solve_polynomial(zero(1) + zero(2))
    assert np.allclose(p345.evaluate(u)[0], 10 * u**3 - 15 * u**4 + 6 * u**5)
    assert p345.degree == 5
    p4567 = solve_polynomial(zero(1) + zero(2) + zero(3))
    assert np.allclose(p4567.evaluate(u)[0], 35 * u**4 - 84 * u**5 + 70 * u**6 - 20 * u**7)


def test_double_harmonic_return_mirrors_the_rise() -> None:
    rise = DoubleHarmonic()
    back = rise.for_return()
    ends_rise, ends_back = rise.ends(), back.ends()
    assert ends_rise[0][2] == pytest.approx(0.0, abs=1e-12)  # f''(0) = 0
    assert ends_rise[1][2] == pytest.approx(-(PI**2))  # f''(1) = -π²
    # the mirrored law starts with the rise's end acceleration and ends at rest
    assert -ends_back[0][2] == pytest.approx(-(PI**2))
    assert ends_back[1][2] == pytest.approx(0.0, abs=1e-12)


def test_table_spline_passes_through_points_and_is_smooth_at_knots() -> None:
    knots = [0, 0.2, 0.5, 0.7, 1]
    values = [0, 0.05, 0.45, 0.8, 1]
    law = SplineLaw(knots, values)
    np.testing.assert_allclose(law.evaluate(np.array(knots))[0], values, atol=1e-12)
    eps = 1e-9
    for k in knots[1:-1]:
        left = law.evaluate(np.array([k - eps]))[:, 0]
        right = law.evaluate(np.array([k + eps]))[:, 0]
        np.testing.assert_allclose(left, right, atol=1e-5)  # C3 (and more) at every knot


@given(st.floats(0.0, 1.0), st.sampled_from([n for n in PUBLISHED]))
@settings(max_examples=200, deadline=None)
def test_symmetric_laws_satisfy_point_symmetry(u: float, name: str) -> None:
    law = standard_law(name)
    if name == "double-harmonic":
        return
    f = law.evaluate(np.array([u, 1 - u]))[0]
    assert f[0] + f[1] == pytest.approx(1.0, abs=1e-12)


def test_every_name_and_alias_resolves() -> None:
    for name in LAW_NAMES:
        assert canonical_law_name(name) == name
    for alias, name in [("shm", "harmonic"), ("Simple-Harmonic", "harmonic"), ("cubic",
                        "polynomial-23"), ("parabolic", "uniform-acceleration"),
                        ("constant_acceleration", "uniform-acceleration"),
                        ("linear", "uniform-velocity"), ("uniform", "uniform-velocity")]:
        assert canonical_law_name(alias) == name
    assert canonical_law_name("cycloid") is None
