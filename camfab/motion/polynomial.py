"""Polynomial motion laws: the fixed 2-3, 3-4-5, 4-5-6-7 laws and the general polynomial.

The general polynomial is the seed's method: s(u) = Σ cₖuᵏ with the boundary conditions
f(0) = 0, f(1) = 1 and any chosen derivatives at the ends (and points inside); its degree is the
number of conditions minus one and the coefficients solve a linear system.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.polynomial import polynomial as P
from numpy.typing import ArrayLike

from camfab.motion.law import Array, Law, as_unit_array


class PolynomialLaw(Law):
    """f(u) = Σ cₖ uᵏ with *coefficients* in ascending order."""

    def __init__(
        self,
        coefficients: ArrayLike,
        name: str = "polynomial",
        peaks: tuple[float, float, float] | None = None,
    ) -> None:
        c = np.trim_zeros(np.asarray(coefficients, dtype=np.float64), "b")
        self.name = name
        self._coeffs = tuple(c if c.size else np.zeros(1))
        self._derivs = [np.asarray(self._coeffs)]
        for _ in range(6):
            self._derivs.append(P.polyder(self._derivs[-1]))
        self._given_peaks = peaks

    top_order = 5

    @property
    def degree(self) -> int:
        return len(self._coeffs) - 1

    def evaluate(self, u: ArrayLike) -> Array:
        u = as_unit_array(u)
        return np.stack([P.polyval(u, self._derivs[n]) for n in range(4)])

    def derivatives(self, u: ArrayLike, order: int) -> Array:
        if order > self.top_order:
            raise ValueError(f"the {self.name} law gives derivatives up to {self.top_order}")
        u = as_unit_array(u)
        return np.stack([P.polyval(u, self._derivs[n]) for n in range(order + 1)])

    def pieces(self) -> tuple[Array, tuple[Array, ...]]:
        return np.array([0.0, 1.0]), (np.asarray(self._coeffs),)

    def _peaks(self) -> tuple[float, float, float]:
        if self._given_peaks is not None:
            return self._given_peaks
        return (self._peak_of(1), self._peak_of(2), self._peak_of(3))

    def _peak_of(self, order: int) -> float:
        """max |p⁽ⁿ⁾| on [0, 1] from the ends and the real roots of p⁽ⁿ⁺¹⁾ inside."""
        return peak_of_pieces(*self.pieces(), order)


def peak_of_pieces(breaks: Array, coefficients: Sequence[Array], order: int) -> float:
    """max |p⁽ᵒʳᵈᵉʳ⁾| over polynomial pieces (as :meth:`Law.pieces` gives them): on each, from
    its ends and the real roots of p⁽ᵒʳᵈᵉʳ⁺¹⁾ inside it."""
    best = 0.0
    for a, b, c in zip(breaks[:-1], breaks[1:], coefficients, strict=True):
        width = float(b - a)
        this = P.polyder(c, order)
        nxt = P.polyder(this)
        candidates = [0.0, width]
        if np.any(nxt != 0) and nxt.size > 1:
            roots = P.polyroots(nxt)
            real = roots[np.abs(roots.imag) < 1e-9].real
            candidates.extend(float(r) for r in real if 0.0 < r < width)
        best = max(best, float(np.max(np.abs(P.polyval(np.array(candidates), this)))))
    return best


@dataclass(frozen=True)
class Condition:
    """f⁽ᵒʳᵈᵉʳ⁾(u) = value in normalised units (u ∈ [0, 1], f from 0 to 1)."""

    u: float
    order: int
    value: float


class SingularConditionsError(ValueError):
    """The boundary conditions do not determine a polynomial."""


def solve_polynomial(conditions: Sequence[Condition], name: str = "polynomial") -> PolynomialLaw:
    """The polynomial of least degree meeting *conditions* plus f(0) = 0 and f(1) = 1.

    Its degree is the number of conditions (including the two end values) minus one.
    """
    rows = [Condition(0.0, 0, 0.0), Condition(1.0, 0, 1.0), *conditions]
    n = len(rows)
    matrix = np.zeros((n, n))
    rhs = np.array([c.value for c in rows], dtype=np.float64)
    powers = np.arange(n)
    for i, cond in enumerate(rows):
        k = powers[cond.order :]
        # d^m/du^m u^k = k!/(k-m)! u^(k-m)
        factor = np.array([math.perm(int(kk), cond.order) for kk in k], dtype=np.float64)
        matrix[i, cond.order :] = factor * np.power(cond.u, k - cond.order)
    try:
        coeffs = np.linalg.solve(matrix, rhs)
    except np.linalg.LinAlgError:
        raise SingularConditionsError("the conditions do not determine a polynomial") from None
    if not np.all(np.isfinite(coeffs)) or np.linalg.cond(matrix) > 1e12:
        raise SingularConditionsError("the conditions do not determine a polynomial")
    return PolynomialLaw(coeffs, name=name)


SQRT3, SQRT5 = math.sqrt(3.0), math.sqrt(5.0)

POLYNOMIAL_23 = PolynomialLaw([0, 0, 3, -2], "polynomial-23", (1.5, 6.0, 12.0))
POLYNOMIAL_345 = PolynomialLaw([0, 0, 0, 10, -15, 6], "polynomial-345", (15 / 8, 10 / SQRT3, 60.0))
POLYNOMIAL_4567 = PolynomialLaw(
    [0, 0, 0, 0, 35, -84, 70, -20], "polynomial-4567", (35 / 16, 84 * SQRT5 / 25, 52.5)
)
#: The 5-6-7-8-9 polynomial: its first four derivatives vanish at both ends, so a polydyne
#: cam's acceleration (which carries the output's fourth) is continuous at its dwells. Its
#: peaks are found from the roots of its derivatives.
POLYNOMIAL_56789 = PolynomialLaw([0, 0, 0, 0, 0, 126, -420, 540, -315, 70], "polynomial-56789")
