"""A scan's points against the exact flanks: which flank each point lies on, its signed deviation
from it, the points set aside, and the flanks as the scan shows them (the fitted surface).

Each point (in the cam's frame, after alignment) is matched to the nearest node of the flank
grids (a k-d tree of them, scipy's ``cKDTree``). Its **deviation** is its distance from that
node's tangent plane along the node's normal: positive where the point stands out of the
design's surface (material left on), negative where it lies under it. The nodes are close
enough (a tenth of a degree by a quarter of a millimetre) that the tangent plane's own error is
well under a micrometre for any flank camfab makes.

A point is **set aside** — counted, not judged — when it lies off every flank: farther along the
surface from its nearest node than the nodes are apart (on the ends, the groove's floor, the
outer surface, the bore, the fixture), or farther from the surface than the *gate* (stray
points, the table).

The **fitted surface** is each flank's grid with every node moved along its normal by the mean
deviation of the points matched within ±*fit*/2 of it (along the rows and across), NaN where
fewer than :data:`MIN_FIT_POINTS` were: a box average of the scan's deviation, which keeps a
bump wider than the box and averages a scanner's noise over the box's points.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from camfab.arrays import Array, Index, Mask
from camfab.inspect.surface import ScanModel

#: A step between a flank's rows longer than this many times their median is a seam, not a
#: step: the rows at either end of a linear cam's stroke are no neighbours.
SEAM_STEPS = 4.0

#: Fewest points averaged into a node of the fitted surface.
MIN_FIT_POINTS = 3

#: Points matched to the nodes at once (bounds the working memory).
_BLOCK = 500_000


@dataclass(frozen=True)
class Nodes:
    """Every flank's nodes, flattened: flank index, row, column, point (mm), unit normal, and
    the node's spacing (mm: the larger of the distances to its neighbours along the row and
    across)."""

    flank: Index
    row: Index
    col: Index
    points: Array
    normals: Array
    spacing: Array

    @cached_property
    def tree(self) -> Any:
        """A k-d tree of the nodes' points (scipy's ``cKDTree``)."""
        from scipy.spatial import cKDTree

        return cKDTree(self.points)


def flank_nodes(model: ScanModel) -> Nodes:
    """The nodes of *model*'s flanks (see :class:`Nodes`)."""
    flank, row, col, points, normals, spacing = [], [], [], [], [], []
    for index, f in enumerate(model.flanks):
        rows, cols = f.points.shape[:2]
        along = np.linalg.norm(np.roll(f.points, -1, axis=0) - f.points, axis=2)
        # (a seam that joins no neighbours, as a linear cam's ends, counts as a usual step)
        along = np.minimum(along, SEAM_STEPS * float(np.median(along)))
        along = np.maximum(along, np.roll(along, 1, axis=0))
        gaps = np.linalg.norm(np.diff(f.points, axis=1), axis=2)
        across = np.maximum(np.pad(gaps, ((0, 0), (0, 1)), mode="edge"),
                            np.pad(gaps, ((0, 0), (1, 0)), mode="edge"))
        r, c = np.meshgrid(np.arange(rows), np.arange(cols), indexing="ij")
        flank.append(np.full(rows * cols, index))
        row.append(r.ravel())
        col.append(c.ravel())
        points.append(f.points.reshape(-1, 3))
        normals.append(f.normals.reshape(-1, 3))
        spacing.append(np.maximum(along, across).ravel())
    return Nodes(np.concatenate(flank), np.concatenate(row), np.concatenate(col),
                 np.concatenate(points), np.concatenate(normals), np.concatenate(spacing))


@dataclass(frozen=True)
class PointDeviations:
    """Each scan point's flank (−1: set aside), row and column of its nearest node, and its
    deviation (mm, + material left on; NaN where set aside)."""

    flank: Index
    row: Index
    col: Index
    deviation: Array
    off_surface: int
    beyond_gate: int

    @property
    def aside(self) -> int:
        return self.off_surface + self.beyond_gate


class Others:
    """The part's surfaces that are no flank (its ends, bore, outer surface, a groove's floor):
    samples of its mesh's faces that lie on no flank, with their normals and spacing (mm)."""

    def __init__(self, model: ScanModel, nodes: Nodes,
                 samples: tuple[Array, Array, Array] | None = None) -> None:
        """*samples*: :func:`~camfab.inspect.models.part_mesh.part_samples` of *model*, when
        already made."""
        from scipy.spatial import cKDTree

        from camfab.inspect.models.part_mesh import part_samples

        points, normals, spacing = part_samples(model) if samples is None else samples
        if len(points):
            on_flank = ~_off_flanks(points, nodes, ON_FLANK_MM)
            points, normals, spacing = points[~on_flank], normals[~on_flank], spacing[~on_flank]
        self.points, self.normals, self.spacing = points, normals, spacing
        self.tree = cKDTree(points) if len(points) else None

    def nearer(self, points: Array, deviation: Array, normals: Array) -> Mask:
        """Which *points* lie nearer one of these surfaces than their flank (*deviation*, mm,
        from it, whose normal there is *normals*): within a sample's spacing along it, nearer
        its plane, and it another surface (its normal more than :data:`OTHER_ANGLE_DEG` from
        the flank's: not the flank's own continuation past its grid)."""
        if self.tree is None or not len(points):
            return np.zeros(len(points), dtype=bool)
        bound = float(np.abs(deviation).max()) + float(self.spacing.max())
        distance, k = self.tree.query(points, distance_upper_bound=bound, workers=-1)
        found = np.isfinite(distance)
        out = np.zeros(len(points), dtype=bool)
        k = k[found]
        d, sideways = _plane_offsets(points[found], self.points[k], self.normals[k])
        other = np.abs(np.einsum("ij,ij->i", self.normals[k], normals[found])) \
            < math.cos(math.radians(OTHER_ANGLE_DEG))
        out[found] = (np.abs(d) < np.abs(deviation[found])) & (sideways <= self.spacing[k]) \
            & other
        return out


#: Least angle (deg) between a surface's normal and a flank's for it to be another surface.
OTHER_ANGLE_DEG = 20.0

#: How near a flank (mm) a sample of the part's mesh lies when it is on it: the mesh holds the
#: flank within a few micrometres.
ON_FLANK_MM = 0.02


def _off_flanks(points: Array, nodes: Nodes, within: float) -> Mask:
    """Which *points* lie off every flank: beyond a node's spacing along it, or *within* mm of
    it no more."""
    nearest, deviation, sideways = _match(points, nodes, within + nodes.spacing.max())
    return (nearest < 0) | (sideways > nodes.spacing[nearest]) | (np.abs(deviation) > within)


def _plane_offsets(points: Array, bases: Array, normals: Array) -> tuple[Array, Array]:
    """Each of *points*' distance (mm) from the plane through its base point with its unit
    normal, along the normal (signed), and its distance from the base point along the plane."""
    offset = points - bases
    d = np.einsum("ij,ij->i", offset, normals)
    return d, np.linalg.norm(offset - d[:, None] * normals, axis=1)


def _match(points: Array, nodes: Nodes, within: float) -> tuple[Index, Array, Array]:
    """Each point's nearest node (−1 beyond *within* mm of every node), its distance from the
    node's tangent plane along the node's normal and its distance from the node along that plane
    (mm; inf beyond *within*). Points far from every node end the tree's search early."""
    count = len(points)
    nearest = np.full(count, -1, dtype=np.int64)
    deviation = np.full(count, np.inf)
    sideways = np.full(count, np.inf)
    for start in range(0, count, _BLOCK):
        block = points[start:start + _BLOCK]
        distance, k = nodes.tree.query(block, distance_upper_bound=within, workers=-1)
        found = np.flatnonzero(np.isfinite(distance))
        k = k[found]
        nearest[start + found] = k
        deviation[start + found], sideways[start + found] = _plane_offsets(
            block[found], nodes.points[k], nodes.normals[k])
    return nearest, deviation, sideways


def point_deviations(points: Array, nodes: Nodes, others: Others, gate: float
                     ) -> PointDeviations:
    """Match *points* (N, 3, mm, cam frame) to *nodes*; set aside those off every flank, on
    one of the *others*, or beyond *gate* (mm) from their flank (see the module)."""
    nearest, deviation, sideways = _match(points, nodes, gate + nodes.spacing.max())
    off = (nearest < 0) | (sideways > nodes.spacing[nearest])
    near = ~off & (np.abs(deviation) <= gate)
    on_other = np.zeros(len(points), dtype=bool)
    on_other[near] = others.nearer(points[near], deviation[near],
                                   nodes.normals[nearest[near]])
    off |= on_other
    far = ~off & (np.abs(deviation) > gate)
    kept = ~(off | far)
    flank = np.where(kept, nodes.flank[nearest], -1)
    return PointDeviations(flank, nodes.row[nearest], nodes.col[nearest],
                           np.where(kept, deviation, np.nan), int(np.count_nonzero(off)),
                           int(np.count_nonzero(far)))


def fitted_deviation(model: ScanModel, dev: PointDeviations, fit: float) -> list[Array]:
    """Per flank, the (R, C) mean deviation (mm) of the points matched within the box of
    *fit* (mm) about each node; NaN where fewer than :data:`MIN_FIT_POINTS` were."""
    from scipy.ndimage import uniform_filter

    out = []
    for index, f in enumerate(model.flanks):
        rows, cols = f.points.shape[:2]
        on = dev.flank == index
        cell = dev.row[on] * cols + dev.col[on]
        sums = np.bincount(cell, weights=dev.deviation[on], minlength=rows * cols)
        counts = np.bincount(cell, minlength=rows * cols).astype(np.float64)
        along = float(np.median(np.linalg.norm(np.roll(f.points, -1, axis=0) - f.points,
                                               axis=2)))
        across = float(np.median(np.linalg.norm(np.diff(f.points, axis=1), axis=2))) \
            if cols > 1 else fit
        size = (_box(fit, along, rows), _box(fit, across, cols))
        mode = ("wrap", "constant")
        total = uniform_filter(sums.reshape(rows, cols), size, mode=mode) * (size[0] * size[1])
        number = uniform_filter(counts.reshape(rows, cols), size, mode=mode) * (size[0] * size[1])
        with np.errstate(invalid="ignore", divide="ignore"):
            mean = total / number
        out.append(np.where(number >= MIN_FIT_POINTS - 1e-6, mean, np.nan))
    return out


def _box(fit: float, spacing: float, most: int) -> int:
    """Nodes in a box of *fit* mm at *spacing* mm: odd, from 1 to *most*."""
    n = min(max(1, round(fit / spacing) if spacing > 0.0 else 1), most)
    return n if n % 2 else n - 1


def fitted_surface(flank_points: Array, normals: Array, deviation: Array) -> Array:
    """The flank's nodes moved by *deviation* (mm) along their normals (NaN where it is)."""
    return flank_points + deviation[..., None] * normals


@dataclass(frozen=True)
class FlankStats:
    """A flank's surface deviation (mm) over its matched points."""

    name: str
    points: int
    mean: float
    std: float
    rms: float
    low: float
    high: float
    p01: float
    p99: float
    over: int

    def to_json(self) -> dict[str, float | int | str]:
        return {"flank": self.name, "points": self.points, "mean_mm": self.mean,
                "std_mm": self.std, "rms_mm": self.rms, "min_mm": self.low, "max_mm": self.high,
                "p01_mm": self.p01, "p99_mm": self.p99, "over_tolerance": self.over}


def flank_stats(model: ScanModel, dev: PointDeviations, tolerance: float | None
                ) -> list[FlankStats]:
    """Each flank's deviation statistics (see :class:`FlankStats`)."""
    out = []
    for index, f in enumerate(model.flanks):
        d = dev.deviation[dev.flank == index]
        if not len(d):
            out.append(FlankStats(f.name, 0, *([math.nan] * 7), 0))
            continue
        p01, p99 = np.percentile(d, [1.0, 99.0])
        over = int(np.count_nonzero(np.abs(d) > tolerance)) if tolerance else 0
        out.append(FlankStats(f.name, len(d), float(d.mean()), float(d.std()),
                              float(np.sqrt(np.mean(d * d))), float(d.min()), float(d.max()),
                              float(p01), float(p99), over))
    return out
