"""Short edges and sliver facets: what mesh checkers and slicers stumble on, and their removal.

A boolean of two independently tessellated solids (a drum's polygonal surface less the groove's
tube) puts new vertices where the edges of each cross the faces of the other. Along the line
where the surfaces meet, a crossing of one can fall a micrometre or less from a crossing of the
other: the facets between them are slivers, which an STL's float32 coordinates can fold over,
and FreeCAD's mesh check then reports the solid self-intersecting. The rule every STL camfab
writes keeps (:data:`MIN_EDGE_MM`, :func:`min_altitude`), and :func:`without_slivers` makes a
solid keep it, moving no corner further than half the shortest edge allowed — or, as a last
resort where that leaves flaws (a globoid's groove meeting its blank at a grazing angle), half
of :data:`LAST_RESORT_EDGE_MM`.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from camfab.arrays import Array, Index, clusters, norms

#: No edge is shorter than this (mm): FreeCAD's mesh module calls edges shorter than 1 µm
#: (``MESH_MIN_EDGE_LEN``) too short; the edges a tolerance-sampled cam needs are far longer.
MIN_EDGE_MM = 1e-3

#: No facet is thinner than this (mm): its smallest altitude (a corner's distance from the
#: opposite edge). An STL stores float32 coordinates, rounded by up to 4e-6 mm on a part of
#: 64 mm and 1.5e-5 mm on one of 256 mm; a facet within a few such roundings of a line can fold
#: over when read back (FreeCAD's checks see self-intersections, admesh flips normals). A plate's
#: extruded faces have long thin triangles between tolerance-sampled outline points, down to
#: about 1e-3 mm thick, which no slicer minds; 1e-4 mm stays well below those.
MIN_ALTITUDE_MM = 1e-4

#: The repair removes facets up to this many times thinner than the check's limit allows, so
#: that the float32 rounding of the file cannot take a facet it kept back under the limit.
REPAIR_MARGIN = 2.0

#: The last resort's longest edge to collapse (mm): its ends move by half of it at most, along
#: a facet thinner than a tenth of a micrometre.
LAST_RESORT_EDGE_MM = 0.05

#: Rounds of repair before giving up; one has always been enough for camfab's solids.
_MAX_ROUNDS = 8


def min_altitude(vertices: Array) -> float:
    """The thinnest facet allowed (mm) on a solid with these *vertices*: :data:`MIN_ALTITUDE_MM`,
    or, on a part so large that an STL's float32 rounds its coordinates by more (from 512 mm
    from the origin on), twice that rounding at its farthest coordinate: a facet thinner
    than the file can place its corners is not a facet the file holds."""
    return max(MIN_ALTITUDE_MM, 2.0 * _float32_spacing(vertices))


def _rounding(vertices: Array) -> float:
    """How far (mm) an STL's float32 coordinates can shorten an edge of a solid with these
    *vertices*: both ends rounded by half the float32 spacing at its farthest coordinate, in
    each of three coordinates (an edge just longer than :data:`MIN_EDGE_MM` the repair keeps
    must not come back shorter)."""
    return 2.0 * math.sqrt(3.0) * 0.5 * _float32_spacing(vertices)


def _float32_spacing(vertices: Array) -> float:
    """The float32 spacing (mm) at the farthest coordinate of *vertices* (0 for none)."""
    if vertices.size == 0:
        return 0.0
    return float(np.spacing(np.float32(np.max(np.abs(vertices)))))


def edge_lengths(vertices: Array, faces: Index) -> Array:
    """(F, 3) lengths (mm) of each facet's edges: edge k runs from corner k to corner k + 1."""
    corners = np.take(vertices, faces, axis=0)  # (numpy's take: quicker than indexing)
    return norms(np.roll(corners, -1, axis=1) - corners)


def altitudes(vertices: Array, faces: Index, lengths: Array | None = None) -> Array:
    """(F,) smallest altitude (mm) of each facet: twice its area over its longest edge."""
    corners = np.take(vertices, faces, axis=0)
    if lengths is None:
        lengths = edge_lengths(vertices, faces)
    area2 = norms(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]))
    return area2 / np.maximum(lengths.max(axis=1), 1e-300)


def flaws(vertices: Array, faces: Index) -> tuple[int, int]:
    """The number of edges shorter than :data:`MIN_EDGE_MM` (an edge shared by two facets
    counts twice) and of facets thinner than :func:`min_altitude`."""
    lengths = edge_lengths(vertices, faces)
    thin = altitudes(vertices, faces, lengths) < min_altitude(vertices)
    return int(np.count_nonzero(lengths < MIN_EDGE_MM)), int(np.count_nonzero(thin))


def without_slivers(solid: Any) -> Any:
    """*solid* (a ``manifold3d.Manifold``) without edges shorter than :data:`MIN_EDGE_MM` (and
    the float32 rounding of the file, :func:`_rounding`) or facets thinner than
    :data:`REPAIR_MARGIN` × :func:`min_altitude`, still a closed 2-manifold.

    The ends of each short edge (of each cluster of them) move to their middle, and the corner
    of a thin facet opposite its longest edge moves onto that edge, so the facet has no area;
    manifold3d, building the solid again, collapses the edges of no length and swaps away the
    facets of no area. A corner moves by less than :data:`MIN_EDGE_MM` along the line where two
    surfaces meet, or by less than the repair's limit across a facet (:func:`_repaired`).

    Should flaws outlast that (a facet the repair's margin takes for thin can, moved, leave its
    neighbours thinner than the check allows, round after round), the last resort collapses the
    shortest edge of every thin facet shorter than :data:`LAST_RESORT_EDGE_MM` and repairs again,
    while the flaws as the file will hold them fall. What is left, flaws and all, goes to the
    STL's read-back check to report.
    """
    solid, flawed = _repaired(solid)
    for _ in range(_MAX_ROUNDS):
        if not flawed:
            break
        collapsed = _needles_collapsed(solid)
        if collapsed is None:
            break
        again, left = _repaired(collapsed)
        if left >= flawed:
            break
        solid, flawed = again, left
    return solid


def _repaired(solid: Any) -> tuple[Any, int]:
    """*solid* through the rounds of repair (see :func:`without_slivers`), and the flaws it
    would be written with (0 when none is left even at the repair's margin). Should a round
    leave the solid broken, or the flaws outlast :data:`_MAX_ROUNDS`, the good solid with the
    fewest flaws as written is returned (the last of those)."""
    seen: list[tuple[int, Any]] = []  # (round, solid): the rounds that left flaws
    for turn in range(_MAX_ROUNDS):
        vertices, faces = _mesh(solid)
        lengths = edge_lengths(vertices, faces)
        short = lengths < MIN_EDGE_MM + _rounding(vertices)
        limit = REPAIR_MARGIN * min_altitude(vertices)
        thin = (altitudes(vertices, faces, lengths) < limit) & ~short.any(axis=1)
        if not short.any() and not thin.any():
            return solid, 0
        seen.append((turn, solid))
        # a thin facet's corner opposite its longest edge, onto that edge (once per corner)
        rows = np.flatnonzero(thin)
        longest = np.argmax(lengths[rows], axis=1)
        apex, first = np.unique(faces[rows, (longest + 2) % 3], return_index=True)
        a = faces[rows, longest][first]
        b = faces[rows, (longest + 1) % 3][first]
        along = vertices[b] - vertices[a]
        t = (np.einsum("ij,ij->i", vertices[apex] - vertices[a], along)
             / np.einsum("ij,ij->i", along, along))
        vertices[apex] = vertices[a] + t[:, None] * along
        # the ends of short edges, to the middle of each cluster of them
        ends = np.concatenate([faces[short[:, k]][:, [k, (k + 1) % 3]] for k in range(3)])
        repaired = _rebuilt(vertices, faces, ends)
        if repaired is None:
            break  # as it was: the STL's read-back check reports what is left
        solid = repaired
    else:
        seen.append((_MAX_ROUNDS, solid))
    # the flaws each would be written with, counted only now that they are needed
    counted = [(_written_flaws(*_mesh(made)), turn, made) for turn, made in seen]
    best = min(counted, key=lambda entry: (entry[0], -entry[1]))
    chosen = best if best[0] < counted[-1][0] else counted[-1]
    return chosen[2], chosen[0]


def _needles_collapsed(solid: Any) -> Any | None:
    """*solid* with the shortest edge of every thin facet shorter than
    :data:`LAST_RESORT_EDGE_MM` collapsed to its middle (None: no such facet, or no valid
    solid)."""
    vertices, faces = _mesh(solid)
    lengths = edge_lengths(vertices, faces)
    thin = altitudes(vertices, faces, lengths) < REPAIR_MARGIN * min_altitude(vertices)
    shortest = np.argmin(lengths, axis=1)
    rows = np.flatnonzero(thin & (lengths.min(axis=1) < LAST_RESORT_EDGE_MM))
    if rows.size == 0:
        return None
    ends = np.stack((faces[rows, shortest[rows]], faces[rows, (shortest[rows] + 1) % 3]), axis=1)
    return _rebuilt(vertices, faces, ends)


def _rebuilt(vertices: Array, faces: Index, ends: Index) -> Any | None:
    """The solid of *vertices* and *faces* with the ends of each edge of *ends* (pairs of
    vertex indices; each cluster of them) moved to their middle, rebuilt by manifold3d, which
    collapses the edges of no length (None should it not be a valid solid)."""
    import manifold3d  # imported only for a solid that needs the repair (a boolean's)

    groups, label = clusters(ends, len(vertices))
    sums = np.zeros((groups, 3))
    np.add.at(sums, label, vertices)
    moved = (sums / np.bincount(label, minlength=groups)[:, None])[label]
    rebuilt = manifold3d.Manifold(manifold3d.Mesh64(
        vert_properties=np.ascontiguousarray(moved),
        tri_verts=np.ascontiguousarray(faces, dtype=np.uint64)))
    return rebuilt if rebuilt.status() == manifold3d.Error.NoError else None


def _mesh(solid: Any) -> tuple[Array, Index]:
    """The (V, 3) vertices (mm) and (F, 3) faces of a ``manifold3d.Manifold``."""
    mesh = solid.to_mesh64()
    return (np.array(mesh.vert_properties, dtype=np.float64)[:, :3],
            np.asarray(mesh.tri_verts, dtype=np.int64))


def _written_flaws(vertices: Array, faces: Index) -> int:
    """The short edges and thin facets (:func:`flaws`) of a mesh with its corners in float32,
    as an STL holds them."""
    return sum(flaws(vertices.astype(np.float32).astype(np.float64), faces))
