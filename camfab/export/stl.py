"""``NAME.stl``: a cam's solid for 3-D printing (SPEC §5): binary, millimetres, watertight.

manifold3d builds the solid a kind describes (:data:`camfab.export.part.Solid`: extrusions of
the tolerance-sampled contours, cylinders cut into chords within the tolerance, meshes, and their
booleans), which keeps it a closed 2-manifold with outward normals; numpy writes the binary
file and reads it back, merging coincident corners as mesh readers do, and checks it closed,
wound alike and of the solid's volume (trimesh, a heavy import, is kept for the tests, as an
independent reader).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from camfab.analysis.verification import StlCheck
from camfab.arrays import Array, Index, Mask, edge_groups, norms
from camfab.curves.sampling import arc_points
from camfab.export.part import (
    Cylinder,
    Difference,
    Extrusion,
    Mesh,
    Revolution,
    Solid,
)

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


#: An STL's coordinates are merged when they agree to this many decimal places of a millimetre
#: (1e-8 mm, far below float32's resolution on any part camfab makes), as mesh readers such as
#: trimesh merge them.
MERGE_DIGITS = 8

#: A facet normal shorter than this (before it is made a unit vector) is written as zero.
ZERO_NORMAL = 1e-13

#: A binary STL: an 80-byte header, a face count, then per face its normal, three corners
#: (float32) and two attribute bytes.
_HEADER = np.dtype([("header", "V80"), ("face_count", "<u4")])
_FACET = np.dtype([("normals", "<f4", (3,)), ("vertices", "<f4", (3, 3)), ("attributes", "<u2")])


def equal_rows(keys: NDArray[np.int64]) -> tuple[Index, Index]:
    """The groups of equal rows of (N, M) integer *keys*: the index of each group's first row
    (groups in the order of their rows), and each row's group.

    (``np.unique`` of the rows does the same sorting the rows as raw bytes, several times
    slower: a sort of each column in turn, stable, finds the groups.)"""
    if len(keys) == 0:
        return np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp)
    order = np.lexsort(keys.T[::-1])
    ordered = keys[order]
    starts = np.ones(len(keys), dtype=bool)
    starts[1:] = (ordered[1:] != ordered[:-1]).any(axis=1)
    group = np.empty(len(keys), dtype=np.intp)
    group[order] = np.cumsum(starts) - 1
    first = order[starts]  # the sort is stable: a group's first row comes first
    by_first = first.argsort()
    return first[by_first], by_first.argsort()[group]


def merged(vertices: Array, faces: Index) -> tuple[Array, Index]:
    """*vertices* (mm) that agree to :data:`MERGE_DIGITS` places made one, each kept where it
    first occurs, and *faces* renumbered to them."""
    first, group = equal_rows(np.round(vertices * 10**MERGE_DIGITS).astype(np.int64))
    return vertices[first], group[faces]


def _crosses(triangles: Array) -> Array:
    """(F, 3) cross products of each triangle's first two edges (corner 0 to 1, 1 to 2)."""
    edges = triangles[:, 1:, :] - triangles[:, :2, :]
    return np.cross(edges[:, 0], edges[:, 1])


def _areas(crosses: Array) -> Array:
    """(F,) facet areas (mm²) from their edges' cross products."""
    return norms(crosses) / 2.0


def _unit_normals(crosses: Array) -> Array:
    """(F, 3) unit normals from the edges' cross products, zero where a facet has none."""
    norm = np.sqrt(np.dot(crosses * crosses, [1.0, 1.0, 1.0]))
    valid = norm > ZERO_NORMAL
    norm[valid] **= -1
    return np.where(valid[:, None], crosses * norm.reshape((-1, 1)), 0.0)


def _has_area(triangles: Array, crosses: Array) -> Mask:
    """(F,) True where a facet has area and neither of its edges from corner 0 is shorter than
    1e-8 mm."""
    areas = _areas(crosses)
    ok = np.ones(len(triangles), dtype=bool)
    for k in (1, 2):
        length = norms(triangles[:, k] - triangles[:, 0])
        long_enough = length > 10.0**-MERGE_DIGITS
        height = np.zeros(len(triangles))
        height[long_enough] = areas[long_enough] * 2 / length[long_enough]
        ok &= height > 0.0
    return ok


def stl_bytes(triangles: Array, crosses: Array | None = None) -> bytes:
    """Binary STL bytes of (F, 3, 3) *triangles* (mm), each with its unit normal (from
    *crosses*, their first two edges' cross products, where already computed)."""
    header = np.zeros(1, dtype=_HEADER)
    header["face_count"] = len(triangles)
    packed = np.zeros(len(triangles), dtype=_FACET)
    packed["normals"] = _unit_normals(_crosses(triangles) if crosses is None else crosses)
    packed["vertices"] = triangles
    return header.tobytes() + packed.tobytes()


def binary_stl(solid: Any) -> bytes:
    """The solid as binary STL bytes, without short edges or sliver facets
    (:mod:`camfab.export.mesh_quality`). The file stores float32: vertices that round to the same
    float32 point become one, and the faces that then have no area (an edge collapsed, which
    keeps the surface closed) are dropped, so what is read back is the closed solid."""
    from camfab.export.mesh_quality import without_slivers

    mesh = without_slivers(solid).to_mesh()
    vertices = np.asarray(mesh.vert_properties)[:, :3].astype(np.float32).astype(np.float64)
    vertices, faces = merged(vertices, np.asarray(mesh.tri_verts, dtype=np.int64))
    triangles = np.take(vertices, faces, axis=0)
    crosses = _crosses(triangles)
    kept = _has_area(triangles, crosses)
    return stl_bytes(triangles[kept], crosses[kept])


def _extruded(solid: Extrusion) -> Any:
    """The extrusion from z = 0 as a ``manifold3d.Manifold``: a plate's outline (and bore) with
    caps of no needle facet (:mod:`camfab.export.plate_mesh`), other regions as manifold3d
    extrudes their even-odd cross-section."""
    import manifold3d

    from camfab.export.mesh_quality import REPAIR_MARGIN, min_altitude
    from camfab.export.plate_mesh import extruded_mesh

    corners = np.vstack([np.column_stack((c, np.full(len(c), solid.height + (solid.z or 0.0))))
                         for c in solid.chains])
    mesh = extruded_mesh(solid.chains, solid.height, REPAIR_MARGIN * min_altitude(corners))
    if mesh is not None:
        made = manifold3d.Manifold(manifold3d.Mesh64(
            vert_properties=np.ascontiguousarray(mesh[0]),
            tri_verts=np.ascontiguousarray(mesh[1], dtype=np.uint64)))
        if made.status() == manifold3d.Error.NoError:
            return made
    section = manifold3d.CrossSection(list(solid.chains), manifold3d.FillRule.EvenOdd)
    return manifold3d.Manifold.extrude(section, solid.height)


@dataclass(frozen=True)
class StlFile:
    """A solid written as binary STL: its bytes, and the volume (mm³) and surface area (mm²)
    of the solid as built (before its vertices were rounded to float32)."""

    data: bytes
    volume_mm3: float
    area_mm2: float


def render_stl(solid: Solid) -> StlFile:
    """The binary STL of *solid* (mm), built with manifold3d (see :func:`build`)."""
    from camfab.stopping import deferred

    held: list[Any] = []
    with deferred():  # a stop raised while manifold3d works has aborted the process
        made = build(solid, held)
        return StlFile(binary_stl(made), float(made.volume()), float(made.surface_area()))


def build(solid: Solid, held: list[Any]) -> Any:
    """*solid* as a ``manifold3d.Manifold``: extrusions of even-odd cross-sections, polygonal
    cylinders, revolved sections, meshes, differences and batch unions, built depth first in
    the order given.

    Every solid built on the way is kept in *held* until the caller lets it go: manifold3d
    computes when the mesh is asked for, and folds a boolean whose operands nobody else holds
    into one n-ary boolean, whose facets come out in another order (the same solid, other
    bytes)."""
    import manifold3d

    made: Any
    if isinstance(solid, Extrusion):
        made = _extruded(solid)
        if solid.z is not None:
            made = made.translate((0.0, 0.0, solid.z))
    elif isinstance(solid, Cylinder):
        made = manifold3d.Manifold.cylinder(solid.height, solid.radius,
                                            circular_segments=solid.segments)
        if solid.z is not None:
            made = made.translate((0.0, 0.0, solid.z))
    elif isinstance(solid, Revolution):
        section = manifold3d.CrossSection([np.ascontiguousarray(solid.section)])
        made = manifold3d.Manifold.revolve(section, circular_segments=solid.segments)
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
        if solid.tolerance is not None:
            body, cut = body.set_tolerance(solid.tolerance), cut.set_tolerance(solid.tolerance)
            held.extend((body, cut))
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


@dataclass(frozen=True)
class StlMesh:
    """A binary STL read back as a reader sees it: its corners merged (see :func:`merged`) into
    (V, 3) ``vertices`` (mm) and (F, 3) ``faces`` indexing them."""

    vertices: Array
    faces: Index

    @cached_property
    def triangles(self) -> Array:
        """(F, 3, 3) corners of each facet (mm)."""
        return np.take(self.vertices, self.faces, axis=0)  # (quicker than indexing)

    @cached_property
    def crosses(self) -> Array:
        """(F, 3) cross products of each facet's first two edges (mm²)."""
        return _crosses(self.triangles)

    @cached_property
    def edge_groups(self) -> tuple[Index, Index, Index]:
        """Each edge once (E, 2), each facet side's edge, and each edge's count of sides
        (:func:`camfab.arrays.edge_groups`)."""
        return edge_groups(self.faces, len(self.vertices))

    def edges(self) -> tuple[bool, bool]:
        """Whether every edge is shared by exactly two facets (the surface is closed), and
        whether every edge shared by two runs one way in one and the other way in the other
        (the facets are wound alike)."""
        edges = self.faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
        _, inverse, counts = self.edge_groups
        closed = bool((counts == 2).all())
        paired = np.flatnonzero(counts[inverse] == 2)
        pairs = paired[np.argsort(inverse[paired], kind="stable")].reshape(-1, 2)
        wound = bool((edges[pairs[:, 0], 1] == edges[pairs[:, 1], 0]).all())
        return closed, wound

    def volume(self) -> float:
        """The signed volume enclosed (mm³; positive for outward normals), by the divergence
        theorem over the facets."""
        triangles = self.triangles
        summed = triangles[:, 0, 0] + triangles[:, 1, 0] + triangles[:, 2, 0]
        return float((self.crosses[:, 0] * summed).sum() / 6.0)

    def areas(self) -> Array:
        """(F,) facet areas (mm²)."""
        return _areas(self.crosses)


def read_stl(data: bytes) -> StlMesh:
    """The binary STL *data* read back (coincident corners merged), as a reader would.

    Raises
    ------
    ValueError
        The data is not a binary STL of the length its face count gives.
    """
    count = -1
    if len(data) >= _HEADER.itemsize:
        count = int(np.frombuffer(data, dtype=_HEADER, count=1)["face_count"][0])
    if count < 0 or len(data) != _HEADER.itemsize + count * _FACET.itemsize:
        raise ValueError("not a binary STL of the length its face count gives")
    facets = np.frombuffer(data, dtype=_FACET, offset=_HEADER.itemsize)
    corners = facets["vertices"].reshape(-1, 3).astype(np.float64)
    vertices, faces = merged(corners, np.arange(3 * count, dtype=np.int64).reshape(-1, 3))
    return StlMesh(vertices, faces)


def check_stl(data: bytes, expected_mm3: float, allowance_mm3: float,
              mesh: StlMesh | None = None) -> StlCheck:
    """Read *data* back as a binary STL (or take its *mesh* already read) and check it (see
    :class:`StlCheck`)."""
    from camfab.export.mesh_quality import flaws

    if mesh is None:
        mesh = read_stl(data)
    short, slivers = flaws(mesh.vertices, mesh.faces)
    closed, wound = mesh.edges()
    return StlCheck(
        faces=len(mesh.faces),
        watertight=closed,
        consistent_winding=wound,
        degenerate_faces=int(np.count_nonzero(mesh.areas() <= DEGENERATE_AREA_MM2)),
        short_edges=short,
        sliver_faces=slivers,
        volume_mm3=mesh.volume(),
        expected_volume_mm3=expected_mm3,
        volume_allowance_mm3=allowance_mm3,
    )
