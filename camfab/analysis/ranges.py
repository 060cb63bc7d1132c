"""Angle ranges in degrees: where along the cycle a condition holds.

A range is ``(start_deg, end_deg)`` in the direction of rotation; a range that runs through
θ = 0 has ``start_deg > end_deg`` (``(350.0, 10.0)``).
"""

from __future__ import annotations

import numpy as np

from camfab.analysis.kinematics import degrees
from camfab.arrays import Array, Mask, runs

Range = tuple[float, float]


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
