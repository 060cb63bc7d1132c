"""``NAME.stl``: a cam's solid for 3-D printing (SPEC §5): binary, millimetres, watertight.

manifold3d builds the solid a kind describes (:data:`camfab.export.part.Solid`: extrusions of
the tolerance-sampled contours, cylinders cut into chords within the tolerance, meshes, and their
booleans), which keeps it a closed 2-manifold with outward normals; trimesh writes the binary
file and reads it back.
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from camfab.analysis.verification import StlCheck
from camfab.arrays import Array
from camfab.curves.sampling import arc_points
from camfab.export.part import Cylinder, Difference, Extrusion, Mesh, Solid

if TYPE_CHECKING:
    from camfab.geometry.plate import Contours


def hole_points(holes: Contours, tolerance: float) -> list[Array]:
    """The holes as closed chains of points (mm), arcs and circles cut into chords within
    *tolerance*."""
    chains = [profile.points(tolerance) for profile in holes.profiles]
    chains += [arc_points(np.zeros(2), np.array([r, 0.0]), 2 * math.pi, tolerance)[:-1]
               for r in holes.circles]
    return chains


def holes_area(holes: Contours) -> float:
    """The exact area (mm²) of *holes*: their contours' (arcs included) and circles'."""
    return (sum(p.area for p in holes.profiles)
            + sum(math.pi * r * r for r in holes.circles))


def chain_length(chain: Array) -> float:
    """The length (mm) of a closed chain of (N, 2) points."""
    return float(np.hypot(*(np.roll(chain, -1, axis=0) - chain).T).sum())


def circle_segments(radius: float, tolerance: float) -> int:
    """Sides of a polygon inscribed in a circle of *radius* whose chords stray at most
    *tolerance* (mm) from it."""
    return max(8, math.ceil(math.pi / math.acos(max(-1.0, 1.0 - tolerance / radius))))


def binary_stl(solid: Any) -> bytes:
    """The solid as binary STL bytes, without short edges or sliver facets
    (:mod:`camfab.export.mesh_quality`). The file stores float32: vertices that round to the same
    float32 point become one, and the faces that then have no area (an edge collapsed, which
    keeps the surface closed) are dropped, so what is read back is the closed solid."""
    import trimesh

    from camfab.export.mesh_quality import without_slivers

    mesh = without_slivers(solid).to_mesh()
    vertices = np.asarray(mesh.vert_properties)[:, :3].astype(np.float32)
    tm = trimesh.Trimesh(vertices, np.asarray(mesh.tri_verts), process=False)
    tm.merge_vertices()
    tm.update_faces(tm.nondegenerate_faces(height=0.0))
    tm.remove_unreferenced_vertices()
    data = tm.export(file_type="stl")
    assert isinstance(data, bytes)
    return data


#: trimesh (which imports much of scipy) is imported before manifold3d computes anything: after
#: a boolean, manifold's worker threads keep a core busy for a while, and the same imports were
#: measured 0.15 s slower on two cores.


@dataclass(frozen=True)
class StlFile:
    """A solid written as binary STL: its bytes, and the volume (mm³) and surface area (mm²)
    of the solid as built (before its vertices were rounded to float32)."""

    data: bytes
    volume_mm3: float
    area_mm2: float


def render_stl(solid: Solid) -> StlFile:
    """The binary STL of *solid* (mm), built with manifold3d (see :func:`build`)."""
    import trimesh  # noqa: F401  (before manifold3d computes: see above)

    held: list[Any] = []
    made = build(solid, held)
    return StlFile(binary_stl(made), float(made.volume()), float(made.surface_area()))


def build(solid: Solid, held: list[Any]) -> Any:
    """*solid* as a ``manifold3d.Manifold``: extrusions of even-odd cross-sections, polygonal
    cylinders, meshes, differences and batch unions, built depth first in the order given.

    Every solid built on the way is kept in *held* until the caller lets it go: manifold3d
    computes when the mesh is asked for, and folds a boolean whose operands nobody else holds
    into one n-ary boolean, whose facets come out in another order (the same solid, other
    bytes)."""
    import manifold3d

    made: Any
    if isinstance(solid, Extrusion):
        section = manifold3d.CrossSection(list(solid.chains), manifold3d.FillRule.EvenOdd)
        made = manifold3d.Manifold.extrude(section, solid.height)
        if solid.z is not None:
            made = made.translate((0.0, 0.0, solid.z))
    elif isinstance(solid, Cylinder):
        made = manifold3d.Manifold.cylinder(solid.height, solid.radius,
                                            circular_segments=solid.segments)
        if solid.z is not None:
            made = made.translate((0.0, 0.0, solid.z))
    elif isinstance(solid, Mesh):
        made = manifold3d.Manifold(manifold3d.Mesh64(
            vert_properties=np.ascontiguousarray(solid.vertices, dtype=np.float64),
            tri_verts=np.ascontiguousarray(solid.faces, dtype=np.uint64)))
    elif isinstance(solid, Difference):
        if solid.cut_first:
            cut = build(solid.cut, held)
            body = build(solid.body, held)
        else:
            body = build(solid.body, held)
            cut = build(solid.cut, held)
        made = body - cut
    else:
        parts = [build(part, held) for part in solid.parts]
        made = (parts[0] if len(parts) == 1 else
                manifold3d.Manifold.batch_boolean(parts, manifold3d.OpType.Add))
    held.append(made)
    return made


#: A face with less area than this (mm²) counts as degenerate: far below any facet a plate of
#: tolerance-sampled curves has, far above the rounding of float32 coordinates' products.
DEGENERATE_AREA_MM2 = 1e-10


def read_stl(data: bytes) -> Any:
    """The STL *data* read back with trimesh (coincident vertices merged), as a reader would."""
    import trimesh

    mesh = trimesh.load(io.BytesIO(data), file_type="stl", force="mesh")
    assert isinstance(mesh, trimesh.Trimesh)
    return mesh


def check_stl(data: bytes, expected_mm3: float, allowance_mm3: float,
              mesh: Any = None) -> StlCheck:
    """Read *data* back as a binary STL (or take its *mesh* already read) and check it (see
    :class:`StlCheck`)."""
    from camfab.export.mesh_quality import flaws

    if mesh is None:
        mesh = read_stl(data)
    short, slivers = flaws(np.asarray(mesh.vertices, dtype=np.float64), np.asarray(mesh.faces))
    return StlCheck(
        faces=len(mesh.faces),
        watertight=bool(mesh.is_watertight),
        consistent_winding=bool(mesh.is_winding_consistent),
        degenerate_faces=int(np.count_nonzero(mesh.area_faces <= DEGENERATE_AREA_MM2)),
        short_edges=short,
        sliver_faces=slivers,
        volume_mm3=float(mesh.volume),
        expected_volume_mm3=expected_mm3,
        volume_allowance_mm3=allowance_mm3,
    )
