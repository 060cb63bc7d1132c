"""Tolerance-driven sampling: points on exact curves placed by chord error, not by count.

A chord of length c on a curve of radius ρ strays ``c²/(8ρ)`` from it, so the points a curve needs
per radian of parameter are ``|dC/dθ| / √(8|ρ|·tol)``. The sampler places points by that density
and then measures every chord against the exact curve, halving those that stray further than the
tolerance, until none does.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from camfab.arrays import Array
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
    grid = np.linspace(0.0, span, max(9, math.ceil(4 * span / MAX_STEP) + 1))
    probe = curve_at(grid)
    with np.errstate(divide="ignore", invalid="ignore"):
        density = probe.speed / np.sqrt(8.0 * np.abs(probe.radius) * tolerance)
    density = np.nan_to_num(density, nan=0.0, posinf=0.0)
    density = np.maximum(density, 1.0 / MAX_STEP)
    cumulative = np.concatenate(([0.0], np.cumsum(0.5 * (density[1:] + density[:-1])
                                                  * np.diff(grid))))
    count = max(1, math.ceil(cumulative[-1]))
    t = np.interp(np.linspace(0.0, cumulative[-1], count + 1), cumulative, grid)
    t[0], t[-1] = 0.0, span
    xy = curve_at(t).xy
    for _ in range(_MAX_ROUNDS):
        lo, hi = t[:-1], t[1:]
        inner = (lo[:, None] + (hi - lo)[:, None] * _PROBES).ravel()
        exact = curve_at(inner).xy.reshape(len(lo), len(_PROBES), 2)
        start = np.repeat(xy[:-1], len(_PROBES), axis=0)
        end = np.repeat(xy[1:], len(_PROBES), axis=0)
        dev = chord_deviation(exact.reshape(-1, 2), start, end).reshape(len(lo), -1).max(axis=1)
        bad = dev > tolerance
        if not bad.any():
            break
        mid_t = 0.5 * (lo[bad] + hi[bad])
        mid_xy = exact[bad, 1]
        where = np.flatnonzero(bad) + 1
        t = np.insert(t, where, mid_t)
        xy = np.insert(xy, where, mid_xy, axis=0)
    return t, xy


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
