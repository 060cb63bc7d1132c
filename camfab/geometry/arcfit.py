"""Arc fitting: a closed chain of points on a smooth curve as few circular arcs as the tolerance
allows, for exports that cut arcs (DXF LWPOLYLINE bulges, SVG arcs).

Each arc passes through three of the points (its two ends and the point halfway along) and is
accepted when every point it spans (and, when asked, every chord between them) lies within the
tolerance of it and it turns at most a quarter circle; the fitter grows each arc as far as it
stays accepted (doubling, then halving the step). Nearly straight runs, and arcs of a radius over
:data:`MAX_RADIUS_RATIO` times the curve's size, become lines.
"""

from __future__ import annotations

import math

import numpy as np

from camfab.arrays import Array
from camfab.curves.profile import Profile

#: The longest arc written (rad): a quarter circle. Longer arcs are ill-conditioned where a file
#: gives an arc by its ends and radius (SVG): near half a circle a rounded radius moves the centre.
MAX_SWEEP = math.pi / 2

#: An arc flatter than this (its sagitta over its chord) is written as a straight line: at
#: 1e-9 the difference is far below any tolerance camfab accepts.
STRAIGHT = 1e-9

#: The largest arc radius written, as a multiple of the size of the curve fitted (the largest
#: side of its points' bounding box); a flatter arc is a line if the line holds the tolerance,
#: else shorter lines and arcs. A DXF gives an arc by its centre, radius and angles, and a
#: reader recomputes its ends from them: one that reads them in single precision (dime, and
#: the programs built on it) is off by some 4e-7 of the radius, which for the arcs of 10⁴ to
#: 10⁵ times the part's size a nearly straight run gave placed them 0.1 to 0.2 mm off. At 100
#: times the size it is 4e-5 of the size, under 0.01 mm on a 200 mm part.
MAX_RADIUS_RATIO = 100.0


def _inside_between(x: Array, y: Array, radius: float) -> float:
    """How far (mm) the chords of a chain of points (*x*, *y*: coordinates from a circle's
    centre, mm, in order) come inside the circle of *radius* about it: radius less each chord's
    nearest approach to the centre, at most.

    The points alone do not bound an arc's distance from the curve they sample: an arc that
    bends more than the curve (one fitted across a corner of it) passes near every point and
    bows off the chords between them. The farthest a chord strays outside the circle is at one
    of its ends (distance from the centre is convex along it), so the points and this bound the
    arc's distance from the chain."""
    ax, ay, dx, dy = x[:-1], y[:-1], np.diff(x), np.diff(y)
    length2 = dx * dx + dy * dy
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.clip(-(ax * dx + ay * dy) / length2, 0.0, 1.0)
    t[~(length2 > 0.0)] = 0.0
    return radius - float(np.min(np.hypot(ax + t * dx, ay + t * dy)))


def _arc_error(points: Array, start: int, end: int, max_radius: float,
               chords: bool = False) -> tuple[float, float]:
    """The largest distance (mm) of points[start..end] from the arc through the ends and the
    middle point (with *chords*, of the chords between them too), and that arc's bulge (0 for a
    line, and for an arc of a radius over *max_radius* (mm), measured as the line: the chords
    between points within a line's tolerance are within it too)."""
    x0, y0 = points[start]
    x1, y1 = points[end]
    xm, ym = points[(start + end) // 2]
    inner = points[start:end + 1]
    cx, cy = x1 - x0, y1 - y0
    length = math.hypot(cx, cy)
    if length == 0.0:
        return math.inf, 0.0
    ax, ay = xm - x0, ym - y0
    sagitta = abs(cx * ay - cy * ax) / length
    if sagitta <= STRAIGHT * length or end - start < 2:
        # a line: distance of the points from the chord
        off = np.abs((inner[:, 0] - x0) * cy - (inner[:, 1] - y0) * cx) / length
        return float(off.max()), 0.0
    turn = ax * (y1 - ym) - ay * (x1 - xm)
    # circle through p0, mid, p1
    d = 2.0 * (ax * cy - ay * cx)
    a2, b2 = ax * ax + ay * ay, cx * cx + cy * cy
    ux = (cy * a2 - ay * b2) / d
    uy = (ax * b2 - cx * a2) / d
    radius = math.hypot(ux, uy)
    if radius > max_radius:  # as a line (accepted only where the line holds the tolerance)
        off = np.abs((inner[:, 0] - x0) * cy - (inner[:, 1] - y0) * cx) / length
        return float(off.max()), 0.0
    # the points must also run along the arc the bulge describes (not around the far side)
    sx, sy, ex, ey = -ux, -uy, x1 - x0 - ux, y1 - y0 - uy
    sweep = math.atan2(sx * ey - sy * ex, sx * ex + sy * ey)
    if turn * sweep < 0 or abs(sweep) > MAX_SWEEP:  # too long an arc (or the long way round)
        return math.inf, 0.0
    x, y = inner[:, 0] - (x0 + ux), inner[:, 1] - (y0 + uy)
    error = float(np.max(np.abs(np.hypot(x, y) - radius)))
    if chords:
        error = max(error, _inside_between(x, y, radius))
    return error, math.tan(sweep / 4.0)


def fit_arcs(points: Array, tolerance: float, closed: bool = True,
             chords: bool = False) -> Profile:
    """A contour of lines and arcs within *tolerance* (mm) of the chain *points*.

    Parameters
    ----------
    points
        (N, 2) points in order along a smooth curve; a closed chain without a repeated closing
        point.
    tolerance
        Largest distance allowed between a point and the arc that replaces it.
    closed
        False for an open chain: the profile then ends with the chain's last point, and its
        closing edge (back to the first) is not part of the curve.
    chords
        Hold the chords between the points within *tolerance* too, not the points alone: for
        a chain sampled from an exact curve with its chords within a known tolerance of it,
        whose arcs must then lie within the sum of both of the curve, corners and jumps of
        curvature included (:func:`_inside_between`).
    """
    chain = np.vstack((points, points[:1])) if closed else points
    max_radius = MAX_RADIUS_RATIO * float(np.max(np.ptp(chain, axis=0)))
    last = len(chain) - 1
    vertices, bulges = [], []
    start = 0
    while start < last:
        step, good, good_bulge = 2, start + 1, 0.0
        # grow by doubling while the arc holds, then bisect between the last good and first bad
        bad = None
        while True:
            end = min(start + step, last)
            error, bulge = _arc_error(chain, start, end, max_radius, chords)
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
                error, bulge = _arc_error(chain, start, middle, max_radius, chords)
                if error <= tolerance:
                    lo, good, good_bulge = middle, middle, bulge
                else:
                    hi = middle
        if good == start + 1:
            good_bulge = 0.0
        vertices.append(chain[start])
        bulges.append(good_bulge)
        start = good
    if not closed:
        vertices.append(chain[-1])
        bulges.append(0.0)
    return Profile(np.array(vertices), np.array(bulges))
