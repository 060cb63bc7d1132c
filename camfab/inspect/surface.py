"""The exact functional surfaces of a cam, sampled for inspecting a scan of it, and the follower
run over them (``FlankGrid``, ``ScanModel``, ``windowed_run``).

A *flank* is one surface the follower rides on: a drum's or globoid's lower and upper groove
wall, a groove plate's inner and outer wall, a disc cam's profile, each plate of a conjugate
pair. It is sampled on a grid: row *i* is the line the follower touches at cam angle
``theta[i]`` (the flank's contact line there), column *j* a position across the flank
(``across[j]``, mm: from the groove's floor outward, or through a plate's thickness). Every
flank of a model has the same rows.

The follower's *coordinate* q is what it moves by: a translating follower's height (mm), an
oscillating one's or a globoid turret's swing (rad). A flank bounds it from one side: a flank of
``side`` −1 pushes the follower toward +q (q is at least its bound: a disc cam's profile, a
drum's lower wall), one of ``side`` +1 toward −q (q is at most its bound). Where the part is as
designed, the bound of every flank at cam angle θ is the design's coordinate there.

All lengths are in mm in the cam frame: the cam axis is Z through the origin, the part as drawn
at cam angle 0 (the frame of camfab's own STL files).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from camfab.arrays import Array

#: Largest spacing (mm) of a flank grid's columns (across the flank).
ACROSS_STEP_MM = 0.25

#: Fewest columns of a flank grid.
MIN_COLUMNS = 9


@dataclass(frozen=True)
class FlankGrid:
    """One functional surface, sampled exactly.

    Attributes
    ----------
    name
        What it is, for the report ("lower wall", "profile", "plate a").
    side
        −1: the flank pushes the follower toward +q (its run is a lower bound of q); +1: toward
        −q (an upper bound).
    points
        (R, C, 3) surface points (mm), row *i* touched at cam angle ``theta[i]``.
    normals
        (R, C, 3) unit normals, pointing out of the material (toward the follower).
    across
        (C,) position across the flank of each column (mm), for the deviation maps.
    """

    name: str
    side: int
    points: Array
    normals: Array
    across: Array


#: ``bounds(points, theta)``: the follower coordinate at which the follower touches each point
#: (mm in the cam frame, shape (..., 3)) at the cam angle *theta* (rad, broadcast with the
#: points' leading shape), seen from a flank of the given side; NaN where the follower cannot
#: touch the point at that angle (it lies beyond the roller's length, or off its footprint).
Bounds = Callable[[Array, Array, int], Array]


class ScanModel(Protocol):
    """What a kind of cam supplies for inspecting a scan of it."""

    #: The rows' cam angles (rad), increasing, evenly spaced over [0, 2π).
    theta: Array

    #: The functional surfaces.
    flanks: tuple[FlankGrid, ...]

    #: mm per unit of the follower coordinate q at the trace point (1 for a translating
    #: follower; the arm's or the roller's mean radius for a swing).
    q_scale: float

    #: "mm" or "rad": the unit of q.
    q_unit: str

    #: The play the design gives the real follower between the two sides (q's unit; 0 for a
    #: groove without clearance or a cam with one side). The flanks' runs use a gauge follower
    #: that fills the play (a roller of radius + half the clearance), so on a part as designed
    #: every run is the design's q, and the real follower's play is
    #: ``clearance + upper run − lower run``.
    clearance: float

    #: u (mm) of each row for the deviation maps: the developed length along the cam
    #: (a drum's R·φ, a plate's arc length along its pitch curve), or the cam angle's degrees.
    map_u: Array

    #: What ``map_u`` is, for the axis of the maps ("R·φ at the surface (mm)", "cam angle (°)").
    map_u_label: str

    def design(self) -> Array:
        """The design's follower coordinate q at ``theta`` (mm or rad)."""

    def run(self, flank: FlankGrid, points: Array) -> Array:
        """The follower run over *points* ((R, C, 3), *flank*'s grid with each node moved as the
        scan says; NaN where the scan has no points): the bound of q it gives at each row's cam
        angle (NaN where no point bounds it)."""

    def pressure_angle(self, q: Array, dq: Array) -> Array:
        """The pressure angle (rad) of the motion q(θ) with q′ (per rad) at ``theta``, at the
        flanks' mean depth."""

    def reference_mesh(self) -> tuple[Array, Array]:
        """The whole part as designed (mm, cam frame): a triangle mesh's vertices (V, 3) and
        faces (F, 3), for aligning a free scan (the ends, the bore, the outer surface fix its
        frame) and for setting aside points on no functional surface."""


def windowed_run(points: Array, theta: Array, side: int, window: int, bounds: Bounds) -> Array:
    """A follower run over a flank grid whose rows are touched at *theta*: at each row's angle,
    the extreme (the largest for *side* −1, the smallest for +1) of *bounds* over the points of
    the rows within *window* rows either side (the follower's footprint along the flank).

    *points* is (R, C, 3) with NaN rows or nodes where nothing was scanned; the result (R,) is
    NaN where no point within the window bounds the follower. Work: (2·window + 1)·R·C
    evaluations of *bounds*, vectorised over the grid.
    """
    rows = points.shape[0]
    best = np.full(rows, -np.inf if side < 0 else np.inf)
    pick = np.maximum if side < 0 else np.minimum
    missing = -np.inf if side < 0 else np.inf
    angles = theta[:, None]
    with np.errstate(invalid="ignore"):
        for shift in range(-window, window + 1):
            moved = np.roll(points, -shift, axis=0)  # row i holds row i + shift
            values = bounds(moved, angles, side)
            filled = np.where(np.isfinite(values), values, missing)
            best = pick(best, filled.max(axis=1) if side < 0 else filled.min(axis=1))
    return np.where(np.isfinite(best), best, np.nan)
