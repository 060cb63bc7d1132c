"""The distance of points from a contour of lines and arcs, measured against nearby edges only.

The nearest point of a contour is a vertex, the foot of a perpendicular inside a line, or the
radial projection inside an arc's span. :func:`all_pairs` measures each point against every
edge; :func:`contour_distance` gives the same numbers against the few edges near each point:
the edges are put in the cells of a square grid that their bounding boxes overlap, and a point
is measured against the edges of its own cell, then of the rings of cells around it, until the
distance found is no larger than the least distance any edge outside the searched cells can
have (the point's distance from the outside of the searched block of cells). The edge that
gives the minimum is then among those measured, and each (point, edge) value is computed by
the same expressions as :func:`all_pairs`, so the minimum is the same number.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from camfab.arrays import Array, Index, Mask

if TYPE_CHECKING:
    from camfab.curves.profile import Profile

#: Slack, relative to the size of the coordinates (and of the largest arc radius), between the
#: distance a point is measured at and the bound that rules the unsearched edges out: far above
#: the rounding of either (about 1e-15 of that size), far below any tolerance.
RELATIVE_SLACK = 1e-9

#: Below this many (point, edge) pairs every edge is measured (the grid would cost more).
ALL_PAIRS_LIMIT = 20_000

#: Contours larger than this (mm, see :attr:`Edges.size`), and points further out, are measured
#: against every edge: the grid's arithmetic could overflow.
LARGEST_SIZE = 1e100

#: Points measured at once by :func:`all_pairs`: the (points × edges) arrays of a block stay in
#: the processor's cache.
BLOCK = 512

#: Points searched at once by :func:`contour_distance`: their (point, edge) pairs of a ring stay
#: some tens of megabytes where many edges crowd the cells (a folded groove's outline crosses
#: itself over and over), not gigabytes for hundreds of thousands of points.
SEARCH_BLOCK = 8192


@dataclass(frozen=True)
class Edges:
    """The edges of a closed contour as the distance formulas take them, one row per edge i
    (from vertex i to vertex i + 1): its start (mm), whether it is a line, a line's direction
    vector and its squared length (mm, mm²), an arc's centre (mm), radius (mm), start direction
    (cos, sin), turning sign and absolute sweep (rad). Rows of the other kind hold zeros."""

    start: Array
    line: Mask
    delta: Array
    length2: Array
    centre: Array
    radius: Array
    start_dir: Array
    sign: Array
    sweep: Array

    @classmethod
    def of(cls, profile: Profile) -> Edges:
        v = profile.vertices
        line = profile.bulges == 0.0
        delta = np.roll(v, -1, axis=0) - v
        length2 = np.maximum(delta[:, 0] * delta[:, 0] + delta[:, 1] * delta[:, 1], 1e-300)
        arcs = profile.arcs()
        centre, radius = np.zeros_like(v), np.zeros(len(v))
        start_dir, sign, sweep = np.zeros_like(v), np.zeros(len(v)), np.zeros(len(v))
        centre[arcs.index], radius[arcs.index] = arcs.centre, arcs.radius
        start_dir[arcs.index] = np.stack((np.cos(arcs.start_angle), np.sin(arcs.start_angle)),
                                         axis=-1)
        sign[arcs.index], sweep[arcs.index] = np.sign(arcs.sweep), np.abs(arcs.sweep)
        return cls(v, line, delta, length2, centre, radius, start_dir, sign, sweep)

    def boxes(self) -> tuple[Array, Array]:
        """Each edge's bounding box (mm): lower-left and upper-right corners, (N, 2) each; an
        arc's includes the points where it crosses the axis directions about its centre."""
        end = self.start + self.delta
        lo, hi = np.minimum(self.start, end), np.maximum(self.start, end)
        arc = np.flatnonzero(~self.line)
        if arc.size:
            quarter = np.arange(4) * (np.pi / 2)
            start_angle = np.arctan2(self.start_dir[arc, 1], self.start_dir[arc, 0])
            turn = np.mod((quarter[None, :] - start_angle[:, None]) * self.sign[arc, None],
                          2 * np.pi)
            reached = turn <= self.sweep[arc, None]
            direction = np.stack((np.cos(quarter), np.sin(quarter)), axis=-1)
            extreme = self.centre[arc, None, :] + self.radius[arc, None, None] * direction
            lo[arc] = np.minimum(lo[arc], np.where(reached[..., None], extreme, np.inf).min(1))
            hi[arc] = np.maximum(hi[arc], np.where(reached[..., None], extreme, -np.inf).max(1))
        return lo, hi

    @property
    def size(self) -> float:
        """The size (mm) the rounding of the distances scales with: the largest coordinate of
        a vertex, plus the largest arc radius."""
        return float(np.abs(self.start).max(initial=0.0) + self.radius.max(initial=0.0))


def vertex_sq(px: Array, py: Array, vx: Array, vy: Array) -> Array:
    """Squared distance (mm²) of points (px, py) from vertices (vx, vy), broadcast."""
    return (px - vx) ** 2 + (py - vy) ** 2


def line_sq(px: Array, py: Array, ax: Array, ay: Array, dx: Array, dy: Array,
            length2: Array) -> Array:
    """Squared distance (mm²) of points from the lines starting at (ax, ay) along (dx, dy) of
    squared length *length2*, where the foot of the perpendicular falls inside the line (inf
    elsewhere), broadcast."""
    rx, ry = px - ax, py - ay
    t = (rx * dx + ry * dy) / length2
    across = (rx * dy - ry * dx) ** 2 / length2
    return np.where((t > 0) & (t < 1), across, np.inf)


def arc_gap(px: Array, py: Array, cx: Array, cy: Array, sx: Array, sy: Array, sign: Array,
            sweep: Array, radius: Array) -> Array:
    """Distance (mm) of points from the arcs about (cx, cy) starting in direction (sx, sy) and
    turning *sign* by *sweep* (rad), where the radial projection falls inside the arc's span
    (inf elsewhere), broadcast."""
    rx, ry = px - cx, py - cy
    # the angle from the arc's start to the point, turning the way the arc turns
    turn = np.arctan2(sx * ry - sy * rx, sx * rx + sy * ry) * sign
    inside = np.mod(turn, 2 * np.pi) <= sweep
    gap = np.abs(np.hypot(rx, ry) - radius)
    return np.where(inside, gap, np.inf)


def all_pairs(edges: Edges, points: Array) -> Array:
    """Distance (mm) of each of (K, 2) *points* from the contour, every edge measured."""
    return np.concatenate([_all_pairs(edges, points[i:i + BLOCK])
                           for i in range(0, len(points), BLOCK)] or [np.zeros(0)])


def _all_pairs(edges: Edges, points: Array) -> Array:
    px, py = points[:, :1], points[:, 1:]
    v = edges.start
    best = np.min(vertex_sq(px, py, v[:, 0], v[:, 1]), axis=1)
    line = edges.line
    if line.any():
        a, d = v[line], edges.delta[line]
        best = np.minimum(best, np.min(line_sq(px, py, a[:, 0], a[:, 1], d[:, 0], d[:, 1],
                                               edges.length2[line]), axis=1))
    best = np.sqrt(best)
    arc = ~line
    if arc.any():
        c, u = edges.centre[arc], edges.start_dir[arc]
        best = np.minimum(best, np.min(arc_gap(px, py, c[:, 0], c[:, 1], u[:, 0], u[:, 1],
                                               edges.sign[arc], edges.sweep[arc],
                                               edges.radius[arc]), axis=1))
    return best


def contour_distance(profile: Profile, points: Array) -> Array:
    """Distance (mm) of each of (K, 2) *points* from *profile*, arcs measured as arcs: the
    numbers :func:`all_pairs` gives, each point measured against the edges near it."""
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    edges = Edges.of(profile)
    size = edges.size
    if (len(points) * len(edges.start) <= ALL_PAIRS_LIMIT or not size < LARGEST_SIZE
            or not np.isfinite(edges.centre).all()
            or not np.abs(points).max(initial=0.0) < LARGEST_SIZE):
        return all_pairs(edges, points)  # few pairs, or numbers a grid cannot hold
    grid = EdgeGrid.of(*edges.boxes(), RELATIVE_SLACK * (1.0 + size))
    slack = RELATIVE_SLACK * (1.0 + size + np.abs(points).sum(axis=1))
    return np.concatenate([_search(edges, grid, points[i:i + SEARCH_BLOCK],
                                   slack[i:i + SEARCH_BLOCK])
                           for i in range(0, len(points), SEARCH_BLOCK)] or [np.zeros(0)])


@dataclass(frozen=True)
class EdgeGrid:
    """Square cells of side *side* (mm) from *origin*, *shape* (columns, rows), and the edges
    whose bounding boxes overlap each cell: cell c holds ``edge[pointer[c]:pointer[c + 1]]``;
    cell (i, j) is number j·columns + i."""

    origin: Array
    side: float
    shape: tuple[int, int]
    pointer: Index
    edge: Index

    @classmethod
    def of(cls, lo: Array, hi: Array, pad: float) -> EdgeGrid:
        """The grid over boxes (N, 2) grown by *pad* (mm), with about one cell per edge."""
        lo, hi = lo - pad, hi + pad
        origin = lo.min(axis=0)
        extent = hi.max(axis=0) - origin
        count = len(lo)
        side = max(math.sqrt(extent[0] * extent[1] / count), float(extent.max()) / count, pad)
        shape = np.floor(extent / side).astype(np.intp) + 1
        first = np.minimum(np.floor((lo - origin) / side).astype(np.intp), shape - 1)
        last = np.minimum(np.floor((hi - origin) / side).astype(np.intp), shape - 1)
        width = last - first + 1
        owner = np.repeat(np.arange(count), width[:, 0] * width[:, 1])
        k = np.arange(owner.size) - (np.cumsum(width[:, 0] * width[:, 1])
                                     - width[:, 0] * width[:, 1])[owner]
        column = first[owner, 0] + k % width[owner, 0]
        row = first[owner, 1] + k // width[owner, 0]
        cell = row * shape[0] + column
        order = np.argsort(cell, kind="stable")
        pointer = np.concatenate(([0], np.cumsum(np.bincount(cell, minlength=int(shape.prod())))))
        return cls(origin, side, (int(shape[0]), int(shape[1])), pointer, owner[order])

    def cell_of(self, points: Array) -> tuple[Index, Index]:
        """The column and row of the cell each point lies in (outside the grid for points
        outside it)."""
        cell = np.floor((points - self.origin) / self.side).astype(np.intp)
        return cell[:, 0], cell[:, 1]

    def first_ring(self, column: Index, row: Index) -> Index:
        """The first ring about each cell that reaches the grid (0 inside it)."""
        columns, rows = self.shape
        return np.maximum.reduce([np.zeros_like(column), -column, column - (columns - 1),
                                  -row, row - (rows - 1)])

    def covers(self, column: Index, row: Index, ring: Index) -> Mask:
        """Whether the block of cells within *ring* of each cell holds the whole grid."""
        columns, rows = self.shape
        return ((column - ring <= 0) & (column + ring >= columns - 1)
                & (row - ring <= 0) & (row + ring >= rows - 1))

    def reach(self, points: Array, column: Index, row: Index, ring: Index) -> Array:
        """Each point's distance (mm) from the outside of the block of cells within *ring* of
        its cell: no edge outside the block is nearer."""
        low = self.origin + (np.stack((column, row), axis=-1) - ring[:, None]) * self.side
        high = self.origin + (np.stack((column, row), axis=-1) + ring[:, None] + 1) * self.side
        return np.minimum(points - low, high - points).min(axis=1)

    def ring_edges(self, column: Index, row: Index, ring: Index) -> tuple[Index, Index]:
        """The edges in the cells of each *ring* about cells (*column*, *row*): pairs (which
        of the cells, edge); an edge over several of the cells comes once for each."""
        near = ring > 0
        sides = [  # (fixed coordinate, first and last along, runs along columns, used)
            (row - ring, column - ring, column + ring, True, np.ones_like(near)),
            (row + ring, column - ring, column + ring, True, near),
            (column - ring, row - ring + 1, row + ring - 1, False, near),
            (column + ring, row - ring + 1, row + ring - 1, False, near),
        ]
        owners, cells = zip(*(self._run(*side) for side in sides), strict=True)
        owner, cell = np.concatenate(owners), np.concatenate(cells)
        count = self.pointer[cell + 1] - self.pointer[cell]
        which = np.repeat(owner, count)
        k = np.arange(which.size) - np.repeat(np.cumsum(count) - count, count)
        return which, self.edge[np.repeat(self.pointer[cell], count) + k]

    def _run(self, fixed: Index, first: Index, last: Index, along_columns: bool,
             used: Mask) -> tuple[Index, Index]:
        """The grid's cells of a straight run of cells, for each owner: (owner, cell)."""
        columns, rows = self.shape
        length, across = (columns, rows) if along_columns else (rows, columns)
        first, last = np.maximum(first, 0), np.minimum(last, length - 1)
        count = np.where(used & (fixed >= 0) & (fixed < across), np.maximum(last - first + 1, 0),
                         0)
        owner = np.repeat(np.arange(len(fixed)), count)
        along = np.repeat(first, count) + np.arange(owner.size) - np.repeat(np.cumsum(count)
                                                                            - count, count)
        if along_columns:
            return owner, fixed[owner] * columns + along
        return owner, along * columns + fixed[owner]


def _search(edges: Edges, grid: EdgeGrid, points: Array, slack: Array) -> Array:
    """Each point measured against the edges of rings of cells about it, ring after ring,
    until no unsearched edge can be nearer than the distance found (less *slack*, mm)."""
    squared, arc = np.full(len(points), np.inf), np.full(len(points), np.inf)
    column, row = grid.cell_of(points)
    ring = grid.first_ring(column, row)
    pending = np.arange(len(points))
    while pending.size:
        which, edge = grid.ring_edges(column[pending], row[pending], ring[pending])
        _measure(edges, points, pending[which], edge, squared, arc)
        found = np.minimum(np.sqrt(squared[pending]), arc[pending])
        done = grid.covers(column[pending], row[pending], ring[pending]) | (
            found <= grid.reach(points[pending], column[pending], row[pending], ring[pending])
            - slack[pending])
        pending = pending[~done]
        ring[pending] += 1
    return np.minimum(np.sqrt(squared), arc)


def _measure(edges: Edges, points: Array, who: Index, edge: Index, squared: Array,
             arc: Array) -> None:
    """Lower *squared* (mm², vertices and lines) and *arc* (mm) of each point *who* to its
    distance from *edge* (pairs), as :func:`all_pairs` computes each."""
    px, py = points[who, 0], points[who, 1]
    v = edges.start[edge]
    value = vertex_sq(px, py, v[:, 0], v[:, 1])
    line = edges.line[edge]
    if line.any():
        d = edges.delta[edge[line]]
        value[line] = np.minimum(value[line], line_sq(px[line], py[line], v[line, 0],
                                                      v[line, 1], d[:, 0], d[:, 1],
                                                      edges.length2[edge[line]]))
    np.minimum.at(squared, who, value)
    curved = ~line
    if curved.any():
        e = edge[curved]
        c, u = edges.centre[e], edges.start_dir[e]
        np.minimum.at(arc, who[curved], arc_gap(px[curved], py[curved], c[:, 0], c[:, 1],
                                                u[:, 0], u[:, 1], edges.sign[e],
                                                edges.sweep[e], edges.radius[e]))
