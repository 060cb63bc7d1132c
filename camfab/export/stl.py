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
from camfab.geometry.profile import Profile
from camfab.geometry.sampling import arc_points

if TYPE_CHECKING:
    from camfab.pipeline import Analysis


def flatten(profile: Profile, tolerance: float) -> Array:
    """A contour's points with its arcs cut into chords within *tolerance* (mm)."""
    arcs = profile.arcs()
    arc_at = {int(i): k for k, i in enumerate(arcs.index)}
    pieces = []
    for i, vertex in enumerate(profile.vertices):
        k = arc_at.get(i)
        if k is None:
            pieces.append(vertex[None, :])
        else:
            pieces.append(arc_points(arcs.centre[k], vertex, float(arcs.sweep[k]), tolerance)[:-1])
    return np.concatenate(pieces)


def bore_points(analysis: Analysis, tolerance: float) -> Array | None:
    """The bore (and keyway) as a closed chain of points (mm), or None without a bore."""
    from camfab.export.dxf import bore_contour

    cam = analysis.design.cam
    if cam.bore is None:
        return None
    keyway = None if cam.keyway is None else (cam.keyway.width, cam.keyway.depth)
    hole = bore_contour(cam.bore, keyway)
    if hole is None:
        r = cam.bore / 2.0
        return arc_points(np.zeros(2), np.array([r, 0.0]), 2 * math.pi, tolerance)[:-1]
    return flatten(hole, tolerance)


def render_stl(analysis: Analysis) -> bytes | None:
    """The binary STL of the plate, or None when the design gives no ``thickness``."""
    import manifold3d
    import trimesh

    geom, cam = analysis.geometry, analysis.design.cam
    assert geom is not None
    if cam.thickness is None:
        return None
    contours = [geom.profile.ccw().vertices]
    hole = bore_points(analysis, geom.tolerance)
    if hole is not None:
        contours.append(hole)
    section = manifold3d.CrossSection(contours, manifold3d.FillRule.EvenOdd)
    solid = manifold3d.Manifold.extrude(section, cam.thickness)
    mesh = solid.to_mesh()
    tm = trimesh.Trimesh(np.asarray(mesh.vert_properties)[:, :3], np.asarray(mesh.tri_verts),
                         process=False)
    data = tm.export(file_type="stl")
    assert isinstance(data, bytes)
    return data
