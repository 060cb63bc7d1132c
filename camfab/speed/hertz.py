"""Hertz contact of two elastic bodies (THEORY §I): the effective modulus, line contact of two
cylinders, and point contact over an elliptical area.

Units: forces in N, lengths in mm, curvatures in 1/mm, moduli and pressures in MPa (N/mm²).
A curvature is positive where the body is convex toward the other, negative where it is
concave, 0 where it is straight; the contact's curvature sum is the two bodies' added.

The elliptical contact is solved exactly through the complete elliptic integrals K(m) and
E(m) of the parameter m = e² (e the ellipse's eccentricity), computed here by the
arithmetic-geometric mean rather than through ``scipy.special``, whose import (some 0.17 s)
would cost a build more than all of its dynamics (``benchmarks/dynamics_speed.py``); the AGM
gives both to the last bit in six to eight rounds.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from camfab.arrays import Array


def effective_modulus(e1: float, nu1: float, e2: float, nu2: float) -> float:
    """E* (MPa) of two bodies of Young's moduli *e1*, *e2* (MPa) and Poisson's ratios *nu1*,
    *nu2*: 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂."""
    return 1.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2)


def line_contact(force: Array, length: float, curvature: Array,
                 modulus: float) -> tuple[Array, Array]:
    """Two cylinders pressed together along a line: the largest pressure p₀ = √(F E* Σκ/(π L))
    (MPa) and the half-width of the contact band b = √(4 F/(π L E* Σκ)) (mm), for the normal
    force *force* (N), the contact's *length* L (mm), the curvature sum Σκ = 1/R* (1/mm) and
    the effective *modulus* E* (MPa). Where the force is not positive the pressure and the band
    are 0; where Σκ ≤ 0 (surfaces that conform or cross) they are NaN."""
    force = np.maximum(np.asarray(force, dtype=np.float64), 0.0)
    curvature = np.asarray(curvature, dtype=np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        good = curvature > 0.0
        safe = np.where(good, curvature, 1.0)
        pressure = np.sqrt(force * modulus * safe / (math.pi * length))
        half_width = np.sqrt(4.0 * force / (math.pi * length * modulus * safe))
    return np.where(good, pressure, np.nan), np.where(good, half_width, np.nan)


def elliptic_integrals(m: Array) -> tuple[Array, Array]:
    """The complete elliptic integrals of the first and second kind, K(m) and E(m), of the
    parameter *m* (0 ≤ m < 1), by the arithmetic-geometric mean: K = π/(2 M(1, √(1 − m))),
    E = K (1 − Σ 2ⁿ⁻¹ cₙ²) with c₀² = m (Abramowitz & Stegun 17.6)."""
    m = np.asarray(m, dtype=np.float64)
    a = np.ones_like(m)
    b = np.sqrt(1.0 - m)
    c2 = m.copy()  # cₙ², from c₀² = m
    total = 0.5 * c2
    power = 0.5
    for _ in range(30):
        if not np.any(c2 > 1e-32 * (a * a)):
            break
        a, b, c2 = 0.5 * (a + b), np.sqrt(a * b), (0.5 * (a - b)) ** 2
        power *= 2.0
        total += power * c2
    k = math.pi / (2.0 * a)
    return k, k * (1.0 - total)


def _ratio_parts(m: Array) -> tuple[Array, Array, Array]:
    """(K − E)/m, E/(1 − m) − K (over m as well) and K, for the ellipse's parameter *m*: the
    two sides of the gap's curvatures, B/A = [E/(1 − m) − K]/(K − E). Near m = 0 both
    quotients are their series (π/4)(1 + 3m/8) and (π/4)(1 + 5m/8), where the differences
    would cancel."""
    m = np.asarray(m, dtype=np.float64)
    k, e = elliptic_integrals(m)
    small = m < 1e-6
    with np.errstate(divide="ignore", invalid="ignore"):
        lower = np.where(small, 0.25 * math.pi * (1.0 + 0.375 * m), (k - e) / np.where(small, 1.0,
                                                                                       m))
        upper = np.where(small, 0.25 * math.pi * (1.0 + 0.625 * m),
                         (e / (1.0 - m) - k) / np.where(small, 1.0, m))
    return lower, upper, k


@lru_cache(maxsize=1)
def _ratio_table() -> tuple[Array, Array]:
    """log(B/A) against t = −log(1 − m) on a grid from m = 0 to m = 1 − e⁻⁴⁰ (an ellipse
    some 5×10⁸ times as long as wide): the start of each inversion."""
    t = np.linspace(0.0, 40.0, 2001)
    m = -np.expm1(-t)
    lower, upper, _ = _ratio_parts(m)
    return np.log(upper / lower), t


def _eccentricity(ratio: Array) -> Array:
    """The parameter m = e² of the contact ellipse whose curvatures stand in *ratio* = B/A ≥ 1:
    read from a table, then Newton's method on log(B/A) in t = −log(1 − m)."""
    log_ratio, t_grid = _ratio_table()
    target = np.log(np.maximum(np.asarray(ratio, dtype=np.float64), 1.0))
    t = np.interp(target, log_ratio, t_grid)
    for _ in range(4):
        m = -np.expm1(-t)
        lower, upper, _ = _ratio_parts(m)
        value = np.log(upper / lower)
        # d/dt by a relative step: the table puts t within 1e-3 of the root already
        h = 1e-6 * np.maximum(t, 1e-3)
        m2 = -np.expm1(-(t + h))
        lower2, upper2, _ = _ratio_parts(m2)
        slope = (np.log(upper2 / lower2) - value) / h
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.where(slope > 0.0, (value - target) / slope, 0.0)
        t = np.maximum(t - step, 0.0)
    return -np.expm1(-t)


def point_contact(force: Array, curvature_x: Array, curvature_y: Array,
                  modulus: float) -> tuple[Array, Array, Array]:
    """Two bodies touching at a point, their principal directions aligned: the largest
    pressure p₀ (MPa) and the contact ellipse's semi-axes a ≥ b (mm), for the normal force
    *force* (N), the curvature sums in the two principal directions (1/mm; each body's
    curvatures added) and the effective *modulus* E* (MPa).

    The gap is h = A x² + B y² with A, B half the smaller and the larger sum; the ellipse's
    eccentricity solves B/A = [E(m)/(1 − m) − K(m)] / [K(m) − E(m)], then
    a³ = 3F (K − E)/(2π A E* m), b = a √(1 − m) and p₀ = 3F/(2π a b) (Johnson, *Contact
    Mechanics*, §4.2). Where the force is not positive the pressure and the axes are 0; where
    a sum is not positive, NaN."""
    force = np.maximum(np.asarray(force, dtype=np.float64), 0.0)
    cx, cy = np.broadcast_arrays(np.asarray(curvature_x, dtype=np.float64),
                                 np.asarray(curvature_y, dtype=np.float64))
    good = (cx > 0.0) & (cy > 0.0)
    small = np.where(good, 0.5 * np.minimum(cx, cy), 1.0)
    large = np.where(good, 0.5 * np.maximum(cx, cy), 1.0)
    m = _eccentricity(large / small)
    lower, _, _ = _ratio_parts(m)
    a = np.cbrt(3.0 * force * lower / (2.0 * math.pi * small * modulus))
    b = a * np.sqrt(1.0 - m)
    with np.errstate(divide="ignore", invalid="ignore"):
        pressure = np.where(force > 0.0, 3.0 * force / (2.0 * math.pi * a * b), 0.0)
    nan = np.nan
    return (np.where(good, pressure, nan), np.where(good, a, nan), np.where(good, b, nan))
