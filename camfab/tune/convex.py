"""The least peak acceleration (or jerk) of polynomial and spline laws, as a linear programme:
the global optimum of that convex sub-problem.

A ``polynomial`` law's coefficients solve a linear system whose right-hand side holds its
conditions: the end conditions (fixed, or matched to a neighbour's ends, which are fixed or
themselves linear in the free values) and its points' lifts; a ``spline`` law is a sum of
B-splines whose weights are its control values, the free ones and those its end conditions
fix. So with the points' shares and the free control values x
(:class:`~camfab.tune.families.PolynomialPoints`, :class:`~camfab.tune.families.SplineControls`)
free in [0, 1], every tuned segment's s⁽ⁿ⁾(θ) is affine in x, piece by polynomial piece, and the
peak max|s⁽ⁿ⁾| over the segments is a convex function of x — a minimax of affine functions. On
a grid of cam angles it is the linear programme

    minimise t  subject to  −t ≤ a_k + b_k·x ≤ t  at every grid point k,  0 ≤ x ≤ 1,

solved by HiGHS (:func:`scipy.optimize.linprog`). The continuous peak may lie between the
grid's points: the exact peak of each piece (at its ends or where s⁽ⁿ⁺¹⁾ vanishes: the roots
of a polynomial) is found at the solution, the places where it passes t added to the grid, and
the programme solved again, until the exact peak and t agree to :data:`AGREE` (an exchange
method for the semi-infinite programme). The answer is then the global optimum of the peak
over the tuned segments, within the limits of nothing but the parameters' bounds; the design's
other limits are checked on it afterwards (:mod:`camfab.tune.search`).

The affine map is read from the programs themselves: the design built at x = ½ and at ½ + ¼eᵢ
for each parameter (the map is exact, so these n + 1 builds give it to rounding).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.polynomial import polynomial as P

from camfab.arrays import Array
from camfab.design import Design

#: Grid points per unit of u (a whole segment) of the first programme, and the least a piece
#: takes (both ends included).
GRID, PIECE_GRID = 1001, 101
#: The exact peak and the programme's agree to this share (relative) when the exchange stops
#: (or when the exact extremes are on the grid already: the programme's answer is then as
#: exact as HiGHS's tolerances, :data:`TOLERANCE`, make it).
AGREE = 1e-10
#: HiGHS's primal and dual feasibility tolerances (its default, 1e-7, leaves the least peak
#: some 1e-8 of itself below the exact peak of its answer).
TOLERANCE = 1e-10
#: The most rounds of the exchange.
ROUNDS = 40


@dataclass(frozen=True)
class LeastPeak:
    """The programme's answer: the parameters *x* (all the tuned families' in order), the
    least peak *t* over the tuned segments (per radianⁿ), the rounds of the exchange it took, and
    whether HiGHS solved it (*solved*, else *message* says why)."""

    x: Array
    t: float
    rounds: int
    solved: bool
    message: str = ""


def derivative_pieces(design: Design, indices: Sequence[int],
                      order: int) -> tuple[Array, Array]:
    """s⁽ᵒʳᵈᵉʳ⁾ on each polynomial piece of the segments *indices* of *design*, as ascending
    coefficients in v ∈ [0, length] (u − the piece's first break; per radian of cam
    angleᵒʳᵈᵉʳ), one row each padded with zeros, and each piece's length in u."""
    rows, lengths = [], []
    for index in indices:
        seg = design.program.segments[index]
        pieces = seg.law.pieces()
        assert pieces is not None, "the tuned laws are piecewise polynomial"
        breaks, coefficients = pieces
        for k, c in enumerate(coefficients):
            rows.append(P.polyder(c, order) * (seg.delta / seg.span**order))
            lengths.append(float(breaks[k + 1] - breaks[k]))
    width = max(row.size for row in rows)
    return np.array([np.pad(row, (0, width - row.size)) for row in rows]), np.array(lengths)


def least_peak(coefficients: Array, basis: Array, lengths: Array) -> LeastPeak:
    """The least over x ∈ [0, 1]ⁿ of the largest |g_j(v)| (v ∈ [0, *lengths*[j]], j a
    piece), where piece j's polynomial has the ascending coefficients *coefficients*[j] +
    *basis*[j] @ x (*coefficients* (J, D), *basis* (J, D, n))."""
    from scipy.optimize import linprog

    n = basis.shape[2]
    grids = [np.linspace(0.0, length, max(PIECE_GRID, math.ceil(GRID * length)))
             for length in lengths]
    x = np.full(n, 0.5)
    t = top = math.inf
    message = ""
    for rounds in range(1, ROUNDS + 1):
        rows, offsets = [], []
        for j, v in enumerate(grids):
            powers = np.vander(v, coefficients.shape[1], increasing=True)  # (K, D)
            rows.append(powers @ basis[j])
            offsets.append(powers @ coefficients[j])
        a = np.concatenate(rows)
        b = np.concatenate(offsets)
        ones = np.ones((a.shape[0], 1))
        a_ub = np.block([[a, -ones], [-a, -ones]])
        b_ub = np.concatenate([-b, b])
        cost = np.zeros(n + 1)
        cost[-1] = 1.0
        result = linprog(cost, A_ub=a_ub, b_ub=b_ub,
                         bounds=[(0.0, 1.0)] * n + [(0.0, None)], method="highs",
                         options={"primal_feasibility_tolerance": TOLERANCE,
                                  "dual_feasibility_tolerance": TOLERANCE})
        if result.status != 0:
            return LeastPeak(x, t, rounds, False, str(result.message))
        x, t = np.clip(result.x[:n], 0.0, 1.0), float(result.x[-1])
        message = str(result.message)
        extremes = [_extremes(row, length)
                    for row, length in zip(coefficients + basis @ x, lengths, strict=True)]
        top = max(float(v.max()) for _, v in extremes)
        if top <= t * (1.0 + AGREE):
            return LeastPeak(x, max(t, top), rounds, True, message)
        grown = False
        for j, (v, g) in enumerate(extremes):
            more = np.union1d(grids[j], v[g > t * (1.0 + AGREE)])
            grown |= more.size > grids[j].size
            grids[j] = more
        if not grown:  # the extremes are on the grid: t is the programme's to its tolerance
            return LeastPeak(x, top, rounds, True, message)
    return LeastPeak(x, top, ROUNDS, True, message)


def _extremes(row: Array, length: float) -> tuple[Array, Array]:
    """The places in [0, *length*] where the polynomial of ascending coefficients *row* may
    take its largest |g| (the ends and the real roots of its slope inside), and |g| there."""
    slope = np.trim_zeros(P.polyder(row), "b")
    at = [0.0, length]
    if slope.size > 1:
        at += [float(r.real) for r in P.polyroots(slope)
               if abs(r.imag) < 1e-9 and 0.0 < r.real < length]
    v = np.array(sorted(at))
    return v, np.abs(P.polyval(v, row))
