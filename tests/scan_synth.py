"""Synthetic 3-D scans of a cam made from camfab's exact surfaces, with known errors, for testing
the inspection of scans (:func:`synthetic_scan`).

A scan is a cloud of points on the part of a design, in the cam frame of camfab's own STL files
(the cam axis Z through the origin, the part drawn at cam angle 0), then moved as a whole:

- a share of the points (*flank_share*) lies on the functional surfaces (the flanks of the kind's
  scan model, :mod:`camfab.inspect.models`, at rows 0.1° of cam angle apart and columns at most
  0.25 mm apart): spread uniformly by area over the grid's cells (a cell chosen in proportion
  to its area, a point in it by bilinear interpolation of its four nodes: the cells are small
  enough that this lies well under a micrometre off the exact surface);
- the rest on the other surfaces of the part (its ends, bore, outer surface, a groove's floor):
  uniformly by area on the triangles of ``model.reference_mesh()`` (the STL's solid), keeping
  only the points that lie on no flank. A design camfab makes no solid of has all its points on
  its flanks.

Errors of the part, on the flanks' points, along the exact surface normal (out of the material,
so + is material left on, as camfab's deviation), added in this order:

- ``bump=(cam_angle_deg, across_mm, height_mm, radius_mm, flank_index)``: a smooth bump
  ``height · (1 + cos(π d / radius)) / 2`` for d < radius, d the straight distance (mm) from
  the flank's point at that cam angle (its row) and that position across it (``across``) to the
  point's place on the design's surface;
- ``oversize_mm``: −oversize/2 on every flank (material removed: a groove that much wider);
- ``taper_mm``: −taper · f, f the point's share of the way across its flank, 0 at its first
  column (the groove's floor, a plate's bottom face) to 1 at its last;
- ``phase_deg``: the flanks' points (and normals) turned about the cam axis by the angle,
  counter-clockwise seen from +Z (the groove's phase error against the rest of the part);
- ``noise_mm``: a Gaussian error of that standard deviation on every point, along its normal
  (a flank's exact normal, another surface's facet normal).

Then the whole cloud is moved rigidly: turned ``whole_phase_deg`` about Z, then ``misplace =
(rx, ry, rz, tx, ty, tz)``: turned rx, ry, rz degrees about the fixed X, Y, Z axes in that
order, and shifted (tx, ty, tz) mm: ``points = cam_points @ rotation.T + translation``.

The ground truth is the part's, in the cam frame: each point's flank (−1 off every flank), its
true signed deviation from that flank (the distance from the design's surface along the exact
normal at the point's foot on it, found by Gauss–Newton on the bilinear grid: the errors as
they lie there, noise included), and the rigid motion applied. All lengths in mm. Deterministic:
the same arguments give the same cloud (numpy's ``default_rng(seed)``).
"""

from __future__ import annotations

import io
import math
import os
from dataclasses import dataclass
from functools import cache
from importlib import import_module
from pathlib import Path
from typing import Any

import numpy as np

from camfab.arrays import Array, Index
from camfab.inspect.surface import FlankGrid, ScanModel

#: The scan models' rows: 0.1° of cam angle apart, as an inspection builds them.
STEP = math.radians(0.1)

#: The kinds' scan models (modules of :mod:`camfab.inspect.models`), by the kind's module.
MODELS = {"camfab.kinds.drum": "drum", "camfab.kinds.globoid": "globoid",
          "camfab.kinds.groove": "groove", "camfab.kinds.pair:CONJUGATE": "pair",
          "camfab.kinds.disc": "plate", "camfab.kinds.shaped": "plate",
          "camfab.kinds.pair:CONSTANT_BREADTH": "plate", "camfab.kinds.linear": "linear"}

#: A sample of the part's mesh lies on a flank when its foot on the flank's grid lies inside
#: the grid and it is within this (mm) of it: the mesh holds the flanks within the design's
#: tolerance (at most some 0.01 mm).
ON_FLANK_MM = 0.02

#: A point's foot lies off its flank's grid when it is clamped to the first or last column and
#: the point stands more than this (mm) beside it along the surface.
OFF_GRID_MM = 1e-4

#: Gauss–Newton iterations finding a point's foot on a flank's grid.
FOOT_ITERATIONS = 8


@dataclass(frozen=True)
class Part:
    """What a design's synthetic scans are made of: its analysis, its kind's scan model (rows
    0.1° apart), a k-d tree of each flank's nodes (scipy's ``cKDTree``) and the part's mesh
    (vertices (V, 3), faces (F, 3); empty when camfab makes no solid of it)."""

    analysis: Any
    model: Any
    trees: tuple[Any, ...]
    vertices: Array
    faces: Index


def part_of(design_path: Path | str) -> Part:
    """The analysis, scan model and mesh of the design at *design_path* (kept per file: the
    scans of one design share them)."""
    return _part(str(Path(design_path).resolve()))


@cache
def _part(design_path: str) -> Part:
    from scipy.spatial import cKDTree

    from camfab.errors import InspectionError
    from camfab.kinds import REGISTRY
    from camfab.pipeline import analyse, load_design

    analysis = analyse(load_design(Path(design_path)))
    kind = MODELS.get(REGISTRY[analysis.design.cam.type])
    if kind is None:
        raise ValueError(f"{design_path}: camfab has no scan model of cam.type "
                         f"{analysis.design.cam.type!r}")
    model = import_module(f"camfab.inspect.models.{kind}").scan_model(analysis, STEP)
    try:
        vertices, faces = model.reference_mesh()
    except InspectionError:  # (no solid: a folded groove)
        vertices, faces = np.zeros((0, 3)), np.zeros((0, 3), dtype=np.intp)
    trees = tuple(cKDTree(f.points.reshape(-1, 3)) for f in model.flanks)
    return Part(analysis, model, trees, np.asarray(vertices, float), np.asarray(faces, np.intp))


@dataclass(frozen=True)
class Synthetic:
    """A synthetic scan and its ground truth (see the module).

    Attributes
    ----------
    points
        (N, 3) the scan's points (mm), in the scanner's frame (after the rigid motion).
    normals
        (N, 3) their unit normals (the design surface's, turned with the point; a bump's slope
        is not in them), or None.
    flank
        (N,) the flank of the model each point was put on, −1 for the other surfaces.
    deviation
        (N,) the true signed deviation (mm, + out of the material) of each flank point from its
        flank along the exact normal at its foot, noise included; NaN off the flanks and where
        a phase error carried the point past the flank's edge.
    surface
        (N,) the same without the noise: the made surface's deviation there.
    cam_angle, across
        (N,) where each flank point's foot lies on its flank: its row's cam angle (rad) and
        its position across the flank (mm, the grid's ``across``); NaN off the flanks.
    design_points
        (N, 3) each point's place on the design's surface before any error (mm, cam frame).
    rotation, translation
        The rigid motion applied: ``points = cam_points @ rotation.T + translation``.
    model, analysis
        The design's scan model and analysis the scan was made from.
    """

    points: Array
    normals: Array | None
    flank: Index
    deviation: Array
    surface: Array
    cam_angle: Array
    across: Array
    design_points: Array
    rotation: Array
    translation: Array
    model: ScanModel
    analysis: Any

    @property
    def cam_points(self) -> Array:
        """(N, 3) the points in the cam frame (the rigid motion undone), mm."""
        return (self.points - self.translation) @ self.rotation

    def write(self, path: Path | str) -> Path:
        """Write the scan to *path*: a binary little-endian PLY (``.ply``: doubles x, y, z and
        nx, ny, nz with normals) or else a CSV with a header row (x,y,z[,nx,ny,nz]). Written to
        a temporary file beside it, then renamed."""
        path = Path(path)
        columns = self.points if self.normals is None else np.hstack((self.points,
                                                                       self.normals))
        names = ["x", "y", "z"] + ([] if self.normals is None else ["nx", "ny", "nz"])
        if path.suffix.lower() == ".ply":
            header = "".join(["ply\nformat binary_little_endian 1.0\n",
                              "comment synthetic scan of a cam (mm)\n",
                              f"element vertex {len(columns)}\n",
                              *(f"property double {name}\n" for name in names),
                              "end_header\n"]).encode("ascii")
            data = header + np.ascontiguousarray(columns, dtype="<f8").tobytes()
        else:
            buffer = io.StringIO()
            np.savetxt(buffer, columns, fmt=["%.7f"] * 3 + ["%.9f"] * (len(names) - 3),
                       delimiter=",", header=",".join(names), comments="")
            data = buffer.getvalue().encode("ascii")
        temporary = path.with_name(f".{path.name}.{os.getpid()}.tmp")
        temporary.write_bytes(data)
        temporary.replace(path)
        return path


def synthetic_scan(design_path: Path | str, *, points: int = 200_000, noise_mm: float = 0.0,
                   bump: tuple[float, float, float, float, int] | None = None,
                   phase_deg: float = 0.0, whole_phase_deg: float = 0.0,
                   oversize_mm: float = 0.0, taper_mm: float = 0.0,
                   misplace: tuple[float, float, float, float, float, float] | None = None,
                   with_normals: bool = False, flank_share: float = 0.6,
                   seed: int = 0) -> Synthetic:
    """A synthetic scan of *points* points of the part of the design at *design_path* with the
    errors asked (see the module)."""
    part = part_of(design_path)
    flanks = part.model.flanks
    rng = np.random.default_rng(seed)
    on_flanks = points if not len(part.faces) else round(points * flank_share)
    # the flanks' points: each flank's share by its area, a cell by its area, a place in it
    areas = [cell_areas(f, not getattr(part.model, 'slides', False)) for f in flanks]
    totals = np.array([area.sum() for area in areas])
    counts = np.floor(on_flanks * totals / totals.sum()).astype(int)
    counts[0] += on_flanks - counts.sum()
    flank = np.repeat(np.arange(len(flanks)), counts)
    s, t = np.empty(on_flanks), np.empty(on_flanks)
    for index, (area, count) in enumerate(zip(areas, counts, strict=True)):
        cell = rng.choice(area.size, size=count, p=(area / area.sum()).ravel())
        row, col = np.divmod(cell, area.shape[1])
        s[flank == index] = row + rng.random(count)
        t[flank == index] = col + rng.random(count)
    step = row_step(part)
    design = np.empty((on_flanks, 3))
    normal = np.empty((on_flanks, 3))
    height = np.zeros(on_flanks)
    for index, f in enumerate(flanks):
        on = flank == index
        across = across_at(f, t[on])
        design[on], _, _ = bilinear(f, s[on], t[on])
        normal[on] = unit_normal(f, s[on], t[on])
        height[on] -= 0.5 * oversize_mm + taper_mm * (across - f.across[0]) / (
            f.across[-1] - f.across[0])
        if bump is not None and int(bump[4]) == index:
            angle, where, top, radius, _ = bump
            column = np.interp([where], f.across, np.arange(f.across.size, dtype=float))
            centre, _, _ = bilinear(f, np.array([math.radians(angle) / step]), column)
            d = np.linalg.norm(design[on] - centre, axis=1)
            height[on] += np.where(d < radius, 0.5 * top * (1.0 + np.cos(np.pi * d / radius)),
                                   0.0)
    turn = turn_z(math.radians(phase_deg))
    made = (design + height[:, None] * normal) @ turn.T
    others, other_normals = other_points(part, points - on_flanks, rng)
    normals = np.vstack((normal @ turn.T, other_normals))
    noise = rng.normal(0.0, noise_mm, points) if noise_mm > 0 else np.zeros(points)
    cam_points = np.vstack((made, others)) + noise[:, None] * normals
    # the truth: each flank point's foot on its flank, from where it was put
    deviation, surface = np.full(points, np.nan), np.full(points, np.nan)
    cam_angle, across_all = np.full(points, np.nan), np.full(points, np.nan)
    for index, f in enumerate(flanks):
        on = np.flatnonzero(flank == index)
        foot = Foot.of(f, made[on], s[on], t[on])
        surface[on] = np.where(foot.inside, foot.deviation, np.nan)
        deviation[on] = np.where(foot.inside, np.einsum(
            "ij,ij->i", cam_points[on] - foot.points, foot.normals), np.nan)
        cam_angle[on] = np.mod(foot.s * step, 2.0 * math.pi)
        across_all[on] = across_at(f, foot.t)
    rotation, translation = rigid_motion(whole_phase_deg, misplace)
    order = rng.permutation(points)
    return Synthetic(
        (cam_points @ rotation.T + translation)[order],
        (normals @ rotation.T)[order] if with_normals else None,
        np.concatenate((flank, np.full(len(others), -1)))[order], deviation[order],
        surface[order], cam_angle[order], across_all[order], np.vstack((design, others))[order],
        rotation, translation, part.model, part.analysis)


# -- the flanks ----------------------------------------------------------------------------------

def row_step(part: Part) -> float:
    """The cam angle (rad) between the scan model's rows."""
    return float(part.model.theta[1] - part.model.theta[0])


def cell_areas(flank: FlankGrid, wraps: bool = True) -> Array:
    """(R, C − 1) the area (mm²) of each cell of *flank*'s grid (rows wrap round the turn): half
    the cross product of its diagonals; the cell from the last row to the first has none on a
    flank that does not wrap (a linear cam's: its ends are the stroke's, far apart)."""
    p = flank.points
    q = np.roll(p, -1, axis=0)
    area = 0.5 * np.linalg.norm(np.cross(q[:, 1:] - p[:, :-1], p[:, 1:] - q[:, :-1]), axis=2)
    if not wraps:
        area[-1] = 0.0
    return area


def _corners(values: Array, s: Array, t: Array) -> tuple[Array, Array, Array, Array, Array,
                                                         Array]:
    """The four corners (N, 3) of the cells of *values* ((R, C, 3), a flank's grid) holding the
    grid coordinates (s, t) (s wraps round the rows, t is clamped to the columns), and (u, v),
    (N, 1) each, the coordinates within the cell."""
    rows, cols = values.shape[:2]
    i0 = np.floor(s).astype(np.intp)
    j = np.clip(np.floor(t).astype(np.intp), 0, cols - 2)
    u, v = (s - i0)[:, None], (t - j)[:, None]
    i, i1 = i0 % rows, (i0 + 1) % rows
    return values[i, j], values[i1, j], values[i, j + 1], values[i1, j + 1], u, v


def bilinear(flank: FlankGrid, s: Array, t: Array) -> tuple[Array, Array, Array]:
    """The point (N, 3, mm) of *flank*'s grid at grid coordinates (s, t) (row, wrapping round
    the turn, and column, clamped to the grid; fractional), bilinear in its cell, and its
    derivatives along s and t."""
    p00, p10, p01, p11, u, v = _corners(flank.points, s, t)
    point = (1 - u) * (1 - v) * p00 + u * (1 - v) * p10 + (1 - u) * v * p01 + u * v * p11
    along = (1 - v) * (p10 - p00) + v * (p11 - p01)
    over = (1 - u) * (p01 - p00) + u * (p11 - p10)
    return point, along, over


def unit_normal(flank: FlankGrid, s: Array, t: Array) -> Array:
    """*flank*'s unit normal (N, 3) at grid coordinates (s, t): its nodes' normals bilinear in
    the cell, made unit."""
    n00, n10, n01, n11, u, v = _corners(flank.normals, s, t)
    n = (1 - u) * (1 - v) * n00 + u * (1 - v) * n10 + (1 - u) * v * n01 + u * v * n11
    return n / np.linalg.norm(n, axis=1)[:, None]


def across_at(flank: FlankGrid, t: Array) -> Array:
    """The position across *flank* (mm, its ``across``) at fractional columns *t*."""
    return np.interp(t, np.arange(flank.across.size, dtype=float), flank.across)


@dataclass(frozen=True)
class Foot:
    """The feet of points on a flank: their grid coordinates (s, t) (fractional row and
    column), the foot points and unit normals (N, 3), the points' signed distance from
    them along the normal (mm), and whether each foot lies inside the flank (not clamped to its
    first or last column with the point beside it)."""

    s: Array
    t: Array
    points: Array
    normals: Array
    deviation: Array
    inside: Array

    @classmethod
    def of(cls, flank: FlankGrid, points: Array, s: Array, t: Array) -> Foot:
        """The feet of *points* (N, 3, mm) on *flank*'s grid (bilinear in its cells), by
        Gauss–Newton from the grid coordinates (s, t)."""
        last = flank.points.shape[1] - 1.0
        s, t = np.asarray(s, float), np.clip(np.asarray(t, float), 0.0, last)
        for _ in range(FOOT_ITERATIONS):
            foot, ds, dt = bilinear(flank, s, t)
            gap = points - foot
            a11, a12 = np.einsum("ij,ij->i", ds, ds), np.einsum("ij,ij->i", ds, dt)
            a22 = np.einsum("ij,ij->i", dt, dt)
            b1, b2 = np.einsum("ij,ij->i", ds, gap), np.einsum("ij,ij->i", dt, gap)
            det = a11 * a22 - a12 * a12
            s = s + (a22 * b1 - a12 * b2) / det
            t = np.clip(t + (a11 * b2 - a12 * b1) / det, 0.0, last)
        foot, _, _ = bilinear(flank, s, t)
        normals = unit_normal(flank, s, t)
        gap = points - foot
        deviation = np.einsum("ij,ij->i", gap, normals)
        beside = np.linalg.norm(gap - deviation[:, None] * normals, axis=1)
        return cls(s, t, foot, normals, deviation, beside <= OFF_GRID_MM)


# -- the other surfaces --------------------------------------------------------------------------

def other_points(part: Part, count: int, rng: np.random.Generator) -> tuple[Array, Array]:
    """*count* points (mm, cam frame) uniform by area on the part's mesh off every flank, and
    their facets' unit normals (outward): points drawn on the whole mesh, those on a flank
    dropped, until there are enough."""
    if count == 0 or not len(part.faces):
        return np.zeros((0, 3)), np.zeros((0, 3))
    tri = part.vertices[part.faces]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    area = np.linalg.norm(cross, axis=1)
    keep = area > 0
    tri, cross, area = tri[keep], cross[keep], area[keep]
    chosen, chosen_normals = [], []
    found, share = 0, 0.5
    while found < count:
        draw = int((count - found) / share * 1.1) + 100
        face = rng.choice(len(tri), size=draw, p=area / area.sum())
        r1, r2 = np.sqrt(rng.random(draw)), rng.random(draw)
        a, b, c = tri[face, 0], tri[face, 1], tri[face, 2]
        p = (1 - r1)[:, None] * a + (r1 * (1 - r2))[:, None] * b + (r1 * r2)[:, None] * c
        off = ~on_a_flank(part, p)
        share = max(float(off.mean()), 0.01)
        chosen.append(p[off])
        chosen_normals.append(cross[face[off]] / area[face[off], None])
        found += int(off.sum())
    return np.concatenate(chosen)[:count], np.concatenate(chosen_normals)[:count]


def on_a_flank(part: Part, points: Array) -> Array:
    """Which *points* (N, 3, mm) lie on one of *part*'s flanks: their foot on it inside it,
    within :data:`ON_FLANK_MM` of it."""
    on = np.zeros(len(points), dtype=bool)
    for f, tree in zip(part.model.flanks, part.trees, strict=True):
        distance, k = tree.query(points, distance_upper_bound=ON_FLANK_MM + max_cell(f),
                                         workers=-1)
        near = np.flatnonzero(np.isfinite(distance))
        row, col = np.divmod(k[near], f.points.shape[1])
        foot = Foot.of(f, points[near], row.astype(float), col.astype(float))
        on[near] |= foot.inside & (np.abs(foot.deviation) <= ON_FLANK_MM)
    return on


def max_cell(flank: FlankGrid) -> float:
    """The longest diagonal (mm) of a cell of *flank*'s grid."""
    p = flank.points
    q = np.roll(p, -1, axis=0)
    return float(max(np.linalg.norm(q[:, 1:] - p[:, :-1], axis=2).max(),
                     np.linalg.norm(p[:, 1:] - q[:, :-1], axis=2).max()))


# -- rigid motions -------------------------------------------------------------------------------

def turn_z(angle: float) -> Array:
    """The turn (3, 3) by *angle* (rad) about Z, counter-clockwise seen from +Z."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rigid_motion(whole_phase_deg: float,
                 misplace: tuple[float, float, float, float, float, float] | None
                 ) -> tuple[Array, Array]:
    """(R, t): a turn of *whole_phase_deg* about Z, then *misplace* (rx, ry, rz in degrees about
    the fixed X, Y, Z axes in turn, then the shift tx, ty, tz in mm)."""
    rotation = turn_z(math.radians(whole_phase_deg))
    translation = np.zeros(3)
    if misplace is not None:
        rx, ry, rz, *shift = misplace
        cx, sx = math.cos(math.radians(rx)), math.sin(math.radians(rx))
        cy, sy = math.cos(math.radians(ry)), math.sin(math.radians(ry))
        about_x = np.array([[1.0, 0.0, 0.0], [0.0, cx, -sx], [0.0, sx, cx]])
        about_y = np.array([[cy, 0.0, sy], [0.0, 1.0, 0.0], [-sy, 0.0, cy]])
        rotation = turn_z(math.radians(rz)) @ about_y @ about_x @ rotation
        translation = np.array(shift, dtype=float)
    return rotation, translation
