"""Array type names used across camfab (float arrays, boolean masks and index arrays), the runs
of a mask, many evenly spaced ranges at once, and the clusters that pairs of indices join."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

#: Floats: points (N, 2), angles (N,), motion (4, N)...
Array = NDArray[np.float64]
#: True/False per element.
Mask = NDArray[np.bool_]
#: Integer positions into another array.
Index = NDArray[np.intp]


def runs(mask: Mask) -> list[tuple[int, int]]:
    """The runs of True in a 1-D *mask*, as (start, stop) index pairs (stop exclusive)."""
    edges = np.flatnonzero(np.diff(np.concatenate(([0], np.asarray(mask, bool).astype(np.int8),
                                                   [0]))))
    return [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2], strict=True)]


def spaced(stop: Array, count: Index) -> tuple[Index, Array]:
    """``np.linspace(0.0, stop[i], count[i])`` for every i at once, concatenated: the range
    each value belongs to, and the values, the same numbers linspace gives (every count at
    least 2, every stop positive)."""
    index = np.repeat(np.arange(len(count)), count)
    first = np.cumsum(count) - count
    k = (np.arange(index.size) - first[index]).astype(np.float64)
    values = k * (stop / (count - 1))[index]
    values[first + count - 1] = stop
    return index, values


def clusters(pairs: Index, count: int) -> tuple[int, Index]:
    """The clusters of *count* points that *pairs* (K, 2) of indices join: their number, and
    each point's cluster (0 up, numbered by the cluster's lowest point).

    Each point takes the lowest label among its pairs' ends, then its label's label (so labels
    halve their way to the lowest of a cluster), until nothing changes: a few rounds of whole
    arrays."""
    label = np.arange(count)
    first, second = pairs[:, 0], pairs[:, 1]
    while True:
        lowest = np.minimum(label[first], label[second])
        new = label.copy()
        np.minimum.at(new, first, lowest)
        np.minimum.at(new, second, lowest)
        new = new[new]
        if np.array_equal(new, label):
            break
        label = new
    roots, numbered = np.unique(label, return_inverse=True)
    return len(roots), numbered.ravel()


def norms(vectors: Array) -> Array:
    """The lengths of 3-vectors along the last axis: their squares summed in the order numpy's
    ``norm`` sums them (the same numbers, bit for bit), some four times quicker."""
    square = vectors * vectors
    return np.sqrt((square[..., 0] + square[..., 1]) + square[..., 2])


def edge_groups(faces: Index, count: int) -> tuple[Index, Index, Index]:
    """The edges of a mesh's (F, 3) *faces* (on *count* vertices): each edge once, as (E, 2)
    vertex indices (the lower first, sorted), the edge of each facet side in turn (3F,: side
    k of a facet runs from its corner k to k + 1), and how many sides each edge has.

    (Each pair of indices made one number, so numpy's unique of numbers finds them: some five
    times quicker than its unique of rows, the same edges in the same order.)"""
    pairs = np.sort(faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1).astype(np.int64)
    span = np.int64(max(count, 1))
    keys, side, sides = np.unique(pairs[:, 0] * span + pairs[:, 1], return_inverse=True,
                                  return_counts=True)
    return (np.column_stack((keys // span, keys % span)).astype(np.intp), side.ravel(),
            sides)


def signed_volume(vertices: Array, faces: Index) -> float:
    """The signed volume (mm³) a closed triangle mesh of (V, 3) *vertices* and (F, 3) *faces*
    encloses: positive when its faces are wound with the normals outward."""
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)
