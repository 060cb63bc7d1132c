"""The exact offset of a closed contour of lines and arcs (mm): the path a cutter's centre
follows round it, as a control's cutter compensation makes it.

Each edge moves along its normal: a line shifts, an arc keeps its centre and sweep and changes
radius. Where two moved edges part (a corner the cutter goes round) a round join of the offset's
radius about the corner fills the gap; where they overlap (a corner the cutter goes into) both
are trimmed to where they meet. This is what LinuxCNC's cutter compensation does, so the path
a program carries and the path a control makes of the contour are the same curves. An edge the
offset consumes (an arc tighter than the cutter, a corner it cannot reach into) stops the offset
and says where.
"""

from __future__ import annotations

import math

import numpy as np

from camfab.arrays import Array, Index
from camfab.curves.plane import cross, dot
from camfab.curves.profile import Profile

#: Ends of two moved edges closer than this (mm) meet halfway, without a join: a join arc so
#: short would be written as a move whose direction the rounding of its ends decides (a control
#: then sees corners that are not there), and meeting halfway moves each end along its edge,
#: off the exact offset by under (gap/2)²/radius.
JOIN_GAP = 2e-3
#: An arc moved nearer its centre than this (mm) is gone.
LEAST_RADIUS = 1e-9


class OffsetError(ValueError):
    """An offset that consumes an edge: *where* (mm) is the edge's start on the contour."""

    def __init__(self, message: str, where: Array) -> None:
        super().__init__(message)
        self.where = where


def offset(profile: Profile, distance: float) -> tuple[Profile, Index]:
    """*profile* moved *distance* (mm) outward (negative: inward), counter-clockwise, with round
    joins where moved edges part and trimmed where they overlap; and, for each edge of
    ``profile.ccw()``, the index of the edge it became.

    Raises
    ------
    OffsetError
        An edge vanishes: an arc shrinks through its centre, or trimming consumes an edge.
    """
    prof = profile.ccw()
    v = prof.vertices
    count = len(v)
    following = np.roll(v, -1, axis=0)
    start_angle, end_angle = prof.normal_angles()
    n_start = np.stack((np.cos(start_angle), np.sin(start_angle)), axis=-1)
    n_end = np.stack((np.cos(end_angle), np.sin(end_angle)), axis=-1)
    a = v + distance * n_start
    e = following + distance * n_end

    arcs = prof.arcs()
    is_arc = np.zeros(count, dtype=bool)
    is_arc[arcs.index] = True
    centre = np.full((count, 2), np.nan)
    centre[arcs.index] = arcs.centre
    radius = np.full(count, np.inf)
    radius[arcs.index] = arcs.radius + np.sign(arcs.sweep) * distance
    sweep = np.zeros(count)
    sweep[arcs.index] = arcs.sweep
    gone = np.flatnonzero(radius <= LEAST_RADIUS)
    if gone.size:
        raise OffsetError(f"an arc of the contour is tighter than {abs(distance):g} mm",
                          v[gone])

    # the turn at vertex i, from edge i − 1's end to edge i's start (counter-clockwise positive)
    turn = np.mod(start_angle - np.roll(end_angle, 1) + math.pi, 2.0 * math.pi) - math.pi
    before = np.roll(np.arange(count), 1)
    parted = np.hypot(*(a - e[before]).T) > JOIN_GAP
    gap = parted & (turn * distance > 0.0)
    overlap = parted & (turn * distance < 0.0)
    meet = (a + e[before]) / 2.0
    meet[overlap] = _meeting(a, e, centre, radius, is_arc, before[overlap],
                             np.flatnonzero(overlap), meet[overlap], v)
    still = ~gap
    a = np.where(still[:, None], meet, a)
    e_new = e.copy()
    e_new[before[still]] = meet[still]
    _check_kept(a, e, e_new, v + distance * n_start, centre, is_arc, sweep, v)
    new_sweep = _trimmed_sweep(a, e_new, centre, sweep, v + distance * n_start, e)

    # the joins then the edges, in order round the contour
    joins = np.flatnonzero(gap)
    order = np.concatenate((np.arange(count) * 2 + 1, joins * 2))
    starts = np.concatenate((a, e[before[joins]]))
    bulges = np.concatenate((np.where(is_arc, np.tan(new_sweep / 4.0), 0.0),
                             np.tan(turn[joins] / 4.0)))
    rank = np.argsort(order, kind="stable")
    where_edge = np.empty(count, dtype=np.intp)
    where_edge[:] = np.argsort(rank)[:count]
    return Profile(starts[rank], bulges[rank]), where_edge


def _meeting(a: Array, e: Array, centre: Array, radius: Array, is_arc: Array, first: Index,
             second: Index, near: Array, v: Array) -> Array:
    """Where the moved edges *first* (its line or circle) and *second* meet, the crossing
    nearest *near* (mm) of the two a line and a circle or two circles have."""
    out = np.empty((len(first), 2))
    both_lines = ~is_arc[first] & ~is_arc[second]
    both_arcs = is_arc[first] & is_arc[second]
    mixed = ~both_lines & ~both_arcs
    if both_lines.any():
        f, s = first[both_lines], second[both_lines]
        df, ds = e[f] - a[f], e[s] - a[s]
        den = cross(df, ds)
        t = cross(a[s] - a[f], ds) / np.where(den == 0.0, 1.0, den)
        out[both_lines] = np.where((den == 0.0)[:, None], near[both_lines],
                                   a[f] + t[:, None] * df)
    if mixed.any():
        f, s = first[mixed], second[mixed]
        line = np.where(is_arc[f], s, f)
        circle = np.where(is_arc[f], f, s)
        out[mixed] = _line_circle(a[line], e[line] - a[line], centre[circle], radius[circle],
                                  near[mixed], v[second[mixed]])
    if both_arcs.any():
        f, s = first[both_arcs], second[both_arcs]
        out[both_arcs] = _circle_circle(centre[f], radius[f], centre[s], radius[s],
                                        near[both_arcs], v[second[both_arcs]])
    return out


def _nearest(roots: Array, near: Array) -> Array:
    """Of (K, 2, 2) candidate points, the one nearest *near* (K, 2)."""
    pick = np.argmin(np.hypot(*(roots - near[:, None, :]).transpose(2, 0, 1)), axis=1)
    return roots[np.arange(len(roots)), pick]


def _line_circle(point: Array, direction: Array, centre: Array, radius: Array, near: Array,
                 v: Array) -> Array:
    u = direction / np.hypot(*direction.T)[:, None]
    rel = point - centre
    b = dot(u, rel)
    disc = b * b - (dot(rel, rel) - radius * radius)
    if np.any(disc < 0.0):
        raise OffsetError("moved edges do not meet", v[disc < 0.0])
    root = np.sqrt(disc)
    t = np.stack((-b - root, -b + root), axis=-1)
    return _nearest(point[:, None, :] + t[..., None] * u[:, None, :], near)


def _circle_circle(c1: Array, r1: Array, c2: Array, r2: Array, near: Array, v: Array) -> Array:
    d = c2 - c1
    dist = np.hypot(*d.T)
    along = (dist**2 + r1**2 - r2**2) / (2.0 * np.where(dist > 0.0, dist, 1.0))
    h2 = r1**2 - along**2
    if np.any((h2 < 0.0) | (dist == 0.0)):
        raise OffsetError("moved edges do not meet", v[(h2 < 0.0) | (dist == 0.0)])
    u = d / dist[:, None]
    mid = c1 + along[:, None] * u
    side = np.sqrt(h2)[:, None] * np.stack((-u[:, 1], u[:, 0]), axis=-1)
    return _nearest(np.stack((mid - side, mid + side), axis=1), near)


def _check_kept(a: Array, e_old: Array, e: Array, a_old: Array, centre: Array,
                is_arc: Array, sweep: Array, v: Array) -> None:
    """Every trimmed edge still runs forward: a line from *a* toward *e* as before, an arc
    through part of its sweep."""
    lines = ~is_arc
    shrunk = np.zeros(len(a), dtype=bool)
    shrunk[lines] = dot(e[lines] - a[lines], e_old[lines] - a_old[lines]) <= 0.0
    kept = _trimmed_sweep(a, e, centre, sweep, a_old, e_old)
    shrunk[is_arc] = kept[is_arc] * sweep[is_arc] <= 0.0
    if shrunk.any():
        raise OffsetError("the moved edges either side consume an edge", v[shrunk])


def _trimmed_sweep(a: Array, e: Array, centre: Array, sweep: Array, a_old: Array,
                   e_old: Array) -> Array:
    """The sweep (rad) of each arc whose ends moved from *a_old*, *e_old* to *a*, *e* along its
    circle (0 for lines)."""
    def angle(p: Array) -> Array:
        return np.arctan2(p[:, 1] - centre[:, 1], p[:, 0] - centre[:, 0])

    def wrapped(x: Array) -> Array:
        return np.mod(x + math.pi, 2.0 * math.pi) - math.pi

    with np.errstate(invalid="ignore"):
        moved_start = wrapped(angle(a) - angle(a_old))
        moved_end = wrapped(angle(e_old) - angle(e))
    out = sweep - moved_start - moved_end
    return np.where(sweep != 0.0, out, 0.0)
