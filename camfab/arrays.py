"""Array type names used across camfab: float arrays, boolean masks and index arrays."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

#: Floats: points (N, 2), angles (N,), motion (4, N)...
Array = NDArray[np.float64]
#: True/False per element.
Mask = NDArray[np.bool_]
#: Integer positions into another array.
Index = NDArray[np.intp]
