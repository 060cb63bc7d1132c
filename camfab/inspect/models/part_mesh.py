"""The part as designed, as the triangle mesh of its STL file (for aligning a free scan and
setting aside the points on no functional surface)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from camfab.arrays import Array, Index

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.inspect.surface import ScanModel


def part_mesh(analysis: Analysis) -> tuple[Array, Index]:
    """The vertices (V, 3, mm) and faces (F, 3) of *analysis*'s part as its STL file holds
    them (the kind's solid built by manifold3d, written and read back), in the STL's frame;
    empty arrays when camfab makes no solid of it (a groove that folds over itself)."""
    from camfab.export.stl import read_stl, render_stl
    from camfab.kinds import kind_of

    part = kind_of(analysis.design.cam.type).part(analysis)
    if part.solid is None:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
    mesh = read_stl(render_stl(part.solid).data)
    return mesh.vertices, mesh.faces


#: Mean spacing (mm) of the samples of a mesh's faces.
SAMPLE_SPACING_MM = 0.5

#: Most samples of a mesh's faces (the spacing grows on a large part to keep to it).
MAX_SAMPLES = 400_000

#: A sample's reach, in spacings: the samples fall at random, evenly by area, so a point on the
#: surface lies within this many spacings of one but for a chance of about e^(−π·3²) ≈ 5·10⁻¹³
#: (at an edge, where only half the disc is surface, e^(−π·3²/2) ≈ 7·10⁻⁷).
SAMPLE_REACH = 3.0


def part_samples(model: ScanModel) -> tuple[Array, Array, Array]:
    """:func:`surface_samples` of *model*'s part (its ``reference_mesh``), empty arrays when it
    has none: what the alignment's target and the points' other surfaces are both made of."""
    vertices, faces = model.reference_mesh()
    if not len(faces):
        return np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0)
    return surface_samples(vertices, faces)


def surface_samples(vertices: Array, faces: Index, spacing: float = SAMPLE_SPACING_MM,
                    most: int = MAX_SAMPLES) -> tuple[Array, Array, Array]:
    """Points spread evenly by area over the triangles (a fixed seed: the same every time),
    about *spacing* (mm) apart (farther on a part so large that it would take more than
    *most*), and each triangle's centroid, each with its face's unit normal and the distance
    (mm) within which a point on the surface has a sample (:data:`SAMPLE_REACH` spacings)."""
    tri = vertices[faces]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    area2 = np.linalg.norm(cross, axis=1)
    keep = area2 > 0.0
    tri, cross, area2 = tri[keep], cross[keep], area2[keep]
    area = 0.5 * area2
    spacing = max(spacing, float(np.sqrt(area.sum() / most)))
    rng = np.random.default_rng(0)
    count = np.floor(area / spacing**2 + rng.random(len(area))).astype(np.int64)
    face = np.repeat(np.arange(len(area)), count)
    u = rng.random((len(face), 2))
    flip = u.sum(axis=1) > 1.0
    u[flip] = 1.0 - u[flip]
    corner = tri[face]
    points = corner[:, 0] + u[:, :1] * (corner[:, 1] - corner[:, 0]) \
        + u[:, 1:] * (corner[:, 2] - corner[:, 0])
    normals = cross[face] / area2[face, None]
    points = np.concatenate((points, tri.mean(axis=1)))
    normals = np.concatenate((normals, cross / area2[:, None]))
    return points, normals, np.full(len(points), SAMPLE_REACH * spacing)
