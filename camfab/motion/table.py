"""``table`` motion law: the designer's points through an interpolating quintic spline.

A quintic B-spline through the points with the first and second derivative fixed at both ends is
C⁴ inside, so velocity, acceleration and jerk are continuous; with zero end derivatives (the
default) the segment also meets dwells without a step in velocity or acceleration. scipy is
imported only when a design uses a table.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from camfab.motion.law import Array, Law, as_unit_array


class SplineLaw(Law):
    """f(u) through normalised points (uᵢ, fᵢ) with end derivatives f′, f″ given.

    Parameters
    ----------
    u, f
        Normalised abscissae (strictly increasing from 0 to 1) and values (0 to 1).
    start, end
        (f′, f″) at u = 0 and u = 1.
    """

    name = "table"

    def __init__(
        self,
        u: Sequence[float],
        f: Sequence[float],
        start: tuple[float, float] = (0.0, 0.0),
        end: tuple[float, float] = (0.0, 0.0),
    ) -> None:
        from scipy.interpolate import PPoly, make_interp_spline

        x = np.asarray(u, dtype=np.float64)
        y = np.asarray(f, dtype=np.float64)
        bc = ([(1, start[0]), (2, start[1])], [(1, end[0]), (2, end[1])])
        self._spline: Any = make_interp_spline(x, y, k=5, bc_type=bc)
        self._derivatives = [self._spline.derivative(n) if n else self._spline for n in range(4)]
        self._ppoly: Any = PPoly.from_spline(self._spline)
        self.breakpoints = tuple(float(v) for v in x[1:-1])

    def evaluate(self, u: ArrayLike) -> Array:
        u = as_unit_array(u)
        return np.stack([np.asarray(d(u), dtype=np.float64) for d in self._derivatives])

    def _peaks(self) -> tuple[float, float, float]:
        peaks = []
        for order in (1, 2, 3):
            candidates = [0.0, 1.0, *self.breakpoints]
            roots = self._ppoly.derivative(order + 1).roots(extrapolate=False)
            candidates.extend(float(r) for r in np.atleast_1d(roots) if np.isfinite(r))
            values = self._ppoly.derivative(order)(np.clip(candidates, 0.0, 1.0))
            peaks.append(float(np.max(np.abs(values))))
        return (peaks[0], peaks[1], peaks[2])
