"""A drum (cylindrical) cam's groove for inspecting a scan of it: its two walls sampled exactly,
and the gauge roller run over them (THEORY §C; frame of :mod:`camfab.geometry.drum`).

The follower's coordinate q is its lift s (mm along the drum's axis). A wall point at radius r
and polar angle ϕ touches the roller whose axis is the radial line at α = −σθ, at height
start + q, when r²sin²(ϕ − α) + (z − start − q)² = R² with R the wall's distance from the axis
(the roller's radius plus half the groove's clearance) and r cos(ϕ − α) > 0: the lower wall
bounds q from below at q = z + √(R² − w²) − start (w = r sin(ϕ − α)), the upper wall from above
at z − √(R² − w²) − start.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from camfab.arrays import Array, Index
from camfab.geometry.drum import Drum, polar_to_xy
from camfab.inspect.surface import ACROSS_STEP_MM, MIN_COLUMNS, FlankGrid, windowed_run
from camfab.motion.program import cycle_angles

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis




@dataclass(frozen=True)
class DrumScan:
    """The drum's groove as :class:`~camfab.inspect.surface.ScanModel` (see the module)."""

    drum: Drum
    theta: Array
    motion: Array
    flanks: tuple[FlankGrid, ...]
    clearance: float
    analysis: Analysis = field(repr=False)
    q_scale: float = 1.0
    q_unit: str = "mm"
    map_u_label: str = "R·θ at the drum's surface (mm)"

    @property
    def map_u(self) -> Array:
        return self.drum.radius * self.theta

    def design(self) -> Array:
        return self.motion[0]

    def run(self, flank: FlankGrid, points: Array) -> Array:
        """The gauge roller run over *points* ((R, C, 3) mm, *flank*'s grid moved; NaN where
        unscanned): the bound of the lift (mm) they give at each row's cam angle. Each point's
        radius and polar angle are taken once, not once for each row of the roller's window."""
        d = self.drum
        step = float(self.theta[1] - self.theta[0])
        reach = math.asin(min(1.0, d.roller / max(d.root, d.roller)))
        window = math.ceil(reach / step) + 2
        return windowed_run(cylindrical(points), self.theta, flank.side, window, self._bounds)

    def _bounds(self, polar: Array, theta: Array, side: int) -> Array:
        """The lift (mm) at which the gauge roller at cam angles *theta* touches the points
        whose :func:`cylindrical` coordinates are *polar*."""
        d = self.drum
        r, phi, z = polar[..., 0], polar[..., 1], polar[..., 2]
        delta = phi - d.axis_angle(theta)
        w = r * np.sin(delta)
        rise = np.sqrt(d.roller * d.roller - w * w)  # NaN off the roller's footprint
        rise = np.where(r * np.cos(delta) > 0.0, rise, np.nan)
        return z - d.start + (rise if side < 0 else -rise)

    def pressure_angle(self, q: Array, dq: Array) -> Array:
        return self.drum.pressure_angle(dq, self.drum.pitch)

    def reference_mesh(self) -> tuple[Array, Index]:
        return self._mesh

    @cached_property
    def _mesh(self) -> tuple[Array, Index]:
        from camfab.inspect.models.part_mesh import part_mesh

        return part_mesh(self.analysis)


def cylindrical(points: Array) -> Array:
    """(..., 3) points (mm, cam frame) as (..., 3) radius from the drum's axis (mm), polar angle
    ϕ = atan2(−x, y) (rad: the frame of :mod:`camfab.geometry.drum`) and z (mm); NaN stays
    NaN."""
    x, y = points[..., 0], points[..., 1]
    return np.stack((np.hypot(x, y), np.arctan2(-x, y), points[..., 2]), axis=-1)


def scan_model(analysis: Analysis, step: float) -> DrumScan:
    """The drum of *analysis* sampled on rows *step* (rad) apart (see the module)."""
    from camfab.geometry.drum import drum

    design = analysis.design
    d = drum(design)
    theta = cycle_angles(step)
    motion = analysis.program.evaluate(theta)
    columns = max(MIN_COLUMNS, math.ceil(d.depth / ACROSS_STEP_MM) + 1)
    radii = np.linspace(d.root, d.radius, columns)
    s, ds = motion[0][:, None], motion[1][:, None]
    walls = d.walls(theta[:, None], s, ds, radii[None, :])
    centre = d.start + s
    flanks = []
    for name, side, phi, z in (("lower wall", -1, walls.phi_lower, walls.z_lower),
                               ("upper wall", 1, walls.phi_upper, walls.z_upper)):
        xy = polar_to_xy(radii[None, :], phi)
        points = np.concatenate((xy, np.broadcast_to(z, phi.shape)[..., None]), axis=-1)
        # toward the roller's axis: its point nearest the wall point, less the wall point
        along = radii[None, :] * np.cos(phi - d.axis_angle(theta)[:, None])
        foot = np.concatenate((polar_to_xy(along, np.broadcast_to(
            d.axis_angle(theta)[:, None], phi.shape)), np.broadcast_to(
                centre, phi.shape)[..., None]), axis=-1)
        normals = (foot - points) / d.roller
        flanks.append(FlankGrid(name, side, points, normals, radii - d.root))
    clearance = float(design.follower.groove_clearance)
    return DrumScan(d, theta, motion, tuple(flanks), clearance, analysis)
