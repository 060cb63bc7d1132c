"""Undercut: where the follower's envelope folds over itself, and the cam that is really cut.

On a convex stretch whose pitch radius of curvature is smaller than the roller radius, the offset
curve runs backwards and crosses itself (a swallowtail); a flat face does the same where
Rb + s + s″ < 0. GEOS buffers remove such loops silently, so camfab detects them from curvature
and from the raw envelope (is it a simple ring?), and then trims them: the raw envelope is noded
into faces and the faces the follower never enters are kept. Their boundary is the cam a cutter
following the design would leave, and the follower simulation on it measures the motion error.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import shapely

from camfab.arrays import Array, Mask

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
    """Points on the cam side of every face line ``x·n ≤ h`` (flat faces), *normals* (K, 2) and
    *heights* (K,) in the cam frame."""

    limit = heights[None, :] + slack
    # a block of points at a time: a cam whose every bump folds has hundreds of thousands of
    # faces to test against thousands of face lines, gigabytes at once
    block = max(1, FACE_TEST_ELEMENTS // max(1, normals.shape[0]))

    def keep(points: Array) -> Mask:
        return np.concatenate([np.all(points[i:i + block] @ normals.T <= limit, axis=1)
                               for i in range(0, points.shape[0], block)]
                              or [np.zeros(0, dtype=bool)])

    return keep


def cut_away(raw_xy: Array, profile_xy: Array, tolerance: float) -> Mask:
    """True for each raw envelope point farther than *tolerance* from the trimmed profile."""
    ring = shapely.LinearRing(profile_xy)
    shapely.prepare(ring)  # an indexed test: plain distances take N·M time on long curves
    near = shapely.dwithin(ring, shapely.points(raw_xy), tolerance)
    return ~near & np.isfinite(raw_xy).all(axis=1)
