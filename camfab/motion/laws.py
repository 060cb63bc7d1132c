"""The standard motion laws in closed form and the registry of law names.

Each law is a :class:`~camfab.motion.law.Law` (f, f′, f″, f‴ of u ∈ [0, 1]). The peak
coefficients are exact constants; the tests check them against dense sampling and the published
values. ``LAWS`` lists every law a design file may name, with its aliases.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from camfab.motion.law import Array, Law, Mirrored, as_unit_array
from camfab.motion.polynomial import (
    POLYNOMIAL_23,
    POLYNOMIAL_345,
    POLYNOMIAL_4567,
    POLYNOMIAL_56789,
)
from camfab.motion.scca import SCCA

PI = math.pi


class UniformVelocity(Law):
    """f = u: constant velocity; the velocity steps at both ends (impacts)."""

    name = "uniform-velocity"

    def evaluate(self, u: ArrayLike) -> Array:
        u = as_unit_array(u)
        return np.stack([u, np.ones_like(u), np.zeros_like(u), np.zeros_like(u)])

    def _peaks(self) -> tuple[float, float, float]:
        return (1.0, 0.0, 0.0)


class ModifiedUniformVelocity(Law):
    """Uniform velocity with parabolic blends over the fraction *blend* at each end."""

    name = "modified-uniform-velocity"
    inner_step_order = 2

    def __init__(self, blend: float = 0.25) -> None:
        if not 0.0 < blend <= 0.5:
            raise ValueError(f"blend must be in (0, 0.5] (got {blend})")
        self.blend = blend
        self.breakpoints = (blend, 1.0 - blend) if blend < 0.5 else (0.5,)
        self._k = 1.0 / (blend * (1.0 - blend))

    def evaluate(self, u: ArrayLike) -> Array:
        u = as_unit_array(u)
        r, k = self.blend, self._k
        start, end = u < r, u >= 1.0 - r
        w = 1.0 - u
        middle = (u - r / 2) / (1 - r)
        f = np.where(start, k * u * u / 2, np.where(end, 1.0 - k * w * w / 2, middle))
        f1 = np.where(start, k * u, np.where(end, k * w, 1.0 / (1 - r)))
        f2 = np.where(start, k, np.where(end, -k, 0.0))
        return np.stack([f, f1, f2, np.zeros_like(u)])

    def _peaks(self) -> tuple[float, float, float]:
        return (1.0 / (1.0 - self.blend), self._k, 0.0)


class UniformAcceleration(Law):
    """Two parabolas: constant acceleration, then constant deceleration (steps at ½)."""

    name = "uniform-acceleration"
    breakpoints = (0.5,)
    inner_step_order = 2

    def evaluate(self, u: ArrayLike) -> Array:
        u = as_unit_array(u)
        first = u < 0.5
        w = 1.0 - u
        f = np.where(first, 2 * u * u, 1.0 - 2 * w * w)
        f1 = np.where(first, 4 * u, 4 * w)
        f2 = np.where(first, 4.0, -4.0)
        return np.stack([f, f1, f2, np.zeros_like(u)])

    def _peaks(self) -> tuple[float, float, float]:
        return (2.0, 4.0, 0.0)


class Harmonic(Law):
    """Simple harmonic motion f = ½(1 − cos πu)."""

    name = "harmonic"

    def evaluate(self, u: ArrayLike) -> Array:
        x = PI * as_unit_array(u)
        s, c = np.sin(x), np.cos(x)
        return np.stack([0.5 * (1 - c), PI / 2 * s, PI**2 / 2 * c, -(PI**3) / 2 * s])

    def _peaks(self) -> tuple[float, float, float]:
        return (PI / 2, PI**2 / 2, PI**3 / 2)


class Cycloidal(Law):
    """Cycloidal motion f = u − sin(2πu)/(2π)."""

    name = "cycloidal"

    def evaluate(self, u: ArrayLike) -> Array:
        u = as_unit_array(u)
        x = 2 * PI * u
        s, c = np.sin(x), np.cos(x)
        return np.stack([u - s / (2 * PI), 1 - c, 2 * PI * s, 4 * PI**2 * c])

    def _peaks(self) -> tuple[float, float, float]:
        return (2.0, 2 * PI, 4 * PI**2)


_DH_C = (1.0 - math.sqrt(129.0)) / 16.0  # cos(πu) where |f‴| of the double harmonic peaks


class DoubleHarmonic(Law):
    """f = ½[(1 − cos πu) − ¼(1 − cos 2πu)]: for a rise running straight into a mirrored return.

    f″(0) = 0 but f″(1) = −π², so the top of the rise must meet a return, not a dwell.
    """

    name = "double-harmonic"

    def evaluate(self, u: ArrayLike) -> Array:
        x = PI * as_unit_array(u)
        s1, c1, s2, c2 = np.sin(x), np.cos(x), np.sin(2 * x), np.cos(2 * x)
        f = 0.5 * ((1 - c1) - 0.25 * (1 - c2))
        f1 = 0.5 * (PI * s1 - PI / 2 * s2)
        f2 = 0.5 * PI**2 * (c1 - c2)
        f3 = 0.5 * PI**3 * (2 * s2 - s1)
        return np.stack([f, f1, f2, f3])

    def _peaks(self) -> tuple[float, float, float]:
        cv = 3 * PI * math.sqrt(3.0) / 8  # at u = 2/3, where f″ = 0
        cj = 0.5 * PI**3 * math.sqrt(1 - _DH_C**2) * (1 - 4 * _DH_C)
        return (cv, PI**2, cj)

    def for_return(self) -> Law:
        return Mirrored(self)


class Dwell(Law):
    """No motion: used for dwell segments (their height Δ is zero)."""

    name = "dwell"
    top_order = 5

    def derivatives(self, u: ArrayLike, order: int) -> Array:
        return np.zeros((order + 1, as_unit_array(u).size))

    def pieces(self) -> tuple[Array, tuple[Array, ...]]:
        return np.array([0.0, 1.0]), (np.zeros(1),)

    def evaluate(self, u: ArrayLike) -> Array:
        u = as_unit_array(u)
        return np.zeros((4, u.size))

    def _peaks(self) -> tuple[float, float, float]:
        return (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class LawInfo:
    """A law a design may name: canonical name, aliases, parameters, and a one-line summary."""

    name: str
    aliases: tuple[str, ...]
    summary: str
    params: tuple[str, ...] = ()
    continuity: str = ""


LAWS: tuple[LawInfo, ...] = (
    LawInfo("uniform-velocity", ("uniform", "linear"), "constant velocity",
            continuity="velocity steps at the ends (impact)"),
    LawInfo("modified-uniform-velocity", (), "uniform velocity with parabolic blends",
            ("blend",), "acceleration steps (infinite jerk)"),
    LawInfo("uniform-acceleration", ("parabolic", "constant-acceleration"),
            "constant acceleration then deceleration", continuity="acceleration steps"),
    LawInfo("harmonic", ("shm", "simple-harmonic"), "simple harmonic motion",
            continuity="acceleration steps next to dwells"),
    LawInfo("cycloidal", (), "cycloidal motion", continuity="jerk steps next to dwells"),
    LawInfo("polynomial-23", ("cubic",), "2-3 polynomial 3u² − 2u³",
            continuity="acceleration steps at the ends"),
    LawInfo("polynomial-345", (), "3-4-5 polynomial", continuity="jerk steps next to dwells"),
    LawInfo("polynomial-4567", (), "4-5-6-7 polynomial", continuity="jerk continuous"),
    LawInfo("polynomial-56789", (), "5-6-7-8-9 polynomial",
            continuity="four derivatives continuous (a polydyne cam's output)"),
    LawInfo("modified-trapezoid", (), "SCCA b=¼ c=½ d=¼", continuity="jerk steps next to dwells"),
    LawInfo("modified-sine", (), "SCCA b=¼ c=0 d=¾", continuity="jerk steps next to dwells"),
    LawInfo("double-harmonic", (), "rise straight into a mirrored return (no top dwell)",
            continuity="acceleration steps if the top meets a dwell"),
    LawInfo("polynomial", (), "general polynomial from boundary conditions",
            ("start", "end", "points"), "as the boundary conditions make it"),
    LawInfo("table", (), "user points through a quintic spline (C4)",
            ("points", "csv", "start", "end"), "as the end conditions make it"),
    LawInfo("spline", (), "B-spline of an order (default 6: C4) with free control values",
            ("order", "controls", "start", "end"),
            "derivatives to order − 2 as the end conditions make them (0 by default)"),
)

LAW_NAMES: tuple[str, ...] = tuple(info.name for info in LAWS)
ALIASES: dict[str, str] = {alias: info.name for info in LAWS for alias in info.aliases}
LAW_INFO: dict[str, LawInfo] = {info.name: info for info in LAWS}

#: Laws whose f does not depend on anything but an optional blend.
_FIXED: dict[str, Law] = {
    "uniform-velocity": UniformVelocity(),
    "uniform-acceleration": UniformAcceleration(),
    "harmonic": Harmonic(),
    "cycloidal": Cycloidal(),
    "polynomial-23": POLYNOMIAL_23,
    "polynomial-345": POLYNOMIAL_345,
    "polynomial-4567": POLYNOMIAL_4567,
    "polynomial-56789": POLYNOMIAL_56789,
    "modified-trapezoid": SCCA(0.25, 0.5, 0.25, "modified-trapezoid"),
    "modified-sine": SCCA(0.25, 0.0, 0.75, "modified-sine"),
    "double-harmonic": DoubleHarmonic(),
}

DWELL = Dwell()
DEFAULT_BLEND = 0.25


def laws_taking(key: str) -> str:
    """Which laws take the segment key *key*, as a sentence's subject and verb: "the table law
    takes", "the polynomial, table and spline laws take" (empty when none does)."""
    owners = [info.name for info in LAWS if key in info.params]
    if len(owners) < 2:
        return f"the {owners[0]} law takes" if owners else ""
    return f"the {', '.join(owners[:-1])} and {owners[-1]} laws take"


def canonical_law_name(name: str) -> str | None:
    """The canonical name for *name* or an alias of it (case-insensitive), else None."""
    key = name.strip().lower().replace("_", "-").replace(" ", "-")
    if key in LAW_INFO:
        return key
    return ALIASES.get(key)


def standard_law(name: str, blend: float | None = None) -> Law:
    """The law called *name* (canonical or alias) that needs no design-specific data."""
    canonical = canonical_law_name(name)
    if canonical == "modified-uniform-velocity":
        return ModifiedUniformVelocity(DEFAULT_BLEND if blend is None else blend)
    if canonical in _FIXED:
        return _FIXED[canonical]
    raise KeyError(f"{name!r} is not a standard law")
