"""Tolerance-driven sampling: points on exact curves placed by chord error, not by count.

A chord of length c on a curve of radius ρ strays ``c²/(8ρ)`` from it, so the points a curve needs
per radian of parameter are ``|dC/dθ| / √(8|ρ|·tol)``. The sampler places points by that density
and then measures every chord against the exact curve, halving those that stray further than the
tolerance, until none does. Many curves (the segments of a motion program) are sampled together:
each round measures the chords of every curve halved in the round before, in one evaluation.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from camfab.arrays import Array, Index, spaced
from camfab.curves.plane import CurvePoints

#: The share of ``manufacturing.tolerance`` spent on sampling the exact curves. The rest is left
#: for the exporters (arc fitting, rounding), and it keeps the lift error of a follower on the
#: sampled profile, about (deviation)/cos φ, inside the tolerance for pressure angles up to 60°.
SAMPLING_SHARE = 0.5

#: The largest step of the curve parameter (cam angle) between two samples. Straight and nearly
#: straight stretches need no points for accuracy; this keeps them resolved for the simulation
#: and the drawings.
MAX_STEP = math.radians(2.0)

#: Chords are measured at these fractions of their parameter interval.
_PROBES = np.array([0.25, 0.5, 0.75])

#: Refinement rounds; each halves the offending intervals, so 40 rounds reach 1e-12 of a step.
_MAX_ROUNDS = 40


def chord_deviation(points: Array, start: Array, end: Array) -> Array:
    """Distance (mm) of each of *points* from the segment *start*–*end* (all (N, 2))."""
    d = end - start
    length2 = np.einsum("ij,ij->i", d, d)
    rel = points - start
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(length2 > 0.0, np.einsum("ij,ij->i", rel, d) / length2, 0.0)
    foot = start + np.clip(t, 0.0, 1.0)[:, None] * d
    return np.hypot(*(points - foot).T)


def sample_curve(curve_at: Callable[[Array], CurvePoints], span: float,
                 tolerance: float) -> tuple[Array, Array]:
    """Sample a curve C(t), 0 ≤ t ≤ *span*, so every chord is within *tolerance* (mm) of it.

    Parameters
    ----------
    curve_at
        The exact curve at parameters t (rad); must accept the interval's ends.
    span
        Parameter interval length (rad).
    tolerance
        Largest allowed distance between a chord and the curve (mm).

    Returns
    -------
    t, xy
        The parameters (increasing, from 0 to *span*) and points of the samples.
    """
    _, t, xy = sample_curves(lambda _, t: curve_at(t), np.array([float(span)]),
                             np.array([float(tolerance)]))
    return t, xy


def sample_curves(curve_at: Callable[[Index, Array], CurvePoints], spans: Array,
                  tolerances: Array) -> tuple[Index, Array, Array]:
    """Sample many curves at once, each as :func:`sample_curve` samples it alone (the same
    points): curve i over 0 ≤ t ≤ ``spans[i]`` within ``tolerances[i]``.

    Parameters
    ----------
    curve_at
        The exact curves: ``curve_at(i, t)`` is curve ``i[k]`` at parameter ``t[k]`` (rad) for
        every k; each value must depend on its own (i, t) alone.
    spans
        (C,) parameter interval lengths (rad), positive.
    tolerances
        (C,) largest allowed distance between a chord and its curve (mm).

    Returns
    -------
    index, t, xy
        The curve of each sample, its parameter and its point (mm), curve by curve with t
        increasing from 0 to the curve's span.
    """
    spans = np.asarray(spans, dtype=np.float64)
    tolerances = np.asarray(tolerances, dtype=np.float64)
    index, t = _density_spread(curve_at, spans, tolerances)
    return _refine(curve_at, index, t, curve_at(index, t).xy, tolerances)


def _density_spread(curve_at: Callable[[Index, Array], CurvePoints], spans: Array,
                    tolerances: Array) -> tuple[Index, Array]:
    """The first samples of each curve: parameters (rad) spread by the chord density the
    curve's speed and radius ask for on a grid at most a quarter of :data:`MAX_STEP` apart."""
    grid_count = np.maximum(9, np.ceil(4 * spans / MAX_STEP).astype(np.intp) + 1)
    index, grid = spaced(spans, grid_count)
    probe = curve_at(index, grid)
    with np.errstate(divide="ignore", invalid="ignore"):
        density = probe.speed / np.sqrt(8.0 * np.abs(probe.radius) * tolerances[index])
    density = np.nan_to_num(density, nan=0.0, posinf=0.0)
    density = np.maximum(density, 1.0 / MAX_STEP)
    inner = index[1:] == index[:-1]
    area = (0.5 * (density[1:] + density[:-1]) * np.diff(grid))[inner]
    # cumulative areas of each curve as numpy's cumsum adds them: one column per curve
    table = np.zeros((int(grid_count.max()), len(spans)))
    row = np.arange(index.size) - (np.cumsum(grid_count) - grid_count)[index]
    table[row[1:][inner], index[1:][inner]] = area
    cumulative = np.cumsum(table, axis=0)
    total = cumulative[grid_count - 1, np.arange(len(spans))]
    count = np.maximum(1, np.ceil(total).astype(np.intp))
    owner, target = spaced(total, count + 1)
    t = _interp_columns(target, owner, cumulative, grid, grid_count)
    first = np.cumsum(count + 1) - (count + 1)
    t[first] = 0.0
    t[first + count] = spans
    return owner, t


def _interp_columns(x: Array, owner: Index, cumulative: Array, grid: Array,
                    grid_count: Index) -> Array:
    """``np.interp(x, xp, fp)`` for each x against its own curve's knots, with numpy's
    arithmetic: xp the first ``grid_count`` rows of column *owner* of *cumulative* (increasing,
    from 0), fp that curve's *grid* parameters (rad)."""
    size = grid_count[owner]
    below = _count_at_most(x, cumulative, owner, size)
    j = np.clip(below - 1, 0, size - 2)
    first = (np.cumsum(grid_count) - grid_count)[owner]
    x0, x1 = cumulative[j, owner], cumulative[j + 1, owner]
    y0, y1 = grid[first + j], grid[first + j + 1]
    out = (y1 - y0) / (x1 - x0) * (x - x0) + y0
    out = np.where(x0 == x, y0, out)
    return np.where(below == size, grid[first + size - 1], out)


def _count_at_most(x: Array, knots: Array, owner: Index, size: Index) -> Index:
    """How many of the first *size* knots of column *owner* (increasing) are at most *x*: a
    binary search of every x at once."""
    lo, hi = np.zeros(x.size, dtype=np.intp), size.copy()
    while True:
        active = lo < hi
        if not active.any():
            return lo
        mid = (lo + hi) // 2
        step = active & (knots[np.where(active, mid, 0), owner] <= x)
        lo = np.where(step, mid + 1, lo)
        hi = np.where(active & ~step, mid, hi)


def _refine(curve_at: Callable[[Index, Array], CurvePoints], index: Index, t: Array, xy: Array,
            tolerances: Array) -> tuple[Index, Array, Array]:
    """Halve every chord that strays further than its curve's tolerance (mm) from the curve,
    round after round, measuring only the chords made in the previous round."""
    fresh = np.append(index[1:] == index[:-1], False)  # a chord starts here, not yet measured
    for _ in range(_MAX_ROUNDS):
        at = np.flatnonzero(fresh)
        if not at.size:
            break
        lo, hi = t[at], t[at + 1]
        inner = probes_within(t, at)
        exact = curve_at(np.repeat(index[at], len(_PROBES)), inner).xy
        exact = exact.reshape(len(lo), len(_PROBES), 2)
        start = np.repeat(xy[at], len(_PROBES), axis=0)
        end = np.repeat(xy[at + 1], len(_PROBES), axis=0)
        dev = chord_deviation(exact.reshape(-1, 2), start, end).reshape(len(lo), -1).max(axis=1)
        bad = dev > tolerances[index[at]]
        fresh[at[~bad]] = False
        where = at[bad] + 1
        t = np.insert(t, where, 0.5 * (lo[bad] + hi[bad]))
        xy = np.insert(xy, where, exact[bad, 1], axis=0)
        index = np.insert(index, where, index[at[bad]])
        fresh = np.insert(fresh, where, True)
    return index, t, xy


def probes_within(t: Array, at: Index) -> Array:
    """The parameters at which the interval from ``t[i]`` to ``t[i + 1]`` of each i in *at* is
    measured against its exact curve: a quarter, half and three quarters of the way, interval
    by interval."""
    lo, hi = t[at], t[at + 1]
    return (lo[:, None] + (hi - lo)[:, None] * _PROBES).ravel()


def arc_points(centre: Array, start: Array, sweep: float, tolerance: float) -> Array:
    """Points on the circular arc about *centre* from the point *start* turning *sweep* (rad,
    counter-clockwise positive), with chords within *tolerance* (mm); both ends included."""
    radius = float(np.hypot(*(start - centre)))
    if radius == 0.0 or sweep == 0.0:
        return start[None, :].copy()
    step = 2.0 * math.acos(max(-1.0, 1.0 - tolerance / radius))
    count = max(1, math.ceil(abs(sweep) / step))
    angles = math.atan2(start[1] - centre[1], start[0] - centre[0]) + np.linspace(0.0, sweep,
                                                                                   count + 1)
    return centre + radius * np.stack((np.cos(angles), np.sin(angles)), axis=-1)


def spread(segment: Index, theta: Array, density: Array, count: int) -> Array:
    """Cam angles (rad) spread evenly in the integral of *density* (samples per radian, given
    at the angles *theta* of a program's segment grid, their *segment* index, *count*
    segments), segment by segment: at least two in each, its start included and its end left
    to the next."""
    out = []
    for index in range(count):
        mine = segment == index
        t, rate = theta[mine], density[mine]
        cumulative = np.concatenate(([0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1])
                                                      * np.diff(t))))
        samples = max(2, math.ceil(cumulative[-1]))
        out.append(np.interp(np.linspace(0.0, cumulative[-1], samples + 1), cumulative,
                             t)[:-1])
    return np.concatenate(out)


def spread_count(segment: Index, theta: Array, density: Array, count: int) -> int:
    """How many cam angles :func:`spread` places for the same arguments, without placing them
    (a count, exact but for the last bit of each segment's sum): what a groove's stations
    will cost, known before they take any memory."""
    inner = segment[1:] == segment[:-1]
    area = (0.5 * (density[1:] + density[:-1]) * np.diff(theta))[inner]
    total = np.bincount(segment[1:][inner], weights=area, minlength=count)
    with np.errstate(invalid="ignore", over="ignore"):
        per_segment = np.maximum(2.0, np.ceil(np.nan_to_num(total, nan=np.inf)))
    return int(min(float(per_segment.sum()), 1e18))


#: Points across the floor and across the top of a groove in the grids of its exact surfaces,
#: through which a STEP's surfaces are fitted (count).
SURFACE_ACROSS = 5
#: The most cam angles (spread over the turn) at which the probes of a groove's exact surfaces
#: measure the fitted ones (count).
PROBE_STATIONS = 60


def ahead_and_middle(stations: Array) -> tuple[Array, Array]:
    """For each of *stations* (cam angles, rad, one turn, ascending), the next one (after the
    last, the first a turn on) and the angle halfway to it."""
    ahead = np.append(stations[1:], stations[0] + 2 * math.pi)
    return ahead, 0.5 * (stations + ahead)


def probe_angles(stations: Array) -> Array:
    """Cam angles (rad) halfway between consecutive *stations*, at most about
    :data:`PROBE_STATIONS` of them spread over the turn: where a surface fitted through the
    stations strays furthest, to measure it by."""
    return ahead_and_middle(stations)[1][::max(1, math.ceil(stations.size / PROBE_STATIONS))]

