"""A closed cam contour in the cam frame: vertices joined by lines and circular arcs.

Arcs use the bulge convention of DXF LWPOLYLINE: edge i runs from vertex i to vertex i + 1
(the last back to the first) with bulge ``b = tan(included angle / 4)``, positive when the arc
turns counter-clockwise, 0 for a straight line. :meth:`Profile.ccw` puts any contour in
counter-clockwise order, in which a positive bulge is convex (the arc bulges outward).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camfab.arrays import Array, Index
from camfab.curves.nearest import contour_distance
from camfab.curves.plane import cross
from camfab.curves.sampling import arc_points

#: Two consecutive vertices closer than this (mm) are one point: far below any tolerance and far
#: above the rounding of coordinates of cams up to metres in size.
MERGE_DISTANCE = 1e-9


@dataclass(frozen=True)
class Arcs:
    """The arc edges of a profile: their edge index, centre, radius, start angle and sweep (rad,
    counter-clockwise positive)."""

    index: Index
    centre: Array
    radius: Array
    start_angle: Array
    sweep: Array


@dataclass(frozen=True)
class Profile:
    """A closed contour: (N, 2) *vertices* (mm) and the (N,) *bulges* of the edges after them."""

    vertices: Array
    bulges: Array

    @classmethod
    def from_points(cls, points: Array, bulges: Array | None = None) -> Profile:
        """A contour from points, dropping repeated points and a repeated closing point."""
        pts = np.asarray(points, dtype=np.float64)
        bul = np.zeros(len(pts)) if bulges is None else np.asarray(bulges, dtype=np.float64)
        step = np.hypot(*(np.roll(pts, -1, axis=0) - pts).T)
        keep = step > MERGE_DISTANCE
        if not keep.any():
            raise ValueError("a profile needs at least three distinct points")
        return cls(pts[keep], bul[keep])

    @property
    def signed_area(self) -> float:
        """Area (mm²), positive for counter-clockwise order, arcs included."""
        v = self.vertices
        area = 0.5 * float(np.sum(cross(v, np.roll(v, -1, axis=0))))
        arcs = self.arcs()
        segment = 0.5 * arcs.radius**2 * (arcs.sweep - np.sin(arcs.sweep))
        return area + float(np.sum(segment))

    @property
    def area(self) -> float:
        return abs(self.signed_area)

    def ccw(self) -> Profile:
        """The same contour in counter-clockwise order."""
        if self.signed_area >= 0.0:
            return self
        vertices = self.vertices[::-1]
        bulges = -np.roll(self.bulges[::-1], -1)
        return Profile(vertices.copy(), bulges)

    def canonical(self) -> Profile:
        """The same contour counter-clockwise, starting at its vertex of least x (then y): one
        contour, however it was chained, gives the same arrays (and the same arithmetic)."""
        prof = self.ccw()
        first = int(np.lexsort((prof.vertices[:, 1], prof.vertices[:, 0]))[0])
        return Profile(np.roll(prof.vertices, -first, axis=0), np.roll(prof.bulges, -first))

    def arcs(self) -> Arcs:
        """Centre, radius and angles of every arc edge."""
        index = np.flatnonzero(self.bulges != 0.0)
        start = self.vertices[index]
        end = np.roll(self.vertices, -1, axis=0)[index]
        bulge = self.bulges[index]
        sweep = 4.0 * np.arctan(bulge)
        chord = end - start
        half = 0.5 * np.hypot(chord[:, 0], chord[:, 1])
        left = np.stack((-chord[:, 1], chord[:, 0]), axis=-1)
        left /= np.maximum(2 * half, 1e-300)[:, None]
        centre = 0.5 * (start + end) + (half / np.tan(sweep / 2))[:, None] * left
        radius = half / np.abs(np.sin(sweep / 2))
        rel = start - centre
        return Arcs(index, centre, radius, np.arctan2(rel[:, 1], rel[:, 0]), sweep)

    def bounds(self) -> tuple[Array, Array]:
        """The exact bounding box (mm): its lower-left and upper-right corners, (2,) each.

        An arc reaches beyond its ends where it crosses the axis directions (0, 90, 180 and
        270° about its centre): those points count, not just the vertices.
        """
        points = [self.vertices]
        arcs = self.arcs()
        if arcs.index.size:
            quarter = np.arange(4) * (np.pi / 2)
            # turn from each arc's start to each axis direction, the way the arc turns
            turn = np.mod((quarter[None, :] - arcs.start_angle[:, None])
                          * np.sign(arcs.sweep)[:, None], 2 * np.pi)
            row, column = np.nonzero(turn <= np.abs(arcs.sweep)[:, None])
            direction = np.stack((np.cos(quarter), np.sin(quarter)), axis=-1)
            points.append(arcs.centre[row] + arcs.radius[row, None] * direction[column])
        every = np.concatenate(points)
        return every.min(axis=0), every.max(axis=0)

    def distance(self, points: Array) -> Array:
        """Distance (mm) of each of (K, 2) *points* from the contour, arcs measured as arcs.

        The nearest point of the contour is a vertex, the foot of a perpendicular inside a
        line, or the radial projection inside an arc's span; each point is measured against
        the edges near it (:func:`camfab.curves.nearest.contour_distance`: the same numbers as
        measuring every edge).
        """
        return contour_distance(self, points)

    def points(self, tolerance: float, split_lines: bool = True) -> Array:
        """The contour as a closed chain of points (mm), in order, without a repeated closing
        point: its arcs cut into chords within *tolerance* (mm), and its lines into pieces no
        longer than those chords, so the chain samples lines as finely as arcs (an arc fit of
        the chain, after an offset say, then cannot bow away from a long line between two of
        its points). A contour of lines only gives its vertices; so do its lines with
        *split_lines* False (for a test or a drawing of the chain, which needs no more, and whose
        points then do not grow without bound when every arc is tiny)."""
        arcs = self.arcs()
        if not arcs.index.size:
            return self.vertices.copy()
        chains = {int(i): arc_points(arcs.centre[k], self.vertices[i], float(arcs.sweep[k]),
                                     tolerance)[:-1]
                  for k, i in enumerate(arcs.index)}
        chords = [np.hypot(*np.diff(c, axis=0).T) for c in chains.values() if len(c) > 1]
        gap = max((float(c.max()) for c in chords), default=math.inf) if split_lines else math.inf
        following = np.roll(self.vertices, -1, axis=0)
        pieces = []
        for i, vertex in enumerate(self.vertices):
            chain = chains.get(i)
            if chain is not None:
                pieces.append(chain)
                continue
            count = max(1, math.ceil(float(np.hypot(*(following[i] - vertex))) / gap))
            t = np.arange(count)[:, None] / count
            pieces.append(vertex + t * (following[i] - vertex))
        return np.concatenate(pieces)

    def normal_angles(self) -> tuple[Array, Array]:
        """Outward normal angles (rad) of each edge at its start and at its end, for a contour in
        counter-clockwise order (a concave arc's outward normal points at its centre)."""
        v = self.vertices
        d = np.roll(v, -1, axis=0) - v
        line_angle = np.arctan2(-d[:, 0], d[:, 1])
        start, end = line_angle.copy(), line_angle.copy()
        arcs = self.arcs()
        outward = np.where(arcs.sweep > 0, 0.0, math.pi)
        start[arcs.index] = arcs.start_angle + outward
        end[arcs.index] = arcs.start_angle + arcs.sweep + outward
        return start, end

    def offset(self, distance: float) -> Profile:
        """The contour moved *distance* (mm) along its outward normal (negative: inward), exactly:
        lines shift, arcs keep their centres and sweeps and change radius. For a contour whose
        edges meet tangentially (no corners) and no edge of which shrinks to nothing.

        Raises
        ------
        ValueError
            The contour has a corner, or an arc would shrink through its centre.
        """
        prof = self.ccw()
        start, end = prof.normal_angles()
        turn = np.mod(start - np.roll(end, 1) + math.pi, 2.0 * math.pi) - math.pi
        if np.abs(turn).max() > 1e-7:
            raise ValueError("the contour has corners: offset it with round joins instead")
        arcs = prof.arcs()
        if np.any(arcs.radius + np.sign(arcs.sweep) * distance <= 0.0):
            raise ValueError(f"an arc of the contour is smaller than the offset {distance:g} mm")
        normal = np.stack((np.cos(start), np.sin(start)), axis=-1)
        return Profile(prof.vertices + distance * normal, prof.bulges.copy())

    def radii(self) -> Array:
        """Distance of every vertex from the cam centre (mm)."""
        return np.hypot(self.vertices[:, 0], self.vertices[:, 1])
