"""Offsets of a plate's regions: the laser's kerf, the milling cutter's centre path, and the
material a cutter of some radius cannot reach.

shapely buffers the polygons (round joins, their arcs cut into chords within the tolerance the
caller gives); the callers fit the results with arcs again for the files.
"""

from __future__ import annotations

import math

import numpy as np

from camfab.arrays import Array, Mask


def quad_segments(radius: float, tolerance: float) -> int:
    """shapely's segments per quarter circle for round joins of *radius* (mm) whose chords stray
    at most *tolerance* (mm) from the arc."""
    radius = abs(radius)
    if radius <= tolerance:
        return 1
    step = 2.0 * math.acos(1.0 - tolerance / radius)
    return max(1, math.ceil(0.5 * math.pi / step))


def _rings(region: object) -> list[Array]:
    """The exteriors of a (Multi)Polygon as (N, 2) points, counter-clockwise, without the
    repeated closing point; holes inside a part are not kept."""
    import shapely

    parts = getattr(region, "geoms", [region])
    rings = []
    for part in parts:
        if part.is_empty or part.area == 0.0:
            continue
        ring = shapely.LinearRing(part.exterior)
        coords = np.asarray(ring.coords)[:-1]
        rings.append(coords if ring.is_ccw else coords[::-1].copy())
    return rings


def grow(points: Array, distance: float, tolerance: float) -> list[Array]:
    """The region inside the closed chain *points* (mm) grown by *distance* (mm; negative
    shrinks it): its outlines, one per piece (a region that shrinks apart gives several, one
    that vanishes none). Round joins stray at most *tolerance* (mm) from true arcs.
    """
    import shapely

    region = shapely.Polygon(points)
    if distance == 0.0:
        return _rings(region)
    return _rings(region.buffer(distance, quad_segs=quad_segments(distance, tolerance)))


def closing(points: Array, radius: float, tolerance: float) -> Array:
    """The outline (mm) of what a cutter of *radius* (mm) running around the outside of the
    region inside *points* leaves: the region grown by the radius and shrunk back, its hollows
    narrower than the cutter filled. Round joins stray at most *tolerance* (mm)."""
    import shapely

    segments = quad_segments(radius, tolerance)
    region = shapely.Polygon(points).buffer(radius, quad_segs=segments)
    # the closing of a connected region is connected: one outline
    return _rings(region.buffer(-radius, quad_segs=segments))[0]


def uncut_depth(part: Array, closed: Array, probes: Array, tolerance: float) -> Array:
    """How deep (mm) each of *probes* lies under material a cutter left: its distance from the
    outline *closed* (see :func:`closing`) where it lies within *tolerance* (mm) of what the
    cutter left beyond the outline *part*, 0 elsewhere."""
    import shapely

    depth = np.zeros(len(probes))
    left = shapely.Polygon(closed).difference(shapely.Polygon(part))
    if left.is_empty:
        return depth
    points = shapely.points(probes)
    near = shapely.dwithin(points, left, tolerance)
    depth[near] = shapely.distance(points[near], shapely.LinearRing(closed))
    return depth


def on_outline(outline: Array, probes: Array, tolerance: float) -> Mask:
    """Which of *probes* lie within *tolerance* (mm) of the closed chain *outline*."""
    import shapely

    return shapely.dwithin(shapely.points(probes), shapely.LinearRing(outline), tolerance)
