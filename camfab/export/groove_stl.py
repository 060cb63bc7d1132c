"""``NAME.stl`` of a groove cam: the plate with the groove pocketed into its face (binary, mm).

manifold3d extrudes the plate (the outer circle with the bore and keyway as holes) from z = 0 to
the thickness, extrudes the band between the groove's walls from the groove's floor to above the
face, and subtracts it once; the solid stays a closed 2-manifold with outward normals. The walls
are the tolerance-sampled chains, the circles cut into chords within the same tolerance.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from camfab.export.stl import binary_stl, chain_length, hole_points, holes_area
from camfab.geometry.sampling import arc_points

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.geometry.plate import Contours

#: How far the pocket's cutting body reaches above the face (mm), so the boolean never meets
#: two coplanar faces.
_OVERSHOOT_MM = 1.0


def render_groove_stl(analysis: Analysis, holes: Contours) -> bytes:
    """The binary STL of the groove cam's plate with its *holes* (mm) through and the groove
    pocketed from the front face (z = thickness) down to the groove's floor."""
    import manifold3d
    import trimesh  # noqa: F401  (before manifold3d computes: see export.stl)

    geom, walls = analysis.geometry, analysis.groove
    assert geom is not None and walls is not None
    tol = geom.tolerance
    rim = arc_points(np.zeros(2), np.array([walls.outer_radius, 0.0]), 2 * math.pi, tol)[:-1]
    plate = manifold3d.Manifold.extrude(
        manifold3d.CrossSection([rim, *hole_points(holes, tol)], manifold3d.FillRule.EvenOdd),
        walls.thickness)
    band = manifold3d.CrossSection([walls.outer_points, walls.inner_points],
                                   manifold3d.FillRule.EvenOdd)
    pocket = manifold3d.Manifold.extrude(band, walls.depth + _OVERSHOOT_MM).translate(
        (0.0, 0.0, walls.thickness - walls.depth))
    return binary_stl(plate - pocket)


def groove_volume(analysis: Analysis, holes: Contours) -> tuple[float, float]:
    """The part's volume (mm³) from the exact circles and holes and the walls' areas (their arcs
    included), and the allowance for the tolerance along every contour through its height
    (mm³)."""
    geom, walls = analysis.geometry, analysis.groove
    assert geom is not None and walls is not None
    t, d = walls.thickness, walls.depth
    hole_area = holes_area(holes)
    groove_area = walls.outer.area - walls.inner.area
    volume = (math.pi * walls.outer_radius**2 - hole_area) * t - groove_area * d
    chains = hole_points(holes, geom.tolerance)
    through = 2 * math.pi * walls.outer_radius + sum(chain_length(c) for c in chains)
    pocket = chain_length(walls.outer_points) + chain_length(walls.inner_points)
    tolerance = analysis.design.manufacturing.tolerance
    return volume, tolerance * (through * t + pocket * d)
