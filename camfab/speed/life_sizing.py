"""The roller bearing's life as a limit of the sizing (:mod:`camfab.analysis.sizing`): the L₁₀
hours at a trial size against ``limits.roller_life``, computed as the build computes them
(:func:`camfab.speed.contact.roller_life`) on the build's grid of cam angles.

The force along the follower's motion does not depend on the cam's size, so it is the one the
contact stress's sizing computes once per sizing (:func:`camfab.speed.stress_sizing.forces`);
at each trial size the normal force (the pressure angle) and the length the roller rolls over
the cam change. A larger cam turns the roller more often for each of its own turns, so its
roller's life in hours mostly falls as the cam grows: the limit bounds the size from above,
and where the sizes it allows are all too small for the other limits, no size meets them all.
Lives in hours, forces in N, lengths in mm.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from camfab.analysis.sizing import Grid, LimitValue
from camfab.arrays import Array
from camfab.speed.contact import trapezoid_weights

if TYPE_CHECKING:
    from camfab.design import Design


@dataclass(frozen=True)
class LifeSide:
    """One side of the cam a roller rides, for :meth:`LifeLimit.at`: +1 where it carries the
    follower when the force along the motion is positive, −1 when negative (*carries*); the
    normal force per newton along the motion and the roller's rolling speed over it (mm/rad),
    (N,) on the sizing's grid; whether the roller rides it loaded or not (*always*: else only
    while it carries)."""

    carries: int
    normal: Array
    rolling: Array
    always: bool = True


@dataclass(frozen=True)
class LifeLimit:
    """What a sizing needs to hold a roller to ``limits.roller_life``: the limit (h), the
    bearing's load rating C (N) and life exponent p, the cam's speed (rpm), the roller's
    radius (mm), and the force along the follower's motion (N) on the build's grid."""

    limit: float
    rating: float
    exponent: float
    speed_rpm: float
    roller_radius: float
    force: Array

    def hours(self, grid: Grid, sides: Sequence[LifeSide]) -> float:
        """L₁₀ (h) of a roller riding *sides* over the build's part of *grid* (the sizing's
        finer grid holds the build's first): ISO 281, L₁₀ = (C/P)ᵖ·10⁶ revolutions, P the
        cubic (p-th power) mean of the normal force weighted by the roller's revolutions."""
        count = self.force.size
        weights = trapezoid_weights(grid.theta[:count])
        turns = np.zeros(count)
        work = np.zeros(count)
        for side in sides:
            carrying = side.carries * self.force > 0.0
            load = np.where(carrying, np.abs(self.force) * side.normal[:count], 0.0)
            rides = np.ones_like(carrying) if side.always else carrying
            step = np.where(rides, side.rolling[:count], 0.0) * weights / (
                2.0 * math.pi * self.roller_radius)
            turns += step
            work += load**self.exponent * step
        total = float(turns.sum())
        if not total > 0.0:
            return math.inf
        equivalent = (float(work.sum()) / total) ** (1.0 / self.exponent)
        if not equivalent > 0.0:
            return math.inf
        return (self.rating / equivalent) ** self.exponent * 1e6 / (
            total * self.speed_rpm * 60.0)

    def at(self, grid: Grid, sides: Sequence[LifeSide], suffix: str = "") -> LimitValue:
        """The life of the roller riding *sides* against the limit."""
        hours = self.hours(grid, sides)
        return LimitValue("roller_life" + suffix, "the roller's bearing life",
                          hours >= self.limit, hours, self.limit, "h", "min")


def life_limit(design: Design, grid_pair: tuple[Grid, Grid]) -> LifeLimit | None:
    """The roller's bearing life as a limit of *design*'s sizing on *grid_pair*, or None
    where the design gives no ``limits.roller_life`` (the design file's rules refuse one whose
    life cannot be computed: no roller, no load rating, no force)."""
    from camfab.speed.stress_sizing import forces

    limit, fol, speed = design.limits.roller_life, design.follower, design.cam.speed_rpm
    if limit is None:
        return None
    assert fol.roller_load_rating is not None and fol.roller_radius is not None
    assert speed is not None
    return LifeLimit(limit, fol.roller_load_rating, fol.life_exponent, speed, fol.roller_radius,
                     forces(design, grid_pair, design.spring is not None)[0])


def offset_rolling(pitch_speed: Array, pitch_radius: Array, distance: float) -> Array:
    """How fast a roller rolls over the curve *distance* (mm) inside a pitch curve of speed
    *pitch_speed* (mm/rad) and signed radius of curvature *pitch_radius* (mm; a negative
    *distance*: outside, a groove's outer wall): the offset curve's speed, |ρ − d|/|ρ| of the
    pitch curve's (:func:`camfab.curves.plane.offset_inward`)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(np.isinf(pitch_radius), 1.0,
                         (pitch_radius - distance) / pitch_radius)
    return pitch_speed * np.abs(ratio)
