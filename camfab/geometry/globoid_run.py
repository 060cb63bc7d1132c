"""The roller run through a globoidal cam's groove read back (docs/THEORY.md §H): the roller put
at its pose for each cam angle against the edges of the surface's mesh, each edge's point
nearest the roller's axis line measured in closed form.

The mesh's edges near the roller at a pose are found in two steps. A block of consecutive poses
shares one pass over its angular window, which keeps the edges that can come near the roller at
any pose of the block (the axis line at each pose lies within a distance the block computes of
the axis line at its middle pose); each pose then keeps, of those, the edges that can come near
its own roller. Only those are measured in full, unless a side of the roller finds no wall near
(then every edge of its window is). The numbers are those of measuring every edge of the
window: an edge left out stands further from the axis than the nearest wall on each side, and
each measured edge's numbers come from the same operations whichever others are measured.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from camfab.arrays import Array, Index, norms
from camfab.geometry.globoid import turned_back

if TYPE_CHECKING:
    from camfab.geometry.globoid_cam import GloboidCam

#: The edges measured first at a pose of the roller: those with a point within its wall radius
#: and this many tolerances of its axis line, beside its length. A groove that passes has each
#: flank within one tolerance of the wall radius; a side with no wall this near (a groove that
#: fails) has every edge of its window measured.
NEAR_TOLERANCES = 2.0
#: Consecutive poses that share one pass over their angular window (count).
BLOCK = 8
#: Added to every bound of the search (mm): far above the rounding of the distances compared
#: (some 1e-12 mm), far below anything measured.
SLACK_MM = 1e-6


@dataclass(frozen=True)
class RollerRun:
    """The roller run through a groove read back (mm), at each cam angle: how deep the surface
    cuts into the roller's wall radius (0 or less: clear) and how far the nearest surface point
    on each side of the roller stands off it (the gap on the + and − flank)."""

    theta: Array
    cut_mm: Array
    gap_plus_mm: Array
    gap_minus_mm: Array


@dataclass(frozen=True)
class _Poses:
    """The roller at each pose, on the cam (mm; unit vectors): its axis' direction, the pivot,
    the middle of its length, the contact normal there, and that middle's polar angle (rad)."""

    axis: Array
    pivot: Array
    middle: Array
    normal: Array
    polar: Array


def _poses(blank: GloboidCam, theta: Array, motion: Array, middle: float) -> _Poses:
    """The roller's pose at each cam angle of *theta* (its *motion*), *middle* mm from the
    pivot: the numbers of :meth:`Globoid.axis_point`, :meth:`Globoid.normal` and
    :func:`to_cam` for each pose alone, bit for bit (their sines and cosines taken one angle
    at a time, as they take them; the rest is products and sums, the same in any batch)."""
    g = blank.follower
    theta = np.asarray(theta, dtype=np.float64)
    turned = g.sigma * theta
    psi, dpsi = g.rest + motion[0], motion[1]
    c, s = (np.array([f(x) for x in turned]) for f in (np.cos, np.sin))
    cos_psi, sin_psi = (np.array([f(x) for x in psi]) for f in (np.cos, np.sin))

    zero = np.zeros_like(theta)
    axis = turned_back(-np.array([math.cos(x) for x in psi]), zero,
                       np.array([math.sin(x) for x in psi]), c, s)
    pivot = turned_back(np.full_like(theta, g.centre), zero, zero, c, s)
    d = g.centre - middle * cos_psi
    mid = turned_back(d, zero, middle * sin_psi, c, s)
    across = np.array([np.hypot(x, y) for x, y in zip(d, dpsi * middle, strict=True)])
    normal = turned_back(g.sigma * d * sin_psi / across, dpsi * middle / across,
                         g.sigma * d * cos_psi / across, c, s)
    polar = np.array([math.atan2(float(y), float(x)) for x, y in mid[:, :2]])
    return _Poses(axis, pivot, mid, normal, polar)


def roller_run(blank: GloboidCam, edges: Array, theta: Array, motion: Array,
               tolerance: float) -> RollerRun:
    """Put the roller (the wall's radius, over its length inside the groove) at its pose for
    each cam angle of *theta* (their *motion*) against the surface's *edges* ((E, 2, 3), mm,
    on the cam, as a read-back mesh gives them): each edge's point nearest the roller's axis
    line, in closed form, is measured by its distance from it where it lies beside the
    roller's length, those on either side of the plane (a, a × n) apart (the flank on the +
    side of n and on the −). The nearest point of a flat facet to a line that does not pierce
    it lies on its edges, so the edges measure the facets.

    Every edge of an angular window about the roller is measured at each pose, or (the same
    numbers, bit for bit) only those that can come within the wall radius and
    :data:`NEAR_TOLERANCES` *tolerance* (mm) of its axis line beside its length, where each
    side of the roller has a wall that near."""
    g = blank.follower
    ends = blank.contact(2)
    low, high = float(np.min(ends)), float(np.max(ends))
    edges = _split(edges, g.radius)
    start, step = edges[:, 0], edges[:, 1] - edges[:, 0]
    middle_xy = start + 0.5 * step
    polar = np.arctan2(middle_xy[:, 1], middle_xy[:, 0])
    order = np.argsort(polar, kind="stable")
    polar, start, step = polar[order], start[order], step[order]
    half_edge = 0.5 * float(np.max(np.linalg.norm(step, axis=1), initial=0.0))
    # the angular window about the roller's middle holding every edge near it
    middle = 0.5 * (low + high)
    psi_all = g.rest + motion[0]
    r_min = float(np.min(blank.radius_at(np.asarray([low, high])[:, None], psi_all[None, :])))
    reach = g.radius * 1.5 + 1.0 + half_edge
    window = math.pi if r_min <= reach else math.asin(reach / r_min) + 0.02
    poses = _poses(blank, theta, motion, middle)
    near = _Near(start, step, g.radius + NEAR_TOLERANCES * tolerance, low, high)
    cut, gap_p, gap_m = (np.full(theta.size, np.inf) for _ in range(3))
    for first in range(0, theta.size, BLOCK):
        block = np.arange(first, min(first + BLOCK, theta.size))
        nearby = near.of_block(poses, block, polar, window)
        for k in block:
            found = near.measure(poses, k, nearby[k])
            if found is None or max(found) > near.distance:  # a side with no wall near
                pick = _window(polar, float(poses.polar[k]), window)
                found = _nearest(start[pick] - poses.pivot[k], step[pick], poses, k, low, high)
                if found is None:
                    continue
            cut[k] = float(g.radius - found[0])
            gap_p[k] = found[1] - g.radius
            gap_m[k] = found[2] - g.radius
    return RollerRun(np.asarray(theta), cut, gap_p, gap_m)


class _Near:
    """The search for the edges (from *start* along *step*, mm, sorted by polar angle) with a
    point within *distance* mm of the roller's axis line and beside its length (*low* to
    *high* mm from the pivot along it).

    An edge is judged by its middle, which stands within half its length of each of its
    points: within that further of the axis line, and along it within that further of the
    roller's length."""

    def __init__(self, start: Array, step: Array, distance: float, low: float,
                 high: float) -> None:
        self.start, self.step, self.distance = start, step, distance
        self.low, self.high = low, high
        self.centre = start + 0.5 * step
        half = 0.5 * np.linalg.norm(step, axis=1)
        self.half = half + SLACK_MM
        self.off = distance + half + SLACK_MM
        self.longest = float(np.max(half, initial=0.0)) + SLACK_MM
        self.square = np.einsum("ij,ij->i", self.centre, self.centre)
        self.mean, self.half_span = 0.5 * (low + high), 0.5 * (high - low)

    def of_block(self, poses: _Poses, block: Array, polar: Array,
                 window: float) -> dict[int, Array]:
        """For each pose of *block*, the indices of the edges of its window that can come
        near its roller, sorted (of the *polar*-sorted edges; *window*: the window's half
        angle, rad).

        The axis line at pose k stands within ``dev`` of the block's middle pose m at every
        point beside the roller's length (the ends bound it: the gap between two lines grows
        linearly along them); an edge's middle within ``off`` of line k there is within
        ``off + dev`` of line m, and along it within the same of where it is along k. The
        distances are compared squared, expanded into products with the pivot and the axis
        (one matrix product for the block): their rounding, some 1e-11 mm², is far inside
        :data:`SLACK_MM`."""
        m = int(block[len(block) // 2])
        spread = np.abs(np.angle(np.exp(1j * (poses.polar[block] - poses.polar[m]))))
        ends = np.array([self.low - self.longest, self.high + self.longest])
        moved = ((poses.pivot[block] - poses.pivot[m])[:, None, :]
                 + ends[None, :, None] * (poses.axis[block] - poses.axis[m])[:, None, :])
        dev = float(np.max(np.linalg.norm(moved, axis=2))) + SLACK_MM
        kept = []
        for run in _runs(polar, float(poses.polar[m]), window + float(spread.max()) + 1e-9):
            b = self.centre[run] - poses.pivot[m]
            along = b @ poses.axis[m]
            reach = self.off[run] + dev
            keep = ((np.einsum("ij,ij->i", b, b) - along * along <= reach * reach)
                    & (np.abs(along - self.mean) <= self.half_span + self.half[run] + reach))
            kept.append(np.flatnonzero(keep) + run.start)
        pool = np.concatenate(kept)
        # each pose of the block: its own window, and its own line
        centre = np.take(self.centre, pool, axis=0)
        products = centre @ np.concatenate((poses.axis[block], poses.pivot[block])).T
        pivot_along = np.einsum("ij,ij->i", poses.pivot[block], poses.axis[block])
        pivot_square = np.einsum("ij,ij->i", poses.pivot[block], poses.pivot[block])
        along = products[:, :block.size] - pivot_along
        off2 = (self.square[pool][:, None] - 2.0 * products[:, block.size:] + pivot_square
                - along * along)
        limit = self.off[pool]
        keep = ((off2 <= (limit * limit)[:, None])
                & (np.abs(along - self.mean) <= (self.half_span + self.half[pool])[:, None]))
        return {int(k): pool[keep[:, i] & _inside(pool, polar, float(poses.polar[k]), window)]
                for i, k in enumerate(block)}

    def measure(self, poses: _Poses, k: int, picked: Array) -> tuple[float, float, float] | None:
        """:func:`_nearest` of the edges *picked* at pose *k*."""
        return _nearest(np.take(self.start, picked, axis=0) - poses.pivot[k],
                        np.take(self.step, picked, axis=0), poses, int(k), self.low, self.high)


def _nearest(a: Array, e: Array, poses: _Poses, k: int, low: float,
             high: float) -> tuple[float, float, float] | None:
    """The least distance (mm) from the roller's axis line at pose *k* of the edges from *a*
    along *e* (mm, from the pivot) over their stretch beside the roller's length
    (``low ≤ (a + s·e)·axis ≤ high``): of all of them, of those on the + side of the contact
    normal and of those on its − side (inf where there is none); None when no edge lies
    beside it. Each edge's numbers come from its own row alone."""
    axis, n = poses.axis[k], poses.normal[k]
    a_along = a @ axis
    e_along = e @ axis
    with np.errstate(divide="ignore", invalid="ignore"):
        s_low, s_high = (low - a_along) / e_along, (high - a_along) / e_along
    flat = np.abs(e_along) < 1e-12
    first = np.where(flat, 0.0, np.maximum(np.minimum(s_low, s_high), 0.0))
    last = np.where(flat, 1.0, np.minimum(np.maximum(s_low, s_high), 1.0))
    beside = np.flatnonzero((first <= last) & (~flat | ((a_along >= low) & (a_along <= high))))
    if beside.size == 0:
        return None
    # (numpy's take: a copy of the rows, some three times quicker than indexing for them)
    a, e = np.take(a, beside, axis=0), np.take(e, beside, axis=0)
    first, last = first[beside], last[beside]
    # across the axis: a⊥ + s·e⊥, nearest at s = −a⊥·e⊥/|e⊥|², kept on that stretch (a row's
    # product with the axis is the same whichever rows are with it)
    a_across = a - a_along[beside][:, None] * axis
    e_across = e - e_along[beside][:, None] * axis
    with np.errstate(divide="ignore", invalid="ignore"):
        s = -np.einsum("ij,ij->i", a_across, e_across) / np.einsum("ij,ij->i", e_across,
                                                                    e_across)
    s = np.minimum(np.maximum(np.where(np.isnan(s), 0.0, s), first), last)
    radial = a_across + s[:, None] * e_across
    off = norms(radial)
    side = radial @ n
    plus, minus = off[side > 0], off[side < 0]
    return (float(off.min()), float(plus.min()) if plus.size else math.inf,
            float(minus.min()) if minus.size else math.inf)


def _split(edges: Array, longest: float) -> Array:
    """*edges* ((E, 2, 3), mm) cut into pieces no longer than *longest* (the same lines)."""
    length = np.linalg.norm(edges[:, 1] - edges[:, 0], axis=1)
    pieces = np.maximum(1, np.ceil(length / longest).astype(np.intp))
    if int(pieces.max(initial=1)) == 1:
        return edges
    owner = np.repeat(np.arange(len(edges)), pieces)
    index = np.arange(owner.size) - np.repeat(np.cumsum(pieces) - pieces, pieces)
    f0 = (index / pieces[owner])[:, None]
    f1 = ((index + 1) / pieces[owner])[:, None]
    a, b = edges[owner, 0], edges[owner, 1]
    return np.stack((a + f0 * (b - a), a + f1 * (b - a)), axis=1)


def _run(polar: Array, at: float, half: float) -> tuple[int, int, bool] | None:
    """The sorted angles *polar* (rad, −π..π) within *half* of *at*: from index i to j, or,
    across ±π, from i to the end and from the start to j (None: all of them)."""
    if half >= math.pi:
        return None
    lo = (at - half + math.pi) % (2 * math.pi) - math.pi
    hi = (at + half + math.pi) % (2 * math.pi) - math.pi
    i, j = np.searchsorted(polar, [lo, hi])
    return int(i), int(j), lo > hi


def _runs(polar: Array, at: float, half: float) -> list[slice]:
    """The sorted angles *polar* (rad, −π..π) within *half* of *at*, as one or two slices."""
    run = _run(polar, at, half)
    if run is None:
        return [slice(0, polar.size)]
    i, j, across = run
    return [slice(i, polar.size), slice(0, j)] if across else [slice(i, j)]


def _window(polar: Array, at: float, half: float) -> Array:
    """Indices of the sorted angles *polar* (rad, −π..π) within *half* of *at*, across ±π."""
    run = _run(polar, at, half)
    if run is None:
        return np.arange(polar.size)
    i, j, across = run
    if not across:
        return np.arange(i, j)
    return np.concatenate((np.arange(i, polar.size), np.arange(0, j)))


def _inside(index: Array, polar: Array, at: float, half: float) -> Array:
    """Which of *index* (into the sorted angles *polar*) :func:`_window` picks."""
    run = _run(polar, at, half)
    if run is None:
        return np.ones(index.shape, dtype=bool)
    i, j, across = run
    if not across:
        return (index >= i) & (index < j)
    return (index >= i) | (index < j)


def near_roller(blank: GloboidCam, points: Array) -> Array:
    """Which of *points* (mm, on the cam) the roller can come near at some pose: within its
    radius (and 1 mm) of the stretch of the pivot's circles its contact line sweeps, judged in
    each point's plane through the cam axis by its distance from the pivot there."""
    g = blank.follower
    ends = blank.contact(2)
    r = np.hypot(points[:, 0], points[:, 1])
    x = g.centre - r if blank.inward > 0 else g.centre + r
    d = np.hypot(x, points[:, 2])
    margin = g.radius + 1.0
    inside = (d >= float(np.min(ends)) - margin) & (d <= float(np.max(ends)) + margin)
    return inside


def mesh_edges(vertices: Array, pairs: Index, keep: Array | None = None) -> Array:
    """The mesh's edges *pairs* (each once, (E, 2) vertex indices) as (E, 2, 3) end points
    (mm): of those with an end among the vertices *keep* (a mask; all by default)."""
    if keep is not None:
        pairs = pairs[keep[pairs[:, 0]] | keep[pairs[:, 1]]]
    return vertices[pairs]
