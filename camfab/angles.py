"""Angles along the cycle: in degrees as reports give them, the ranges where a condition
holds, and the extremes of a curve and where they fall.

A range is ``(start_deg, end_deg)`` in the direction of rotation; a range that runs through
θ = 0 has ``start_deg > end_deg`` (``(350.0, 10.0)``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camfab.arrays import Array, Mask, runs

Range = tuple[float, float]


def degrees(angle: float) -> float:
    """*angle* (rad) in degrees, rounded to 1e-9° so 120° does not print as 119.99999999999999."""
    return round(math.degrees(angle), 9) + 0.0


@dataclass(frozen=True)
class Extreme:
    """A largest or smallest value (in the report unit) and where it occurs (deg); None when the
    curve never has that kind of value (no concave part, say)."""

    value: float | None
    at_deg: float | None


def extreme(theta: Array, values: Array, mask: Mask | None = None, *,
            largest: bool) -> Extreme:
    """The largest (or smallest) finite value of *values* over *theta* (rad) where *mask*
    holds, and where it falls."""
    picked = np.isfinite(values) if mask is None else (mask & np.isfinite(values))
    if not picked.any():
        return Extreme(None, None)
    index = np.flatnonzero(picked)
    best = index[np.argmax(values[index]) if largest else np.argmin(values[index])]
    return Extreme(float(values[best]), degrees(float(theta[best])))


def ranges_deg(theta: Array, mask: Mask) -> tuple[Range, ...]:
    """The runs of *mask* along *theta* (rad, non-decreasing over one turn) as degree ranges; a run
    at the end of the grid and one at its start are one range through 0°."""
    mask = np.asarray(mask, dtype=bool)
    if not mask.any():
        return ()
    out = [(degrees(float(theta[a])), degrees(float(theta[b - 1]))) for a, b in runs(mask)]
    if mask[0] and mask[-1] and len(out) > 1:  # the grid covers the turn: a run through 0°
        out[-1] = (out[-1][0], 360.0)
    return merge(out)


def merge(ranges: list[Range]) -> tuple[Range, ...]:
    """Union of ranges (a range through 0° given as start > end), sorted, touching ones joined
    and one running through 360° joined with one starting at 0°."""
    flat: list[Range] = []
    for start, end in ranges:
        if start > end:
            flat += [(start, 360.0), (0.0, end)]
        else:
            flat.append((start, end))
    flat.sort()
    out: list[list[float]] = []
    for start, end in flat:
        if out and start <= out[-1][1] + 1e-9:
            out[-1][1] = max(out[-1][1], end)
        else:
            out.append([start, end])
    if len(out) > 1 and out[0][0] <= 1e-9 and out[-1][1] >= 360.0 - 1e-9:
        first = out.pop(0)
        out[-1][1] = first[1]
    return tuple((a, b) for a, b in out)
