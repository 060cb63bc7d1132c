"""Array type names used across camfab (float arrays, boolean masks and index arrays), and the
runs of a mask."""

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
