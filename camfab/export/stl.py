"""``NAME.stl``: the disc-cam plate for 3-D printing (SPEC §5): binary, millimetres, watertight.

manifold3d builds the solid (the outline with the bore and keyway as holes, extruded from z = 0 to
z = thickness), which keeps it a closed 2-manifold with outward normals; trimesh writes the binary
file. Curves are the tolerance-sampled profile; the bore's circle is cut into chords within the
same tolerance.
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from camfab.arrays import Array
from camfab.geometry.sampling import arc_points

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.geometry.plate import Contours, Plate


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


def render_drum_stl(analysis: Analysis) -> tuple[bytes, float, float]:
    """The binary STL of a drum cam (mm): the drum along Z from 0 to its length, the bore
    through, and the groove subtracted once as one closed tube; with the solid's volume (mm³)
    and surface area (mm²) as built."""
    import manifold3d
    import trimesh  # noqa: F401  (before manifold3d computes: see above)

    from camfab.geometry.drum_mesh import groove_tube
    from camfab.geometry.sampling import SAMPLING_SHARE

    dense = analysis.drum
    assert dense is not None
    d = dense.drum
    tolerance = SAMPLING_SHARE * analysis.design.manufacturing.tolerance
    tube = groove_tube(d, analysis.program, tolerance)
    groove = manifold3d.Manifold(manifold3d.Mesh64(
        vert_properties=np.ascontiguousarray(tube.vertices, dtype=np.float64),
        tri_verts=np.ascontiguousarray(tube.faces, dtype=np.uint64)))
    body = manifold3d.Manifold.cylinder(d.length, d.radius,
                                        circular_segments=circle_segments(d.radius, tolerance))
    if d.bore > 0.0:
        bore = manifold3d.Manifold.cylinder(d.length + 2.0, d.bore,
                                            circular_segments=circle_segments(d.bore, tolerance))
        body = body - bore.translate((0.0, 0.0, -1.0))
    solid = body - groove
    return binary_stl(solid), float(solid.volume()), float(solid.surface_area())


def render_stl(analysis: Analysis, plate: Plate) -> bytes | None:
    """The binary STL of the plate, or None when the design gives no ``thickness``."""
    geom, cam = analysis.geometry, analysis.design.cam
    assert geom is not None
    if cam.thickness is None:
        return None
    return render_stack_stl([geom.outline_points()], plate.holes, geom.tolerance, cam.thickness)


def render_stack_stl(outlines: list[Array], holes: Contours, tolerance: float,
                     thickness: float) -> bytes:
    """The binary STL of plates stacked along Z on one bore (mm): plate i is the outline
    *outlines[i]* with the *holes*, from z = i·thickness to (i + 1)·thickness, the plates joined
    face to face into one solid (a conjugate pair printed as one part; one outline, one plate)."""
    import manifold3d
    import trimesh  # noqa: F401  (before manifold3d computes: see above)

    bores = hole_points(holes, tolerance)
    plates = [manifold3d.Manifold.extrude(
                  manifold3d.CrossSection([outline, *bores], manifold3d.FillRule.EvenOdd),
                  thickness).translate((0.0, 0.0, i * thickness))
              for i, outline in enumerate(outlines)]
    if len(plates) == 1:
        return binary_stl(plates[0])
    return binary_stl(manifold3d.Manifold.batch_boolean(plates, manifold3d.OpType.Add))


#: A face with less area than this (mm²) counts as degenerate: far below any facet a plate of
#: tolerance-sampled curves has, far above the rounding of float32 coordinates' products.
DEGENERATE_AREA_MM2 = 1e-10


@dataclass(frozen=True)
class StlCheck:
    """The STL as a reader sees it: read back from its bytes with trimesh (vertices merged).
    ``short_edges`` and ``sliver_faces`` count what breaks the rule of
    :mod:`camfab.export.mesh_quality` (an edge shared by two faces counts twice).

    ``volume_allowance_mm3`` is how far the volume may differ from the part's area × thickness:
    the tolerance along every contour, through the thickness.
    """

    faces: int
    watertight: bool
    consistent_winding: bool
    degenerate_faces: int
    short_edges: int
    sliver_faces: int
    volume_mm3: float
    expected_volume_mm3: float
    volume_allowance_mm3: float

    @property
    def ok(self) -> bool:
        """Closed, consistently wound with outward normals (positive volume), no degenerate
        face, short edge or sliver, and the volume of the part."""
        return (self.watertight and self.consistent_winding and self.degenerate_faces == 0
                and self.short_edges == 0 and self.sliver_faces == 0
                and abs(self.volume_mm3 - self.expected_volume_mm3) <= self.volume_allowance_mm3)


def expected_volume(analysis: Analysis, plate: Plate) -> tuple[float, float]:
    """The plate's volume (mm³) from its exact hole areas and its outline's area, and the
    allowance for the tolerance along every contour (mm³)."""
    geom, cam = analysis.geometry, analysis.design.cam
    assert geom is not None and cam.thickness is not None
    area = geom.profile.area - holes_area(plate.holes)
    chains = [geom.outline_points(), *hole_points(plate.holes, geom.tolerance)]
    length = sum(chain_length(c) for c in chains)
    tolerance = analysis.design.manufacturing.tolerance
    return area * cam.thickness, tolerance * length * cam.thickness


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
