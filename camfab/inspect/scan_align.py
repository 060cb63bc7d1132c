"""Aligning a scan to the cam's frame (``align_scan``): the rigid motion that carries the
scanner's frame onto the cam's (its axis Z, drawn at cam angle 0), found by a best fit of the
points to the exact part.

The target is the part as designed: its functional surfaces (the flank grids, exact) and the
rest of it (the ends, the bore, the outer surface: the faces of its STL mesh, sampled about
half a millimetre apart by :func:`~camfab.inspect.models.part_mesh.surface_samples`). A
point's distance is measured to the nearest target sample's tangent plane (point-to-plane).

- **Fixtured** (``fixtured=True``): the scan is in the cam's frame (a CMM with the part on its
  fixture) up to the turn about the cam axis: the phase is found by a search over the whole turn
  (every :data:`COARSE_PHASE_DEG`) on a sample of the points, then refined by least squares.
- **Free**: the whole rigid motion. The start: the cam axis is the direction that the points'
  normals (the file's, or each point's neighbours' plane) single out — the surfaces of a cam are
  mostly surfaces of revolution about it and faces across it, so in the normals' scatter matrix
  Σ n nᵀ the axis is the eigenvector whose eigenvalue differs from the other two, which are
  alike; the centre is the circle fitted to the points whose normals are across the axis,
  matched with the same fit of the part; the height matches the ends. Both senses of the axis
  and, for each, the phase over the whole turn are tried, and the identity besides; the best
  start is then iterated (trimmed point-to-plane ICP, 6 degrees of freedom, linearised).

Points farther from the target than a gate that shrinks from :data:`START_GATE_MM` to
:data:`FINAL_GATE_MM` do not pull the fit (the fixture, the table, stray points).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camfab.arrays import Array
from camfab.inspect.models.part_mesh import surface_samples
from camfab.inspect.surface import ScanModel

#: Points used to search the phase, and to iterate the fit (a deterministic sample).
SEARCH_POINTS = 1500
FIT_POINTS = 20_000

#: Steps of the phase search (deg): coarse over the turn, then fine about the best (the fit's
#: iterations take it from within a fine step).
COARSE_PHASE_DEG = 2.0
FINE_PHASE_DEG = 0.25

#: Size (mm) of the cells of the phase search's occupancy grid: a point counts when it lies in
#: a cell next to one holding a sample of the part (within about one to two cells).
SEARCH_CELL_MM = 0.5

#: The fit's gate on a point's distance from the target (mm): from the first iteration's to the
#: last's.
START_GATE_MM = 5.0
FINAL_GATE_MM = 1.0

#: Most iterations of the fit, and the update (rad, mm) below which it has converged.
MAX_ITERATIONS = 60
CONVERGED = 1e-6

#: Neighbours of a point whose plane gives its normal when the file has none.
NORMAL_NEIGHBOURS = 12


@dataclass(frozen=True)
class Alignment:
    """The rigid motion p ↦ R p + t (mm) from the scanner's frame to the cam's.

    Attributes
    ----------
    rotation, translation
        R (3, 3) and t (3,), mm.
    mode
        "fixtured" (only the turn about the cam axis was fitted) or "free".
    residual_mm
        RMS distance of the points that counted in the last iteration from the part (mm).
    used
        How many points counted in it.
    iterations
        Iterations of the fit.
    start
        How the fit started, in words.
    """

    rotation: Array
    translation: Array
    mode: str
    residual_mm: float
    used: int
    iterations: int
    start: str

    def apply(self, points: Array) -> Array:
        """*points* (N, 3, scanner's frame, mm) in the cam's frame."""
        return points @ self.rotation.T + self.translation

    @property
    def phase_deg(self) -> float:
        """The turn about the cam axis (deg, counter-clockwise seen from +Z) the fit applied."""
        return math.degrees(math.atan2(self.rotation[1, 0], self.rotation[0, 0]))

    @property
    def tilt_deg(self) -> float:
        """The angle (deg) between the scanner's Z and the cam axis."""
        return math.degrees(math.acos(min(1.0, abs(float(self.rotation[2, 2])))))


class Target:
    """The part as designed, sampled for the fit: points (M, 3, mm) with their unit normals
    (out of the material), and a k-d tree of the points."""

    def __init__(self, points: Array, normals: Array) -> None:
        from scipy.spatial import cKDTree

        self.points, self.normals = points, normals
        self.tree = cKDTree(points)
        self.low = points.min(axis=0) - 4.0 * SEARCH_CELL_MM
        cells = self._cells(points)
        shifts = np.stack(np.meshgrid(*[np.arange(-1, 2)] * 3, indexing="ij"), -1).reshape(-1, 3)
        self.size = cells.max(axis=0) + 3
        self.occupied = np.unique(self._keys((cells[:, None, :] + shifts[None]).reshape(-1, 3)))

    def _cells(self, points: Array) -> Array:
        return np.floor((points - self.low) / SEARCH_CELL_MM).astype(np.int64)

    def _keys(self, cells: Array) -> Array:
        inside = np.all((cells >= 0) & (cells < self.size), axis=1)
        keys = (cells[:, 0] * self.size[1] + cells[:, 1]) * self.size[2] + cells[:, 2]
        return np.where(inside, keys, -1)

    def hits(self, points: Array) -> int:
        """How many of *points* lie within a cell or so of the part (the occupancy grid's
        count: a quick measure of how well they fit, for the phase search)."""
        keys = self._keys(self._cells(points))
        at = np.clip(np.searchsorted(self.occupied, keys), 0, len(self.occupied) - 1)
        return int(np.count_nonzero((self.occupied[at] == keys) & (keys >= 0)))

    def planes(self, points: Array, bound: float) -> tuple[Array, Array, Array]:
        """The points within *bound* (mm) of a sample (a mask), and their nearest samples'
        points and normals."""
        distance, k = self.tree.query(points, distance_upper_bound=bound, workers=-1)
        near = np.isfinite(distance)
        return near, self.points[k[near]], self.normals[k[near]]


def target_of(model: ScanModel) -> Target:
    """The flanks' nodes (every other row and column) and the part's mesh faces sampled."""
    points, normals = [], []
    for flank in model.flanks:
        points.append(flank.points[::2, ::2].reshape(-1, 3))
        normals.append(flank.normals[::2, ::2].reshape(-1, 3))
    vertices, faces = model.reference_mesh()
    if len(faces):
        p, n, _ = surface_samples(vertices, faces)
        points.append(p)
        normals.append(n)
    return Target(np.concatenate(points), np.concatenate(normals))


def align_scan(points: Array, normals: Array | None, model: ScanModel, *,
               fixtured: bool) -> Alignment:
    """The rigid motion carrying *points* (N, 3, mm, with unit *normals* or None) onto the part
    of *model* (see the module)."""
    target = target_of(model)
    search = points[_sample(len(points), SEARCH_POINTS)]
    if fixtured:
        phase = _phase_search(search, np.eye(3), np.zeros(3), target)
        rotation, translation, start = _turn_z(phase), np.zeros(3), (
            f"the scan's own frame, turned {math.degrees(phase):.4g}° about the cam axis by a "
            "search of the whole turn")
    else:
        rotation, translation, start = _free_start(points, normals, search, target)
    fit = points[_sample(len(points), FIT_POINTS)]
    return _iterate(fit, rotation, translation, target, fixtured, start)


def _sample(count: int, most: int) -> Array:
    """Indices of at most *most* of *count* points, evenly spread through the file's order."""
    if count <= most:
        return np.arange(count)
    return np.linspace(0, count - 1, most).astype(np.int64)


def _turn_z(angle: float) -> Array:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _score(points: Array, target: Target) -> float:
    """Lower is better: the share of *points* away from the part."""
    return 1.0 - target.hits(points) / max(1, len(points))


def _phase_search(points: Array, rotation: Array, translation: Array, target: Target) -> float:
    """The turn about Z (rad), applied after the rigid motion (R, t), that brings *points*
    nearest the target: the best of a coarse search over the whole turn, refined."""
    moved = points @ rotation.T + translation
    coarse = np.radians(np.arange(0.0, 360.0, COARSE_PHASE_DEG))
    scores = [_score(moved @ _turn_z(a).T, target) for a in coarse.tolist()]
    best = float(coarse[int(np.argmin(scores))])
    fine = best + np.radians(np.arange(-COARSE_PHASE_DEG, COARSE_PHASE_DEG + 1e-9,
                                       FINE_PHASE_DEG))
    scores = [_score(moved @ _turn_z(a).T, target) for a in fine.tolist()]
    return float(fine[int(np.argmin(scores))])


def _free_start(points: Array, normals: Array | None, search: Array, target: Target
                ) -> tuple[Array, Array, str]:
    """The best start of a free fit: the identity, or the axis and centre the points' normals
    and circles give, each turned by the best phase."""
    starts = [(np.eye(3), np.zeros(3), "the scanner's frame")]
    axis_start = _axis_start(points, normals, target)
    if axis_start is not None:
        for sense in (1.0, -1.0):
            rotation, translation = axis_start(sense)
            starts.append((rotation, translation, "the cam axis and centre found from the "
                           "scan's surfaces of revolution"))
    best: tuple[float, Array, Array, str] | None = None
    for rotation, translation, words in starts:
        phase = _phase_search(search, rotation, translation, target)
        turned = _turn_z(phase)
        r, t = turned @ rotation, turned @ translation
        score = _score(search @ r.T + t, target)
        if best is None or score < best[0]:
            best = (score, r, t, f"{words}, turned {math.degrees(phase):.4g}° about the cam axis "
                                 "by a search of the whole turn")
    assert best is not None
    return best[1], best[2], best[3]


def _axis_start(points: Array, normals: Array | None, target: Target):  # type: ignore[no-untyped-def]
    """A function of the axis's sense (±1) giving the start (R, t) that carries the scan's axis
    onto Z, its centre onto the part's, its ends onto the part's; None when the normals single
    out no axis."""
    picked = _sample(len(points), 20_000)
    sample = points[picked]
    n = normals[picked] if normals is not None else _estimated_normals(points, sample)
    axis = _odd_axis(n)
    ref_axis = np.array([0.0, 0.0, 1.0])
    if axis is None:
        return None
    scan_centre = _circle_centre(sample, n, axis)
    part_centre = _circle_centre(target.points, target.normals, ref_axis)
    if scan_centre is None or part_centre is None:
        return None
    along = sample @ axis
    ref_along = target.points[:, 2]
    scan_span = np.percentile(along, [0.5, 99.5])
    ref_span = np.percentile(ref_along, [0.5, 99.5])

    def start(sense: float) -> tuple[Array, Array]:
        rotation = _rotation_onto(sense * axis, ref_axis)
        lo, hi = (scan_span if sense > 0 else -scan_span[::-1])
        centre = rotation @ scan_centre
        translation = np.array([part_centre[0] - centre[0], part_centre[1] - centre[1],
                                0.5 * ((ref_span[0] - lo) + (ref_span[1] - hi))])
        return rotation, translation

    return start


def _estimated_normals(points: Array, at: Array) -> Array:
    """Unit normals at *at* from the plane of their :data:`NORMAL_NEIGHBOURS` nearest *points*
    (the smallest principal direction of the neighbours' scatter), of either sense."""
    from scipy.spatial import cKDTree

    _, k = cKDTree(points).query(at, k=NORMAL_NEIGHBOURS, workers=-1)
    near = points[k] - points[k].mean(axis=1, keepdims=True)
    scatter = np.einsum("nki,nkj->nij", near, near)
    _, vectors = np.linalg.eigh(scatter)
    return vectors[:, :, 0]


def _odd_axis(normals: Array) -> Array | None:
    """The eigenvector of Σ n nᵀ whose eigenvalue stands apart from the other two (the axis of a
    part of surfaces of revolution and faces across it); None when no eigenvalue does."""
    values, vectors = np.linalg.eigh(normals.T @ normals / len(normals))
    gaps = (values[1] - values[0], values[2] - values[1])
    if max(gaps) < 0.05:
        return None
    k = 0 if gaps[0] > gaps[1] else 2
    return vectors[:, k] / np.linalg.norm(vectors[:, k])


def _circle_centre(points: Array, normals: Array, axis: Array) -> Array | None:
    """The centre (mm, in the points' frame, on the plane through the origin across *axis*) of
    the circle fitted (algebraically, Kåsa) to the points whose normals lie across the axis."""
    across = np.abs(normals @ axis) < 0.2
    if np.count_nonzero(across) < 10:
        return None
    u = np.cross(axis, [1.0, 0.0, 0.0] if abs(axis[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    v = np.cross(axis, u)
    x, y = points[across] @ u, points[across] @ v
    a = np.column_stack((x, y, np.ones_like(x)))
    (cx, cy, _), *_ = np.linalg.lstsq(a, x * x + y * y, rcond=None)
    return 0.5 * cx * u + 0.5 * cy * v


def _rotation_onto(a: Array, b: Array) -> Array:
    """The rotation turning unit vector *a* onto unit vector *b* (the shortest)."""
    v, c = np.cross(a, b), float(a @ b)
    if c < -1.0 + 1e-12:
        axis = np.cross(a, [1.0, 0.0, 0.0] if abs(a[0]) < 0.9 else [0.0, 1.0, 0.0])
        axis /= np.linalg.norm(axis)
        return 2.0 * np.outer(axis, axis) - np.eye(3)
    k = np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])
    return np.eye(3) + k + k @ k / (1.0 + c)


def _rodrigues(w: Array) -> Array:
    angle = float(np.linalg.norm(w))
    if angle < 1e-15:
        return np.eye(3)
    k = w / angle
    km = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + math.sin(angle) * km + (1.0 - math.cos(angle)) * km @ km


def _iterate(points: Array, rotation: Array, translation: Array, target: Target,
             fixtured: bool, start: str) -> Alignment:
    """Trimmed point-to-plane iterations from (R, t): each solves the linearised least squares
    for a small turn ω and shift τ (only ω about Z when *fixtured*)."""
    gate = START_GATE_MM
    used, residual, iterations = 0, math.nan, 0
    while iterations < MAX_ITERATIONS:
        iterations += 1
        moved = points @ rotation.T + translation
        near, q, n = target.planes(moved, gate)
        if np.count_nonzero(near) < 6:
            break
        p = moved[near]
        d = np.einsum("ij,ij->i", p - q, n)
        spread = float(np.median(np.abs(d)))
        keep = np.abs(d) <= max(4.0 * 1.4826 * spread, 0.02)
        p, n, d = p[keep], n[keep], d[keep]
        used, residual = len(d), float(np.sqrt(np.mean(d * d)))
        cross = np.cross(p, n)
        if fixtured:
            a = cross[:, 2:3]
            step, *_ = np.linalg.lstsq(a, -d, rcond=None)
            w, tau = np.array([0.0, 0.0, step[0]]), np.zeros(3)
        else:
            a = np.hstack((cross, n))
            step, *_ = np.linalg.lstsq(a, -d, rcond=None)
            w, tau = step[:3], step[3:]
        turn = _rodrigues(w)
        rotation, translation = turn @ rotation, turn @ translation + tau
        gate = max(FINAL_GATE_MM, 0.6 * gate)
        small = max(float(np.linalg.norm(w)), float(np.linalg.norm(tau))) < CONVERGED
        if small and gate == FINAL_GATE_MM:
            break
    return Alignment(rotation, translation, "fixtured" if fixtured else "free", residual, used,
                     iterations, start)
