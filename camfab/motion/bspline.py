"""``spline`` motion law: a B-spline of a stated order with its ends fixed and free control values
between them, the law a tuner shapes.

The spline has order k (degree k − 1) on knots clamped (k-fold) at u = 0 and u = 1 with uniform
interior knots, so it is C^(k−2) inside: order 6 (quintic) keeps f and its first four derivatives
continuous, what a polydyne cam's output motion needs. At a clamped end the j-th derivative
depends on the first (last) j + 1 control values alone, so f = 0 (1) and the derivatives
1 … k − 2 at each end fix k − 1 control values there, solved from a triangular system; the
control values between them are free. Evaluation, derivatives and pieces are scipy's exact
B-spline arithmetic; the peaks come from the pieces' polynomial roots. scipy is imported only
when a design uses a spline.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from camfab.motion.law import Array, Law, as_unit_array
from camfab.motion.polynomial import peak_of_pieces

#: The least order: a cubic (order 4) is the lowest whose acceleration is continuous inside.
MIN_SPLINE_ORDER = 4
#: The greatest order: order 10 keeps eight derivatives continuous, far past the fifth that
#: any of camfab's analyses reads; higher orders only add end conditions nobody can give and
#: make the end blocks' solve less well conditioned.
MAX_SPLINE_ORDER = 10
#: The order a design gets when it gives none: 6, a quintic, continuous to the fourth
#: derivative (a polydyne cam's output motion).
DEFAULT_SPLINE_ORDER = 6
#: The free control values a design gets when it gives none: four, enough to move the peak of
#: the velocity and the acceleration's shape either way without making a tuner's search large.
DEFAULT_SPLINE_CONTROLS = 4
#: The most free control values: far more shape than one segment's motion needs. The end
#: derivatives rest on differences of neighbouring control values, so the rounding of the
#: j-th grows as (k·n)ʲ·1e-16: at 100 an order-6 spline's fourth derivative at its ends still
#: holds some nine digits of its peak.
MAX_SPLINE_CONTROLS = 100


class BSplineLaw(Law):
    """f(u), u ∈ [0, 1], a clamped B-spline of *order* k with control values
    ``[fixed at 0] + free + [fixed at 1]``.

    Parameters
    ----------
    order
        k = degree + 1, from :data:`MIN_SPLINE_ORDER` to :data:`MAX_SPLINE_ORDER`.
    free
        The free control values in order along u (normalised: 0 is the segment's start lift,
        1 its end lift; values in [0, 1] keep f in [0, 1] where the ends allow).
    start, end
        f′, f″, … f⁽ᵏ⁻²⁾ (normalised) at u = 0 and u = 1: k − 2 values each (zeros: at rest,
        next to a dwell).
    """

    name = "spline"
    top_order = 5

    def __init__(self, order: int, free: Sequence[float], start: Sequence[float] | None = None,
                 end: Sequence[float] | None = None) -> None:
        from scipy.interpolate import BSpline
        from scipy.linalg import solve_triangular

        if not MIN_SPLINE_ORDER <= order <= MAX_SPLINE_ORDER:
            raise ValueError(f"order must be from {MIN_SPLINE_ORDER} to {MAX_SPLINE_ORDER} "
                             f"(got {order})")
        self.order = int(order)
        self.free = tuple(float(v) for v in free)
        self.start = _end_values(start, order, "start")
        self.end = _end_values(end, order, "end")
        if not all(np.isfinite([*self.free, *self.start, *self.end])):
            raise ValueError("the control and end values must be finite")
        #: The knots (n + k,): k-fold at 0 and 1, uniform between.
        self.knots = spline_knots(order, len(self.free))
        count = len(self.knots) - order
        fixed = order - 1
        # f⁽ʲ⁾ at u = 0 of the basis: lower triangular in c₀ … c_(k−2), with c₀ = f(0) = 0; at
        # u = 1 the same mirrored, solved for the offsets from c_(n−1) = f(1) = 1 (the
        # derivatives of a constant vanish), so an end at rest has its values exactly 0 or 1
        basis: Any = BSpline(self.knots, np.eye(count), order - 1)
        at_start = np.stack([basis(0.0, nu=j) for j in range(1, fixed)])[:, 1:fixed]
        at_end = np.stack([basis(1.0, nu=j) for j in range(1, fixed)])[:, -fixed:-1]
        first = solve_triangular(at_start, np.array(self.start), lower=True)
        last = solve_triangular(at_end[:, ::-1], np.array(self.end), lower=True)[::-1]
        first, last = np.concatenate([[0.0], first]), np.concatenate([1.0 + last, [1.0]])
        #: Every control value (n,): the fixed ones at the start, :attr:`free`, those at the end.
        self.control_values = np.concatenate([first, self.free, last])
        spline: Any = BSpline(self.knots, self.control_values, order - 1)
        # each derivative a spline of its own, its control values the differences of the last
        # one's: equal values next to an end at rest give exactly 0 there
        self._splines: list[Any] = [spline]
        for _ in range(min(5, order - 1)):
            self._splines.append(self._splines[-1].derivative())
        self.breakpoints = tuple(float(v) for v in np.unique(self.knots)[1:-1])
        # a cubic's jerk steps at its interior knots; a quartic's snap (past the jerk) steps
        self.inner_step_order = 3 if order == 4 else None
        if order < 6:  # C⁴ inside, what top_order 5 promises, needs a quintic
            self.top_order = 3

    @classmethod
    def smooth(cls, order: int, count: int, start: Sequence[float] | None = None,
               end: Sequence[float] | None = None) -> BSplineLaw:
        """The law with *count* free values taken from the smooth rise of its order (the
        regularised incomplete beta function I_u(k − 1, k − 1), whose derivatives 1 … k − 2
        vanish at both ends: the 5-6-7-8-9 polynomial for order 6) at the Greville abscissae,
        where a B-spline's control values follow its curve."""
        from scipy.special import betainc

        if not 0 <= count <= MAX_SPLINE_CONTROLS:
            raise ValueError(f"count must be from 0 to {MAX_SPLINE_CONTROLS} (got {count})")
        at = greville(spline_knots(order, count), order)[order - 1 : order - 1 + count]
        return cls(order, betainc(order - 1, order - 1, at), start, end)

    def with_free(self, free: Sequence[float]) -> BSplineLaw:
        """The same order and ends with other free control values (as many or not)."""
        return BSplineLaw(self.order, free, self.start, self.end)

    def evaluate(self, u: ArrayLike) -> Array:
        return self.derivatives(u, 3)

    def derivatives(self, u: ArrayLike, order: int) -> Array:
        if order > self.top_order:
            raise ValueError(f"the {self.name} law of order {self.order} gives derivatives up "
                             f"to {self.top_order}")
        u = as_unit_array(u)
        return np.stack([np.asarray(self._splines[n](u), dtype=np.float64)
                         for n in range(order + 1)])

    def pieces(self) -> tuple[Array, tuple[Array, ...]]:
        """Each knot span's Taylor coefficients f⁽ʲ⁾(a⁺)/j! at its first knot a (scipy's
        ``PPoly.from_spline`` does the same through FITPACK, which stops at degree 5)."""
        breaks = np.unique(self.knots)
        spline = self._splines[0]
        rows = [np.asarray(spline(breaks[:-1], nu=j), dtype=np.float64) / math.factorial(j)
                for j in range(self.order)]
        return breaks, tuple(np.ascontiguousarray(c) for c in np.stack(rows, axis=1))

    def _peaks(self) -> tuple[float, float, float]:
        breaks, coefficients = self.pieces()
        return (peak_of_pieces(breaks, coefficients, 1), peak_of_pieces(breaks, coefficients, 2),
                peak_of_pieces(breaks, coefficients, 3))

    def __repr__(self) -> str:
        return f"<BSplineLaw order {self.order}, free {list(self.free)}>"


def spline_knots(order: int, count: int) -> Array:
    """The knots of a spline law of *order* with *count* free values: k-fold at 0 and 1 with
    k − 2 + *count* uniform interior knots (so that n = 2(k − 1) + count control values)."""
    interior = order - 2 + count
    inside = np.arange(1, interior + 1) / (interior + 1)
    return np.concatenate([np.zeros(order), inside, np.ones(order)])


def greville(knots: Array, order: int) -> Array:
    """The Greville abscissae (n,): each control value's mean of its k − 1 inner knots."""
    count = len(knots) - order
    return np.array([knots[i + 1 : i + order].mean() for i in range(count)])


def _end_values(given: Sequence[float] | None, order: int, where: str) -> tuple[float, ...]:
    """The k − 2 end derivatives at *where*, zeros when not given."""
    if given is None:
        return (0.0,) * (order - 2)
    values = tuple(float(v) for v in given)
    if len(values) != order - 2:
        raise ValueError(f"{where} needs {order - 2} derivatives for order {order} "
                         f"(got {len(values)})")
    return values
