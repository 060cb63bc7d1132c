"""The part as designed, as the triangle mesh of its STL file (for aligning a free scan and
setting aside the points on no functional surface)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from camfab.arrays import Array, Index

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis


def part_mesh(analysis: Analysis) -> tuple[Array, Index]:
    """The vertices (V, 3, mm) and faces (F, 3) of *analysis*'s part, built as its STL file is
    (the kind's solid, by manifold3d), in the STL's frame; empty arrays when the kind makes no
    solid of it."""
    from camfab.export.stl import build
    from camfab.kinds import kind_of

    part = kind_of(analysis.design.cam.type).part(analysis)
    if part.solid is None:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
    held: list[Any] = []
    mesh = build(part.solid, held).to_mesh()
    vertices = np.asarray(mesh.vert_properties, dtype=np.float64)[:, :3]
    return vertices, np.asarray(mesh.tri_verts, dtype=np.int64)


#: Largest spacing (mm) of the samples of a mesh's faces.
SAMPLE_SPACING_MM = 0.5

#: Most samples of a mesh's faces (the spacing grows on a large part to keep to it).
MAX_SAMPLES = 400_000

#: Most samples along a face's longest edge.
MAX_PER_EDGE = 40


def surface_samples(vertices: Array, faces: Index) -> tuple[Array, Array, Array]:
    """Points on each triangle on a barycentric lattice about :data:`SAMPLE_SPACING_MM` apart
    (coarser on large faces and parts, see :data:`MAX_PER_EDGE` and :data:`MAX_SAMPLES`),
    with the face's unit normal and the lattice's spacing (mm) at each."""
    tri = vertices[faces]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    area2 = np.linalg.norm(cross, axis=1)
    keep = area2 > 0.0
    tri, cross, area2 = tri[keep], cross[keep], area2[keep]
    normal = cross / area2[:, None]
    longest = np.max(np.linalg.norm(tri - np.roll(tri, 1, axis=1), axis=2), axis=1)
    n = np.clip(np.ceil(longest / SAMPLE_SPACING_MM), 1, MAX_PER_EDGE).astype(np.int64)
    while ((n + 1) * (n + 2) // 2).sum() > MAX_SAMPLES and n.max() > 1:
        n = np.maximum(1, n // 2)
    points, normals, spacing = [tri.mean(axis=1)], [normal], [longest]
    for level in np.unique(n[n > 1]).tolist():
        pick = n == level
        i, j = np.meshgrid(np.arange(level + 1), np.arange(level + 1), indexing="ij")
        inside = i + j <= level
        a, b = i[inside] / level, j[inside] / level
        corner = tri[pick]
        lattice = (a[None, :, None] * corner[:, None, 0] + b[None, :, None] * corner[:, None, 1]
                   + (1.0 - a - b)[None, :, None] * corner[:, None, 2])
        points.append(lattice.reshape(-1, 3))
        normals.append(np.repeat(normal[pick], inside.sum(), axis=0))
        spacing.append(np.repeat(longest[pick] / level, inside.sum()))
    spacing[0] = np.minimum(longest, np.where(n > 1, longest / n, longest))
    return np.concatenate(points), np.concatenate(normals), np.concatenate(spacing)
