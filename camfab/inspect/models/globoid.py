"""A globoidal cam's scan model: the groove's two walls sampled exactly, and the gauge roller on
its swinging arm run over them (:class:`~camfab.inspect.surface.ScanModel`).

The follower's coordinate q is the arm's angle ψ = ψ₀ + s(θ) from the line of centres (rad,
growing toward +Z: :mod:`camfab.geometry.globoid`). Row *i* of each wall is the roller's contact
line at cam angle θᵢ, from the same :meth:`~camfab.geometry.globoid.Globoid.across` the groove's
tube is built from; its columns run along the roller's working length, from its end nearest the
groove's floor outward as far as both walls stay inside the blank at every cam angle.

The run: in the frame at cam angle θ, a point at (ρ, β, h) in cylindrical coordinates about the
pivot axis (ρ from it, β the angle from the line of centres as ψ is measured, h along the pivot
axis) stands ρ² sin²(β − ψ) + h² from the roller's axis swung to ψ, squared: the gauge roller
(the wall's radius R, the roller's and half the groove's clearance) touches it when that is R²,
at ψ = β ∓ asin(√(R² − h²) / ρ), where it lies √(ρ² − R² + h²) along the roller from the pivot:
only points beside the roller's length count.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from camfab.inspect.surface import ACROSS_STEP_MM, MIN_COLUMNS, FlankGrid, windowed_run

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.arrays import Array, Index
    from camfab.geometry.globoid_cam import GloboidCam

#: How far beyond the gauge roller's radius (mm) a point moved off the design's wall is still
#: sought in the run's window of rows: deviations of a made part are well inside it.
WINDOW_MARGIN_MM = 1.0
#: Slack (mm) on the roller's ends for the points at its ends: their distance along it is
#: computed, and rounds either way of the end itself.
END_SLACK_MM = 1e-6

#: The walls: their name for the report, and their side (−1: it pushes the arm toward +ψ).
WALLS = (("raising wall", -1), ("lowering wall", 1))


@dataclass(frozen=True, eq=False)
class GloboidScan:
    """A globoidal cam's scan model (ScanModel): its walls at the cam angles ``theta`` (rad),
    the arm's swing ψ as the follower's coordinate (rad).

    Attributes
    ----------
    theta
        (R,) the rows' cam angles (rad).
    flanks
        The groove's two walls, side −1 (behind the roller as ψ grows) and +1.
    q_scale
        mm per radian of swing: the middle of the roller's working length from the pivot.
    clearance
        The groove's clearance as a swing at that distance (rad).
    map_u
        (R,) the rows' cam angles (°).
    blank
        The cam (follower and blank) the walls are of.
    motion
        (4, R) s, s′, s″, s‴ of the swing at ``theta``.
    window
        Rows either side of a row whose points the gauge roller can reach at its angle.
    analysis
        The design's analysis, for the part's mesh.
    """

    theta: Array
    flanks: tuple[FlankGrid, ...]
    q_scale: float
    clearance: float
    map_u: Array
    blank: GloboidCam
    motion: Array
    window: int
    analysis: Analysis = field(repr=False)
    q_unit: str = "rad"
    map_u_label: str = "cam angle (°)"

    def design(self) -> Array:
        """The design's swing ψ = ψ₀ + s at ``theta`` (rad)."""
        return self.blank.follower.rest + self.motion[0]

    def run(self, flank: FlankGrid, points: Array) -> Array:
        """The gauge roller run over *points* ((R, C, 3) mm, *flank*'s grid moved; NaN where
        unscanned): at each row's cam angle the bound of ψ (rad) the points give, the largest
        for side −1, the smallest for +1 (NaN where none bounds it)."""
        return windowed_run(points, self.theta, flank.side, self.window, self.bounds)

    def bounds(self, points: Array, theta: Array, side: int) -> Array:
        """The swing ψ (rad) at which the gauge roller touches each of *points* (..., 3, mm on
        the cam) at the cam angles *theta* (rad, broadcast with the points' leading shape) from
        the wall of *side* (−1: the point behind the roller as ψ grows, +1: ahead of it); NaN
        where it never does, or only beyond the roller's ends."""
        g = self.blank.follower
        turned = g.sigma * np.asarray(theta)
        c, s = np.cos(turned), np.sin(turned)
        x, y, z = points[..., 0], points[..., 1], points[..., 2]
        # the point in the frame (Rot_z(σθ)), about the pivot at (C, 0, 0)
        back = g.centre - (c * x - s * y)  # ρ cos β
        h = s * x + c * y  # along the pivot axis
        across2 = g.radius * g.radius - h * h  # (√(R² − h²))²
        along2 = back * back + z * z - across2  # ρ² − R² + h²
        low, high = self.roller_span
        with np.errstate(invalid="ignore"):
            across, along = np.sqrt(across2), np.sqrt(along2)
            # β − side·atan2(√(R² − h²), √(ρ² − R² + h²)), as one angle: arg((ρ cos β + iz)
            # (along − i·side·across)) (both well inside ±π/2)
            swing = np.arctan2(z * along - side * back * across, back * along + side * z * across)
            touches = (across2 >= 0.0) & (along >= low) & (along <= high)
        return np.where(touches, swing, np.nan)

    @cached_property
    def roller_span(self) -> tuple[float, float]:
        """The roller's ends along its axis from the pivot (mm), nearest first."""
        ends = self.blank.follower.ells(2)
        return float(ends.min()) - END_SLACK_MM, float(ends.max()) + END_SLACK_MM

    def pressure_angle(self, q: Array, dq: Array) -> Array:
        """|α| (rad) at the middle of the roller's working length (``q_scale`` from the pivot)
        with the arm at *q* (rad) swinging *dq* per radian of cam angle: tan α = |ψ′|ℓ /
        |C − ℓ cos ψ|."""
        return self.blank.follower.pressure_angle(np.asarray(self.q_scale), q, dq)

    def reference_mesh(self) -> tuple[Array, Index]:
        """The part as camfab builds it (mm, the STL's frame): (V, 3) vertices and (F, 3)
        faces of the solid the STL writer makes, read back as the STL file is."""
        return self._mesh

    @cached_property
    def _mesh(self) -> tuple[Array, Index]:
        from camfab.errors import InspectionError
        from camfab.inspect.models.part_mesh import part_mesh
        from camfab.kinds import kind_of

        mesh = part_mesh(self.analysis)
        if not len(mesh[1]):  # (a flank folds: see the undercut check)
            withheld = kind_of(self.analysis.design.cam.type).part(self.analysis).withheld
            raise InspectionError(self.analysis.design.source or self.analysis.design.name,
                                  "camfab makes no solid of this design to hold a scan to: "
                                  + withheld.get("stl", "none is made"))
        return mesh


def scan_model(analysis: Analysis, step: float) -> GloboidScan:
    """The scan model of a globoidal cam's *analysis*, its rows *step* rad of cam angle apart
    over the turn (see :class:`GloboidScan`)."""
    dense = analysis.globoid
    assert dense is not None
    blank = dense.blank
    theta = step * np.arange(round(2 * math.pi / step))
    motion = analysis.program.evaluate(theta)
    ells = working_ells(blank, theta, motion)
    middle = 0.5 * float(ells[0] + ells[-1])
    flanks = tuple(wall_grid(blank, theta, motion, ells, name, side) for name, side in WALLS)
    clearance = analysis.design.follower.groove_clearance or 0.0
    return GloboidScan(theta, flanks, middle, clearance / middle, np.degrees(theta), blank,
                       motion, window_rows(blank, flanks, theta), analysis)


def working_ells(blank: GloboidCam, theta: Array, motion: Array) -> Array:
    """Distances from the pivot (mm) along the roller's working length, from its end inside
    the groove (nearest the floor) out to where both walls leave the blank at some cam angle
    of *theta* (their *motion*, (4, R); :func:`wall_span`): at most :data:`ACROSS_STEP_MM`
    apart and at least :data:`MIN_COLUMNS` of them, an odd count (the middle one is the
    length's middle, ``q_scale`` from the pivot)."""
    inner, top = wall_span(blank, theta, motion)
    count = max(MIN_COLUMNS, math.ceil(abs(top - inner) / ACROSS_STEP_MM) + 1)
    count += 1 - count % 2
    return np.linspace(inner, top, count)


def wall_span(blank: GloboidCam, theta: Array, motion: Array) -> tuple[float, float]:
    """The stretch of the roller (mm from the pivot) its walls are made over at every cam
    angle of *theta* (their *motion*): from its end inside the groove out to its other end or
    as far toward it as every point of both walls stays inside the blank. (A wall's point
    stands off the roller's axis along the contact normal, by the roller's radius: the walls
    leave the blank's surface a little before or after the roller's axis does.)"""
    g = blank.follower
    start, inner = blank.roller_outer, blank.roller_inner
    t, m = theta[:, None], motion[:, :, None]
    sides = np.array([1.0, -1.0])[None, :]

    def depth(ell: float) -> float:
        """The least depth (mm) in the blank of both walls' points at *ell* over the turn."""
        return float(np.min(blank_depth(blank, g.across(t, np.asarray(ell), m, sides))))

    if depth(start) >= 0.0:
        return inner, start
    deep = inner  # (the roller's inner end lies deep in the groove: its walls in the blank)
    for _ in range(50):  # bisection to well under a nanometre
        middle = 0.5 * (deep + start)
        if depth(middle) >= 0.0:
            deep = middle
        else:
            start = middle
    return inner, deep


def blank_depth(blank: GloboidCam, points: Array) -> Array:
    """How deep (mm) each of *points* (..., 3, on the cam) lies inside the blank's surface
    (negative outside it): in the point's plane through the cam axis, the surface is the circle
    of radius ``surface`` about the pivot, the cam's inside beyond it (concave) or within it
    (convex)."""
    g = blank.follower
    radius = np.hypot(points[..., 0], points[..., 1])
    pivot = np.hypot(radius - blank.inward * g.centre, points[..., 2])
    return blank.inward * (pivot - blank.surface)


def wall_grid(blank: GloboidCam, theta: Array, motion: Array, ells: Array, name: str,
              side: int) -> FlankGrid:
    """The wall of *side* (−1: behind the roller as ψ grows, +1: ahead) at the cam angles
    *theta* (rad; their *motion*, (4, R)) and the distances *ells* (mm) from the pivot: points
    on the cam (mm), unit normals toward the roller's axis (out of the material), and each
    column's distance from the groove's floor (mm)."""
    g = blank.follower
    # the contact normal n has the sign of σ(C − ℓ cos ψ) along the swing, C − ℓ cos ψ that
    # of ``inward`` (the roller never crosses the cam axis): the wall ahead is along n·σ·inward
    u = side * g.sigma * blank.inward
    t, e, m = theta[:, None], ells[None, :], motion[:, :, None]
    points = g.across(t, e, m, u)
    axis = g.across(t, e, m, 0.0)
    normals = (axis - points) / g.radius
    across = blank.inward * (blank.floor - ells)
    return FlankGrid(name, side, points, normals, across)


def window_rows(blank: GloboidCam, flanks: tuple[FlankGrid, ...], theta: Array) -> int:
    """Rows either side of a row (count) over which the cam turns every point of its walls
    (and any :data:`WINDOW_MARGIN_MM` off them) out of the gauge roller's reach: a point r
    from the cam axis, at the polar angle φ from the plane of the arm in the frame at its own
    row, stays within the roller's radius R of that plane only while the cam turns by no more
    than |φ| + asin(R / r)."""
    g = blank.follower
    step = float(theta[1] - theta[0])
    widest = 0.0
    for flank in flanks:
        # each row in the frame, turned by σθ: its distance from the plane of the arm
        turned = g.sigma * theta[:, None]
        x, y = flank.points[..., 0], flank.points[..., 1]
        radius = np.hypot(x, y)
        polar = np.arcsin(np.clip((np.sin(turned) * x + np.cos(turned) * y) / radius, -1, 1))
        reach = np.arcsin(np.minimum(1.0, (g.radius + WINDOW_MARGIN_MM) / radius))
        widest = max(widest, float(np.max(np.abs(polar) + reach)))
    return min(math.ceil(widest / step) + 1, theta.size // 2)
