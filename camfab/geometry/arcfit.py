"""Arc fitting: a closed chain of points on a smooth curve as few circular arcs as the tolerance
allows, for exports that cut arcs (DXF LWPOLYLINE bulges, SVG arcs).

Each arc passes through three of the points (its two ends and the point halfway along) and is
accepted when every point it spans lies within the tolerance of it and it turns at most a quarter
circle; the fitter grows each arc as far as it stays accepted (doubling, then
halving the step). Nearly straight runs become lines.
"""

from __future__ import annotations

import math

import numpy as np

from camfab.arrays import Array
from camfab.geometry.curves import cross
from camfab.geometry.profile import Profile

#: The longest arc written (rad): a quarter circle. Longer arcs are ill-conditioned where a file
#: gives an arc by its ends and radius (SVG): near half a circle a rounded radius moves the centre.
MAX_SWEEP = math.pi / 2

#: An arc flatter than this (its sagitta over its chord) is written as a straight line: at
#: 1e-9 the difference is far below any tolerance camfab accepts.
STRAIGHT = 1e-9


def _arc_error(points: Array, start: int, end: int) -> tuple[float, float]:
    """The largest distance (mm) of points[start..end] from the arc through the ends and the
    middle point, and that arc's bulge (0 for a line)."""
    p0, p1 = points[start], points[end]
    mid = points[(start + end) // 2]
    inner = points[start:end + 1]
    chord = p1 - p0
    length = math.hypot(*chord)
    if length == 0.0:
        return math.inf, 0.0
    turn = float(cross((mid - p0)[None], (p1 - mid)[None])[0])
    sagitta = abs(float(cross(chord[None], (mid - p0)[None])[0])) / length
    if sagitta <= STRAIGHT * length or end - start < 2:
        # a line: distance of the points from the chord
        rel = inner - p0
        off = np.abs(rel[:, 0] * chord[1] - rel[:, 1] * chord[0]) / length
        return float(off.max()), 0.0
    # circle through p0, mid, p1
    a, b = mid - p0, p1 - p0
    d = 2.0 * (a[0] * b[1] - a[1] * b[0])
    ux = (b[1] * (a @ a) - a[1] * (b @ b)) / d
    uy = (a[0] * (b @ b) - b[0] * (a @ a)) / d
    centre = p0 + np.array([ux, uy])
    radius = math.hypot(ux, uy)
    error = float(np.max(np.abs(np.hypot(*(inner - centre).T) - radius)))
    # the points must also run along the arc the bulge describes (not around the far side)
    sweep = math.atan2(float(cross((p0 - centre)[None], (p1 - centre)[None])[0]),
                       float((p0 - centre) @ (p1 - centre)))
    if turn * sweep < 0 or abs(sweep) > MAX_SWEEP:  # too long an arc (or the long way round)
        return math.inf, 0.0
    return error, math.tan(sweep / 4.0)


def fit_arcs(points: Array, tolerance: float) -> Profile:
    """A closed contour of lines and arcs within *tolerance* (mm) of the closed chain *points*.

    Parameters
    ----------
    points
        (N, 2) points in order along a smooth closed curve, without a repeated closing point.
    tolerance
        Largest distance allowed between a point and the arc that replaces it.
    """
    chain = np.vstack((points, points[:1]))
    last = len(chain) - 1
    vertices, bulges = [], []
    start = 0
    while start < last:
        step, good, good_bulge = 2, start + 1, 0.0
        # grow by doubling while the arc holds, then bisect between the last good and first bad
        bad = None
        while True:
            end = min(start + step, last)
            error, bulge = _arc_error(chain, start, end)
            if error <= tolerance:
                good, good_bulge = end, bulge
                if end == last:
                    break
                step *= 2
            else:
                bad = end
                break
        if bad is not None:
            lo, hi = good, bad
            while hi - lo > 1:
                middle = (lo + hi) // 2
                error, bulge = _arc_error(chain, start, middle)
                if error <= tolerance:
                    lo, good, good_bulge = middle, middle, bulge
                else:
                    hi = middle
        if good == start + 1:
            good_bulge = 0.0
        vertices.append(chain[start])
        bulges.append(good_bulge)
        start = good
    return Profile(np.array(vertices), np.array(bulges))
