"""``NAME.stl``: the disc-cam plate for 3-D printing (SPEC §5): binary, millimetres, watertight.

manifold3d builds the solid (the outline with the bore and keyway as holes, extruded from z = 0 to
z = thickness), which keeps it a closed 2-manifold with outward normals; trimesh writes the binary
file. Curves are the tolerance-sampled profile; the bore's circle is cut into chords within the
same tolerance.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from camfab.arrays import Array
from camfab.geometry.sampling import arc_points

if TYPE_CHECKING:
    from camfab.geometry.plate import Contours, Plate
    from camfab.pipeline import Analysis


def hole_points(holes: Contours, tolerance: float) -> list[Array]:
    """The holes as closed chains of points (mm), arcs and circles cut into chords within
    *tolerance*."""
    chains = [profile.points(tolerance) for profile in holes.profiles]
    chains += [arc_points(np.zeros(2), np.array([r, 0.0]), 2 * math.pi, tolerance)[:-1]
               for r in holes.circles]
    return chains


def render_stl(analysis: Analysis, plate: Plate) -> bytes | None:
    """The binary STL of the plate, or None when the design gives no ``thickness``."""
    import manifold3d
    import trimesh

    geom, cam = analysis.geometry, analysis.design.cam
    assert geom is not None
    if cam.thickness is None:
        return None
    contours = [geom.profile.ccw().vertices, *hole_points(plate.holes, geom.tolerance)]
    section = manifold3d.CrossSection(contours, manifold3d.FillRule.EvenOdd)
    solid = manifold3d.Manifold.extrude(section, cam.thickness)
    mesh = solid.to_mesh()
    tm = trimesh.Trimesh(np.asarray(mesh.vert_properties)[:, :3], np.asarray(mesh.tri_verts),
                         process=False)
    data = tm.export(file_type="stl")
    assert isinstance(data, bytes)
    return data
