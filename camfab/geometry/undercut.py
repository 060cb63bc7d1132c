"""Undercut: where the follower's envelope folds over itself, and the cam that is really cut.

On a convex stretch whose pitch radius of curvature is smaller than the roller radius, the offset
curve runs backwards and crosses itself (a swallowtail); a flat face does the same where
Rb + s + s″ < 0. GEOS buffers remove such loops silently, so camfab detects them from curvature
and from the raw envelope (is it a simple ring?), and then trims them: the raw envelope is noded
into faces and the faces the follower never enters are kept. Their boundary is the cam a cutter
following the design would leave, and the follower simulation on it measures the motion error.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import shapely

from camfab.arrays import Array, Index, Mask

#: A predicate over (K, 2) points: True where the follower never enters.
KeepTest = Callable[[Array], Mask]

#: Most (point, face line) pairs the flat-face test holds at once: 16 M, 128 MB of float64.
FACE_TEST_ELEMENTS = 1 << 24


def is_simple(xy: Array) -> bool:
    """True when the closed polyline through *xy* does not touch or cross itself."""
    return bool(shapely.LinearRing(xy).is_simple)


def trim_loops(xy: Array, keep: KeepTest) -> Array:
    """The boundary of the faces of the closed polyline *xy* that *keep* accepts.

    The polyline is noded at its self-intersections and split into faces; a face is kept when a
    point inside it passes *keep*. Returns the exterior of the kept region (the largest piece if
    it falls apart), as (M, 2) points without a repeated closing point.
    """
    ring = shapely.LineString(np.vstack((xy, xy[:1])))
    faces = shapely.get_parts(shapely.polygonize(shapely.get_parts(shapely.node(ring))))
    faces = faces[shapely.area(faces) > 0.0]
    if faces.size == 0:
        return xy
    inside = shapely.get_coordinates(shapely.point_on_surface(faces))
    kept = faces[keep(inside)]
    if kept.size == 0:
        return xy
    region = shapely.union_all(kept)
    parts = shapely.get_parts(region)
    largest = parts[int(np.argmax(shapely.area(parts)))]
    return np.asarray(largest.exterior.coords)[:-1]


def outside_circle_sweep(pitch_xy: Array, radius: float, slack: float) -> KeepTest:
    """Points inside the closed pitch polyline and at least *radius* − *slack* from it: where a
    circle of *radius* whose centre runs along the pitch curve never reaches (roller, mushroom,
    and with radius 0 a knife)."""
    polygon = shapely.Polygon(pitch_xy)
    if not polygon.is_valid:
        polygon = shapely.make_valid(polygon)
    boundary = shapely.LinearRing(pitch_xy)
    # indexed tests: plain ones take faces × pitch points time (minutes for a cam of a
    # thousand segments whose every bump is undercut)
    shapely.prepare(polygon)
    shapely.prepare(boundary)

    def keep(points: Array) -> Mask:
        pts = shapely.points(points)
        inside = shapely.contains(polygon, pts)
        return inside & ~shapely.dwithin(boundary, pts, radius - slack)

    return keep


def below_face_lines(normals: Array, heights: Array, slack: float) -> KeepTest:
    """Points on the cam side of every face line ``x·n ≤ h`` (flat faces), *normals* (K, 2,
    unit) and *heights* (K,) in the cam frame.

    A point at distance r from the centre is above a line only if the line's normal lies within
    arccos(h_min/r) of the point's direction (h_min the least height: x·n = r·cos of the angle
    between them), and is above some line if r·cos(δ/2) exceeds every height (δ the widest gap
    between the normals' directions: some normal lies within δ/2 of the point's). So a point
    that far out is above one, one nearer the centre than every line below them all, and each
    block of the others, taken in the order of their directions, is tested against the lines
    whose normals lie within that of the block's directions: a cam whose every bump folds has
    hundreds of thousands of faces to test and thousands of face lines, a few near each face."""
    limit = heights + slack
    angle = np.arctan2(normals[:, 1], normals[:, 0])
    order = np.argsort(angle, kind="stable")
    angle, normals, limit = angle[order], normals[order], limit[order]
    least = float(limit.min(initial=np.inf))
    outer = _outer_radius(angle, float(limit.max(initial=-np.inf)))
    # a block of points at a time: their (point, face line) pairs stay within the most held
    block = max(1, FACE_TEST_ELEMENTS // max(1, normals.shape[0]))

    def keep(points: Array) -> Mask:
        radius = np.hypot(points[:, 0], points[:, 1])
        # nearer the centre than every line (below them all), or beyond some line, with room
        # for the rounding of x·n
        out = radius < least * (1.0 - 1e-12)
        between = np.flatnonzero(~out & ~(radius > outer * (1.0 + 1e-12)))
        if not between.size:
            return out
        with np.errstate(divide="ignore", invalid="ignore"):
            reach = np.arccos(np.clip(least / radius[between], -1.0, 1.0)) + FACE_ANGLE_SLACK
        direction = np.arctan2(points[between, 1], points[between, 0])
        turn = np.argsort(direction, kind="stable")
        between, direction, reach = between[turn], direction[turn], reach[turn]
        for i in range(0, between.size, block):
            mine = slice(i, i + block)
            near = _lines_within(angle, float(np.min(direction[mine] - reach[mine])),
                                 float(np.max(direction[mine] + reach[mine])))
            out[between[mine]] = np.all(points[between[mine]] @ normals[near].T <= limit[near],
                                        axis=1)
        return out

    return keep


def _outer_radius(angle: Array, highest: float) -> float:
    """The distance (mm) from the centre beyond which a point is above one of the lines whose
    normals point at the sorted *angle* (rad) and whose heights are at most *highest* (mm):
    *highest* over the cosine of half the widest gap between the angles (round the turn), or
    inf when the gaps leave a half-plane uncovered."""
    if angle.size == 0 or not np.isfinite(highest) or highest <= 0.0:
        return np.inf
    gap = float(np.max(np.diff(angle, append=angle[0] + 2 * np.pi)))
    half = gap / 2 + FACE_ANGLE_SLACK
    return highest / math.cos(half) if half < math.pi / 2 else np.inf


#: Extra angle (rad) about each point's direction within which the face lines it is tested
#: against lie: far above the rounding of the angles (1e-15), so that no line a point could be
#: above is left out.
FACE_ANGLE_SLACK = 1e-6


def _lines_within(angle: Array, low: float, high: float) -> Index:
    """Indices of the sorted angles *angle* (rad, −π..π) within [*low*, *high*] (rad, any
    values), across ±π."""
    if not np.isfinite(low) or not np.isfinite(high) or high - low >= 2 * np.pi:
        return np.arange(angle.size)
    low = (low + np.pi) % (2 * np.pi) - np.pi
    high = (high + np.pi) % (2 * np.pi) - np.pi
    first = int(np.searchsorted(angle, low, side="left"))
    last = int(np.searchsorted(angle, high, side="right"))
    if low <= high:
        return np.arange(first, last)
    return np.concatenate((np.arange(first, angle.size), np.arange(0, last)))


def cut_away(raw_xy: Array, profile_xy: Array, tolerance: float) -> Mask:
    """True for each raw envelope point farther than *tolerance* from the trimmed profile."""
    ring = shapely.LinearRing(profile_xy)
    shapely.prepare(ring)  # an indexed test: plain distances take N·M time on long curves
    near = shapely.dwithin(ring, shapely.points(raw_xy), tolerance)
    return ~near & np.isfinite(raw_xy).all(axis=1)


def crossings(xy: Array, points: Array) -> tuple[Index, Index]:
    """The two chords of the closed polyline *xy* (chord i from point i to point i + 1) each of
    *points* lies on, where the polyline crosses itself (the vertices a trim adds): the nearest
    chord through the point and the nearest that shares no point with it, (K,) indices each,
    −1 where there are not two (an indexed search: a cam whose every bump is undercut has
    thousands of crossings and of chords)."""
    count = len(xy)
    chords = shapely.linestrings(np.stack((xy, np.roll(xy, -1, axis=0)), axis=1))
    found = shapely.points(points)
    reach = 1e-9 * (1.0 + float(np.abs(xy).max(initial=0.0)))  # far above rounding
    point, chord = shapely.STRtree(chords).query(found, predicate="dwithin", distance=reach)
    order = np.lexsort((shapely.distance(chords[chord], found[point]), point))
    point, chord = point[order], chord[order]
    first = np.full(len(points), -1)
    second = np.full(len(points), -1)
    if not point.size:
        return first, second
    starts = np.flatnonzero(np.r_[True, point[1:] != point[:-1]])
    first[point[starts]] = chord[starts]
    lead = np.repeat(chord[starts], np.diff(np.r_[starts, point.size]))
    apart = np.abs((chord - lead + count // 2) % count - count // 2) > 1
    kept, at = np.unique(point[apart], return_index=True)
    second[kept] = chord[apart][at]
    return first, second
