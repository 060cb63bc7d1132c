"""Chaining open pieces (lines, arcs, open polylines) end to end into closed loops.

A drawing's outline often comes as loose pieces whose ends meet. Their ends are merged into
nodes when they lie within a gap of each other; pieces hanging off the loops (a mark drawn to
the outline, a construction line) are peeled away; what is left falls into connected parts. A
part in which every node joins exactly two pieces is one loop, walked once from its lowest-
numbered piece (so the same pieces give the same loop, in the same order, every time). A part
in which three or more pieces meet at a node is *tangled*: which loops it holds is a search
(ezdxf's edge miner does it, within a time limit), so its pieces are handed back as they are.

Everything but the walks and the peeling is array work; those two visit each piece once.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camfab.arrays import Array, Index, Mask, clusters


@dataclass(frozen=True)
class Chaining:
    """Loops found among pieces, and the pieces of tangled parts.

    Attributes
    ----------
    loops
        Each loop as the pieces' indices in order and, for each, whether it is walked from its
        end to its start.
    tangled
        Indices of the pieces in parts where three or more pieces meet at a node.
    """

    loops: list[tuple[Index, Mask]]
    tangled: Index


def end_nodes(points: Array, gap: float) -> Index:
    """A node number for each of (M, 2) *points*: points within *gap* of each other share one
    (points up to (1 + √2)·*gap* apart may share one too).

    The points are binned into square cells of gap/2 and cells whose centres lie within
    (1 + √2/2)·gap are joined, so the pairs compared per cell stay few however many ends pile up
    at one spot.
    """
    from scipy.spatial import cKDTree

    if len(points) == 0:
        return np.zeros(0, dtype=np.intp)
    cell = 0.5 * gap
    keys = np.floor(points / cell).astype(np.int64)
    cells, inverse = np.unique(keys, axis=0, return_inverse=True)
    centres = (cells + 0.5) * cell
    pairs = cKDTree(centres).query_pairs(gap * (1.0 + math.sqrt(0.5)), output_type="ndarray")
    _, label = clusters(pairs, len(cells))
    return label[np.ravel(inverse)].astype(np.intp)


def chain(starts: Array, ends: Array, gap: float) -> Chaining:
    """The closed loops the pieces from (N, 2) *starts* to (N, 2) *ends* make when ends within
    *gap* meet; a piece whose own ends meet is a loop by itself."""
    count = len(starts)
    if count == 0:
        return Chaining([], np.zeros(0, dtype=np.intp))
    nodes = end_nodes(np.concatenate((starts, ends)), gap)
    a, b = nodes[:count], nodes[count:]
    closed = a == b
    loops = [(np.array([k]), np.array([False])) for k in np.flatnonzero(closed)]
    alive = _peeled(a, b, ~closed)
    part, degree = _parts(a, b, alive)
    in_loop = np.zeros(count, dtype=bool)
    tangled_part = np.zeros(int(part.max(initial=-1)) + 1, dtype=bool)
    if alive.any():
        busiest = np.zeros_like(tangled_part, dtype=np.intp)
        np.maximum.at(busiest, part[alive], np.maximum(degree[a[alive]], degree[b[alive]]))
        tangled_part = busiest > 2
        in_loop[alive] = ~tangled_part[part[alive]]
    loops += _walks(a, b, in_loop)
    tangled = np.flatnonzero(alive & ~in_loop)
    return Chaining(sorted(loops, key=lambda loop: int(loop[0][0])), tangled)


def _incidence(a: Index, b: Index, alive: Mask) -> tuple[Index, Index]:
    """For every node, the pieces (alive ones) that end there: ``pieces[first[v]:first[v + 1]]``.
    """
    index = np.flatnonzero(alive)
    ends = np.concatenate((a[index], b[index]))
    pieces = np.concatenate((index, index))
    order = np.argsort(ends, kind="stable")
    size = int(max(a.max(initial=-1), b.max(initial=-1))) + 1
    first = np.concatenate(([0], np.cumsum(np.bincount(ends, minlength=size))))
    return first, pieces[order]


def _peeled(a: Index, b: Index, alive: Mask) -> Mask:
    """*alive* without the pieces that hang off the loops: repeatedly, any piece with an end
    that no other piece reaches (trees, open paths)."""
    alive = alive.copy()
    first, pieces = _incidence(a, b, alive)
    degree = np.diff(first)
    start, stop, at = first.tolist(), first[1:].tolist(), pieces.tolist()
    node_a, node_b = a.tolist(), b.tolist()
    live = alive.tolist()
    deg = degree.tolist()
    loose = [v for v, d in enumerate(deg) if d == 1]
    while loose:
        v = loose.pop()
        if deg[v] != 1:
            continue
        piece = next(p for p in at[start[v]:stop[v]] if live[p])
        live[piece] = False
        for w in (node_a[piece], node_b[piece]):
            deg[w] -= 1
            if deg[w] == 1:
                loose.append(w)
    return np.array(live, dtype=bool)


def _parts(a: Index, b: Index, alive: Mask) -> tuple[Index, Index]:
    """The connected part of every piece (by its nodes) and every node's number of alive
    pieces."""
    size = int(max(a.max(initial=-1), b.max(initial=-1))) + 1
    ia, ib = a[alive], b[alive]
    degree = np.bincount(ia, minlength=size) + np.bincount(ib, minlength=size)
    _, label = clusters(np.stack((ia, ib), axis=1), size)
    return label[a].astype(np.intp), degree


def _walks(a: Index, b: Index, in_loop: Mask) -> list[tuple[Index, Mask]]:
    """Each loop of the pieces *in_loop* (every node of which joins exactly two of them), walked
    from its lowest-numbered piece, forwards along it."""
    first, pieces = _incidence(a, b, in_loop)
    start, at = first.tolist(), pieces.tolist()
    node_a, node_b = a.tolist(), b.tolist()
    seen = (~in_loop).tolist()
    loops = []
    for origin in np.flatnonzero(in_loop).tolist():
        if seen[origin]:
            continue
        order, backwards = [], []
        piece, reverse = origin, False
        while True:
            seen[piece] = True
            order.append(piece)
            backwards.append(reverse)
            node = node_a[piece] if reverse else node_b[piece]
            one, two = at[start[node]], at[start[node] + 1]
            following = two if one == piece else one
            if following == origin:
                break
            reverse = node_b[following] == node and node_a[following] != node
            piece = following
        loops.append((np.array(order, dtype=np.intp), np.array(backwards, dtype=bool)))
    return loops
