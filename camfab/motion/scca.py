"""Sine–constant–cosine acceleration (SCCA) laws in closed form.

The acceleration shape, with b + c + d = 1, is sin(πu/b) on [0, b/2]; +1 on [b/2, (1−d)/2];
cos((π/d)(u − (1−d)/2)) on [(1−d)/2, (1+d)/2]; −1 on [(1+d)/2, 1 − b/2]; sin((π/b)(u − 1)) on
[1 − b/2, 1], scaled so that f(1) = 1. Each zone's acceleration has the form
α + β·sin(kt) + γ·cos(kt) with t the distance into the zone, integrated exactly twice here.
Special cases: cycloidal (b = ½, c = 0, d = ½), harmonic (b = c = 0, d = 1), uniform
acceleration (c = 1), modified trapezoid (¼, ½, ¼), modified sine (¼, 0, ¾).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from camfab.motion.law import Array, Law, as_unit_array


@dataclass(frozen=True)
class _Zone:
    start: float
    alpha: float  # constant part of the acceleration shape
    beta: float  # coefficient of sin(k t)
    gamma: float  # coefficient of cos(k t)
    k: float  # angular rate (k = 1 with beta = gamma = 0 for constant zones)
    v0: float  # unscaled velocity at the zone start
    f0: float  # unscaled displacement at the zone start

    def values(self, t: Array) -> Array:
        """Unscaled f, f′, f″, f‴ at distance *t* into the zone."""
        a, b, g, k = self.alpha, self.beta, self.gamma, self.k
        s, c = np.sin(k * t), np.cos(k * t)
        acc = a + b * s + g * c
        vel = self.v0 + a * t + (b / k) * (1.0 - c) + (g / k) * s
        disp = (self.f0 + self.v0 * t + a * t * t / 2.0
                + (b / k) * (t - s / k) + (g / k**2) * (1.0 - c))
        jerk = b * k * c - g * k * s
        return np.stack([disp, vel, acc, jerk])


class SCCA(Law):
    """The SCCA law with fractions *b*, *c*, *d* (b + c + d = 1)."""

    def __init__(self, b: float, c: float, d: float, name: str = "scca") -> None:
        if min(b, c, d) < 0 or not math.isclose(b + c + d, 1.0, abs_tol=1e-12):
            raise ValueError(f"SCCA needs b, c, d >= 0 with b + c + d = 1 (got {b}, {c}, {d})")
        self.name = name
        self.b, self.c, self.d = b, c, d
        pieces = [  # (width, alpha, beta, gamma, k)
            (b / 2, 0.0, 1.0, 0.0, math.pi / b if b else 1.0),
            (c / 2, 1.0, 0.0, 0.0, 1.0),
            (d, 0.0, 0.0, 1.0, math.pi / d if d else 1.0),
            (c / 2, -1.0, 0.0, 0.0, 1.0),
            (b / 2, 0.0, 0.0, -1.0, math.pi / b if b else 1.0),
        ]
        zones: list[_Zone] = []
        start, v0, f0 = 0.0, 0.0, 0.0
        for width, alpha, beta, gamma, k in pieces:
            if width <= 0:
                continue
            zone = _Zone(start, alpha, beta, gamma, k, v0, f0)
            zones.append(zone)
            end = zone.values(np.array([width]))[:, 0]
            start, f0, v0 = start + width, float(end[0]), float(end[1])
        self._zones = tuple(zones)
        self._scale = 1.0 / f0  # makes f(1) = 1
        self.breakpoints = tuple(z.start for z in zones[1:])
        # With no cosine zone (d = 0) the acceleration jumps from +1 to -1 at u = 1/2.
        self.inner_step_order = 2 if (d == 0 and c > 0) else None

    def evaluate(self, u: ArrayLike) -> Array:
        u = as_unit_array(u)
        starts = np.array([z.start for z in self._zones])
        index = np.clip(np.searchsorted(starts, u, side="right") - 1, 0, len(self._zones) - 1)
        out = np.empty((4, u.size))
        for i, zone in enumerate(self._zones):
            mask = index == i
            if mask.any():
                out[:, mask] = zone.values(u[mask] - zone.start)
        return out * self._scale

    def _peaks(self) -> tuple[float, float, float]:
        cv = float(self.evaluate(np.array([0.5]))[1, 0])  # velocity peaks at mid-rise
        ca = self._scale  # the acceleration shape peaks at 1
        rates = [z.k for z in self._zones if z.beta or z.gamma]
        cj = self._scale * max(rates) if rates else 0.0
        return (cv, ca, cj)
