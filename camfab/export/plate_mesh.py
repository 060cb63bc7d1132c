"""A plate's extrusion as a triangle mesh whose caps have no needle facet.

manifold3d triangulates an extrusion's caps by clipping ears off the contour; on a contour
sampled within a fine tolerance (0.1 µm), any three neighbouring points lie within a few tenths
of a micrometre of a line, so every ear is a needle thinner than an STL can hold
(:data:`camfab.export.mesh_quality.MIN_ALTITUDE_MM`), and a contour without a hole has at least
two. A cam's outline (and its bore) is met once by every ray from the cam centre, so each cap is
the fan from the centre to the outline's chords, or the strip between the outline and the bore
zipped in order of their polar angles: each facet stands on a chord and reaches across the
plate. Contours that are not so (an undercut corner folding back, a hole off the centre), or
a strip with a facet that would be thin or folded (a keyway's side, nearly radial, between two
outline points far apart at a coarse tolerance), are left to manifold3d (None).
"""

from __future__ import annotations

import math

import numpy as np

from camfab.arrays import Array, Index


def extruded_mesh(chains: tuple[Array, ...], height: float,
                  thinnest: float) -> tuple[Array, Index] | None:
    """The (V, 3) vertices (mm) and (F, 3) outward faces of the region of *chains* (an outline,
    or an outline and one hole round the cam centre; (N, 2) points, mm) extruded from z = 0 to
    *height*, its caps fanned from the centre or zipped to the hole, every facet at least
    *thinnest* (mm) across; None when the chains are not so or a facet would be thinner."""
    if len(chains) not in (1, 2):
        return None
    rings = [_counter_clockwise(np.asarray(c, dtype=np.float64)) for c in chains]
    angles = [_polar_angles(ring) for ring in rings]
    if angles[0] is None or angles[-1] is None:
        return None
    outline = rings[0]
    n = len(outline)
    if len(rings) == 1:
        plane = np.vstack((outline, np.zeros((1, 2))))
        i = np.arange(n)
        cap = np.column_stack((np.full(n, n), i, (i + 1) % n))
        walls = [(np.arange(n), False)]
    else:
        hole = rings[1]
        plane = np.vstack((outline, hole))
        cap = _zipped(angles[0], angles[1], n)
        walls = [(np.arange(n), False), (n + np.arange(len(hole)), True)]
    if not _thick(plane, cap, thinnest):
        return None
    count = len(plane)
    vertices = np.vstack((np.column_stack((plane, np.zeros(count))),
                          np.column_stack((plane, np.full(count, height)))))
    faces = [cap[:, ::-1], cap + count]  # bottom facing down, top facing up
    for ring, inward in walls:
        ahead = np.roll(ring, -1)
        low = np.column_stack((ring, ahead, ahead + count))
        high = np.column_stack((ring, ahead + count, ring + count))
        if inward:
            low, high = low[:, ::-1], high[:, ::-1]
        faces += [low, high]
    return vertices, np.vstack(faces).astype(np.int64)


def _counter_clockwise(ring: Array) -> Array:
    """*ring* (N, 2) in counter-clockwise order (its shoelace area positive)."""
    x, y = ring[:, 0], ring[:, 1]
    area = float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))
    return ring if area > 0.0 else ring[::-1]


def _polar_angles(ring: Array) -> Array | None:
    """The polar angles (rad) of *ring*'s points about the origin, unwrapped: rising strictly
    once round (None when a ray from the centre meets it twice or it misses the centre)."""
    if np.min(np.hypot(ring[:, 0], ring[:, 1])) <= 0.0:
        return None
    angle = np.unwrap(np.arctan2(ring[:, 1], ring[:, 0]))
    steps = np.diff(np.append(angle, angle[0] + 2.0 * math.pi))
    if not (steps > 0.0).all() or abs(float(steps.sum()) - 2.0 * math.pi) > 1e-9:
        return None
    return angle


def _zipped(outer: Array, inner: Array, n: int) -> Index:
    """The facets of the strip between a ring of *n* points at polar angles *outer* (indices
    0..n-1) and one inside it at angles *inner* (indices n..), counter-clockwise: each outer
    chord to the inner point before its end, each inner chord to the outer point at or before
    its end, in order of angle."""
    m = len(inner)
    start = outer[0]
    # both rings from the outline's first point on, once round: each point's angle past it
    past_outer = outer - start
    past_inner = np.mod(inner - start, 2.0 * math.pi)
    first = int(np.argmin(past_inner))
    order_inner = (first + np.arange(m)) % m
    past_inner = past_inner[order_inner]
    # the events: the end of each outer chord (points 1..n, n the first again), then of each
    # inner chord (its points 1..m, m its first again); an outer end at a tie goes first
    ends_outer = np.append(past_outer[1:], 2.0 * math.pi)
    ends_inner = np.append(past_inner[1:], past_inner[0] + 2.0 * math.pi)
    keys = np.concatenate((ends_outer, ends_inner))
    is_outer = np.concatenate((np.ones(n, dtype=bool), np.zeros(m, dtype=bool)))
    events = np.lexsort((~is_outer, keys))
    outer_done = np.cumsum(is_outer[events])
    inner_done = np.cumsum(~is_outer[events])
    which = is_outer[events]
    i_end, j_end = outer_done % n, inner_done
    rows = np.empty((len(events), 3), dtype=np.int64)
    # an outer chord (i - 1, i) to the inner point reached so far
    rows[which, 0] = (outer_done[which] - 1) % n
    rows[which, 1] = i_end[which]
    rows[which, 2] = n + order_inner[j_end[which] % m]
    # an inner chord (j - 1, j) to the outer point reached so far
    inner_rows = ~which
    rows[inner_rows, 0] = i_end[inner_rows]
    rows[inner_rows, 1] = n + order_inner[j_end[inner_rows] % m]
    rows[inner_rows, 2] = n + order_inner[(j_end[inner_rows] - 1) % m]
    return rows


def _thick(plane: Array, faces: Index, thinnest: float) -> bool:
    """Whether every facet of *faces* on the (V, 2) *plane* points winds counter-clockwise and
    is at least *thinnest* (mm) across (twice its area over its longest edge)."""
    corners = plane[faces]
    edges = np.roll(corners, -1, axis=1) - corners
    area2 = (edges[:, 0, 0] * edges[:, 1, 1] - edges[:, 0, 1] * edges[:, 1, 0])
    longest = np.hypot(edges[..., 0], edges[..., 1]).max(axis=1)
    return bool((area2 >= thinnest * longest).all())
