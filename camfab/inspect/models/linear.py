"""A linear cam's plate for inspecting a scan of it (:class:`LinearScan`): its profile sampled
exactly, and the follower run over it (frame and closed forms of :mod:`camfab.geometry.linear`).

The plate lies in the XY plane, its base line on y = 0, extruded from z = 0 to its thickness (its
STL's frame); it slides along X, so a scan of it is placed by a shift along X where a turning
cam's is placed by a turn (``slides``). The rows are the cycle angles θ of the design's program,
each at travel u = θ·stroke/2π: row *i* is the follower's contact with the working curve at
travel uᵢ, its columns through the plate's thickness, its normals the profile's, out of the
plate. The follower's coordinate q is the lift s (mm): its trace point at height base_height + q
over x = u. A roller of radius R touches a point (x, y) of the plate when its centre is
√(R² − (x − u)²) above it; a knife touches the profile's height at x = u (each column's nodes
joined by straight lines).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from camfab.arrays import Array, Index
from camfab.curves.plane import perp
from camfab.errors import InspectionError
from camfab.inspect.surface import ACROSS_STEP_MM, MIN_COLUMNS, FlankGrid, windowed_run
from camfab.motion.program import cycle_angles

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.geometry.linear import LinearCam


@dataclass(frozen=True, eq=False)
class LinearScan:
    """The linear cam's profile as :class:`~camfab.inspect.surface.ScanModel` (see the
    module)."""

    cam: LinearCam
    theta: Array
    motion: Array
    flanks: tuple[FlankGrid, ...]
    analysis: Analysis = field(repr=False)
    clearance: float = 0.0
    q_scale: float = 1.0
    q_unit: str = "mm"
    map_u_label: str = "travel along the plate (mm)"
    #: A scan of it is placed by a shift along X, not a turn about Z.
    slides: bool = True

    @property
    def map_u(self) -> Array:
        return self.cam.travel(self.theta)

    def design(self) -> Array:
        return self.motion[0]

    def run(self, flank: FlankGrid, points: Array) -> Array:
        cam = self.cam
        if cam.radius == 0.0:
            return self._knife(points)
        spacing = cam.stroke / self.theta.size
        window = math.ceil(cam.radius / spacing) + 2
        return windowed_run(points, self.theta, flank.side, window, self._bounds)

    def _bounds(self, points: Array, theta: Array, side: int) -> Array:
        """The lift (mm) at which the roller over travel θ·stroke/2π touches *points*."""
        cam = self.cam
        dx = points[..., 0] - cam.travel(theta)
        rise = np.sqrt(cam.radius * cam.radius - dx * dx)  # NaN off the roller's footprint
        return points[..., 1] + rise - cam.base_height

    def _knife(self, points: Array) -> Array:
        """The knife's lift (mm) at each row's travel: the highest column's profile height
        there, each column's scanned nodes joined by straight lines."""
        u = self.cam.travel(self.theta)
        best = np.full(u.size, -np.inf)
        for column in range(points.shape[1]):  # a few tens of columns; the rows vectorised
            x, y = points[:, column, 0], points[:, column, 1]
            known = np.isfinite(x) & np.isfinite(y)
            if np.count_nonzero(known) < 2:
                continue
            order = np.argsort(x[known], kind="stable")
            xs, ys = x[known][order], y[known][order]
            height = np.interp(u, xs, ys, left=np.nan, right=np.nan)
            best = np.fmax(best, height)
        return np.where(np.isfinite(best), best - self.cam.base_height, np.nan)

    def pressure_angle(self, q: Array, dq: Array) -> Array:
        return np.arctan(dq * self.cam.k)

    def reference_mesh(self) -> tuple[Array, Index]:
        return self._mesh

    @cached_property
    def _mesh(self) -> tuple[Array, Index]:
        from camfab.inspect.models.part_mesh import part_mesh

        return part_mesh(self.analysis)


def scan_model(analysis: Analysis, step: float) -> LinearScan:
    """The linear cam of *analysis* sampled on rows *step* rad of cycle angle apart.

    Raises
    ------
    InspectionError
        The design gives no thickness (camfab makes no plate to hold a scan to).
    """
    geom, design = analysis.linear, analysis.design
    assert geom is not None, "a linear cam's analysis has its geometry"
    thickness = design.cam.thickness
    if thickness is None:
        raise InspectionError(design.source or design.name, "cam.thickness is not given: "
                              "camfab makes no plate of this design to hold a scan to")
    cam = geom.cam
    theta = cycle_angles(step)
    motion = analysis.program.evaluate(theta)
    working = cam.working(cam.travel(theta), motion)
    normal = perp(cam.pitch(cam.travel(theta), motion).tangent)  # (−s_x, 1)/√…: out of it
    columns = max(MIN_COLUMNS, math.ceil(thickness / ACROSS_STEP_MM) + 1)
    z = np.linspace(0.0, thickness, columns)
    shape = (theta.size, columns)
    points = np.stack((np.broadcast_to(working.xy[:, None, 0], shape),
                       np.broadcast_to(working.xy[:, None, 1], shape),
                       np.broadcast_to(z, shape)), axis=-1)
    normals = np.stack((np.broadcast_to(normal[:, None, 0], shape),
                        np.broadcast_to(normal[:, None, 1], shape),
                        np.zeros(shape)), axis=-1)
    flank = FlankGrid("profile", -1, np.ascontiguousarray(points),
                      np.ascontiguousarray(normals), z)
    return LinearScan(cam, theta, motion, (flank,), analysis)
