"""The interface every motion law implements.

A law is a normalised rise f(u) on u ∈ [0, 1] with f(0) = 0 and f(1) = 1. It gives f and its
first three derivatives with respect to u in closed form, vectorised over numpy arrays, and its
peak coefficients Cv = max|f′|, Ca = max|f″|, Cj = max|f‴| (``math.inf`` where a lower derivative
steps inside the law, so the next one is unbounded). A segment of span β and signed height Δ then
has s = s₀ + Δ·f(u), s′ = Δ f′/β, s″ = Δ f″/β², s‴ = Δ f‴/β³ (derivatives per radian).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod

import numpy as np
from numpy.typing import ArrayLike

from camfab.arrays import Array


class Law(ABC):
    """A normalised motion law f(u), u ∈ [0, 1], f(0) = 0, f(1) = 1."""

    #: Canonical name as written in design files.
    name: str = ""
    #: Interior values of u where the closed form changes piece (derivatives may kink there).
    breakpoints: tuple[float, ...] = ()
    #: Lowest derivative order that steps inside the law (None: smooth inside up to jerk).
    inner_step_order: int | None = None
    #: The highest derivative :meth:`derivatives` gives: 3 (f‴, as :meth:`evaluate`) for most
    #: laws; 5 for those a polydyne cam's output motion may follow (the cam's jerk carries the
    #: output's fifth derivative).
    top_order: int = 3

    @abstractmethod
    def evaluate(self, u: ArrayLike) -> Array:
        """f, f′, f″, f‴ at *u*: an array of shape (4, len(u)), each column computed from its
        own u alone (a program evaluates the segments that share a law in one call).

        At a breakpoint where a derivative steps, the value from the piece to the right is
        returned (the limit from increasing u), except at u = 1 where the last piece applies.
        """

    def derivatives(self, u: ArrayLike, order: int) -> Array:
        """f and its derivatives up to *order* (≤ :attr:`top_order`) at *u*: shape
        (order + 1, len(u)), with :meth:`evaluate`'s one-sided rule at breakpoints."""
        if order > self.top_order:
            raise ValueError(f"the {self.name} law gives derivatives up to {self.top_order}")
        return self.evaluate(u)[: order + 1]

    def pieces(self) -> tuple[Array, tuple[Array, ...]] | None:
        """The law as polynomial pieces, or None where it is not piecewise polynomial: the
        breaks (K + 1,) from 0 to 1 and each piece's coefficients in (u − its first break),
        ascending."""
        return None

    @abstractmethod
    def _peaks(self) -> tuple[float, float, float]:
        """Cv, Ca, Cj over the law's interior, ignoring inner steps."""

    def peak(self, order: int) -> float:
        """max |f⁽ᵒʳᵈᵉʳ⁾| over [0, 1]; ``math.inf`` when a lower derivative steps inside."""
        if not 1 <= order <= 3:
            raise ValueError(f"order must be 1, 2 or 3 (got {order})")
        if self.inner_step_order is not None and order > self.inner_step_order:
            return math.inf
        peaks = self.__dict__.get("_peak_values")
        if peaks is None:  # a law does not change: its peaks are found once
            peaks = self.__dict__["_peak_values"] = self._peaks()
        return peaks[order - 1]

    @property
    def coefficients(self) -> tuple[float, float, float]:
        """(Cv, Ca, Cj) with ``math.inf`` for unbounded values."""
        return (self.peak(1), self.peak(2), self.peak(3))

    def for_return(self) -> Law:
        """The law a return uses, so that s = s₀ − h·g(u) mirrors a rise in time.

        For laws with f(1 − u) = 1 − f(u) this is the law itself; asymmetric laws (double
        harmonic) override it.
        """
        return self

    def ends(self) -> Array:
        """Derivatives at the ends: shape (2, 4), rows u = 0⁺ and u = 1⁻."""
        return self.evaluate(np.array([0.0, 1.0])).T

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.name}>"


def as_unit_array(u: ArrayLike) -> Array:
    """*u* as a 1-D float array (no clipping: callers pass u ∈ [0, 1])."""
    return np.atleast_1d(np.asarray(u, dtype=np.float64))


class Mirrored(Law):
    """g(u) = 1 − f(1 − u): the time mirror of an asymmetric law, used by returns."""

    def __init__(self, law: Law) -> None:
        self.law = law
        self.name = law.name
        self.breakpoints = tuple(sorted(1.0 - b for b in law.breakpoints))
        self.inner_step_order = law.inner_step_order
        self.top_order = law.top_order

    def evaluate(self, u: ArrayLike) -> Array:
        values = self.law.evaluate(1.0 - as_unit_array(u))
        return np.stack([1.0 - values[0], values[1], -values[2], values[3]])

    def derivatives(self, u: ArrayLike, order: int) -> Array:
        values = self.law.derivatives(1.0 - as_unit_array(u), order)
        sign = (-1.0) ** (np.arange(order + 1) + 1)
        out = values * sign[:, None]
        out[0] += 1.0
        return out

    def pieces(self) -> tuple[Array, tuple[Array, ...]] | None:
        """g(u) = 1 − f(1 − u) piece by piece: f's piece on [a, b] read from u = 1 − b."""
        from numpy.polynomial import Polynomial

        found = self.law.pieces()
        if found is None:
            return None
        breaks, coefficients = found
        out = []
        for a, b, c in zip(breaks[-2::-1], breaks[:0:-1], coefficients[::-1], strict=True):
            flipped = Polynomial(c)(Polynomial([b - a, -1.0])).coef  # f at w − a = (b − a) − v
            out.append(np.concatenate([[1.0 - flipped[0]], -flipped[1:]]))
        return 1.0 - breaks[::-1], tuple(out)

    def _peaks(self) -> tuple[float, float, float]:
        return self.law._peaks()

    def for_return(self) -> Law:
        return self.law
