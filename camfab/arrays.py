"""Array type names used across camfab (float arrays, boolean masks and index arrays), the runs
of a mask, and many evenly spaced ranges at once."""

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
