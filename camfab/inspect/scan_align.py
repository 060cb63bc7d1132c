"""Aligning a scan to the cam's frame (``align_scan``): the rigid motion that carries the
scanner's frame onto the cam's (its axis Z, drawn at cam angle 0), found by a best fit of the
points to the exact part.

The target is the part as designed: its functional surfaces (the flank grids, exact) and the
rest of it (the ends, the bore, the outer surface: the faces of its STL mesh, sampled about
half a millimetre apart by :func:`~camfab.inspect.models.part_mesh.surface_samples`). A
point's distance is measured to the nearest target sample's tangent plane (point-to-plane).

- **Fixtured** (``fixtured=True``): the scan is in the cam's frame (a CMM with the part on its
  fixture) up to the turn about the cam axis (a linear cam's plate: up to a shift along its
  travel, X): the phase is found by a search over the whole turn
  (in steps that move the flanks by a cell, :data:`SEARCH_CELL_MM`) on a sample of the points,
  then refined by least squares.
- **Free**: the whole rigid motion. The start: the cam axis is the direction that the points'
  normals (the file's, or each point's neighbours' plane) single out — the surfaces of a cam are
  mostly surfaces of revolution about it and faces across it, so in the normals' scatter matrix
  Σ n nᵀ the axis is the eigenvector whose eigenvalue differs from the other two, which are
  alike; the centre is the circle fitted to the points whose normals are across the axis,
  matched with the same fit of the part; the height matches the ends (a linear cam's plate is
  then laid with its long axis along the part's, either way). Both senses of the axis and the
  identity besides are starts; for each, the :data:`PHASE_CANDIDATES` best phases of a search
  over the turn (a plate's length) are tried for :data:`TRIAL_ITERATIONS` iterations, and the
  one that then sits best is iterated to the end (trimmed point-to-plane ICP, 6 degrees of
  freedom, linearised).

Points farther from the target than a gate that shrinks from :data:`START_GATE_MM` to
:data:`FINAL_GATE_MM` do not pull the fit (the fixture, the table, stray points); those within
it pull less the farther they lie (Cauchy's weights, :data:`FINAL_SOFT_MM`), so that points
matched across an edge to the wrong face do not bend it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camfab.arrays import Array
from camfab.inspect.models.part_mesh import part_samples
from camfab.inspect.surface import ScanModel

#: Points used to search the phase, to try each start, and to iterate the fit (deterministic
#: samples).
SEARCH_POINTS = 4000
TRIAL_POINTS = 5000
FIT_POINTS = 20_000

#: Phases tried from each start (the best local optima of the search), and the iterations of
#: each trial; the trial that then sits best (the mean of each point's distance, at most
#: :data:`MISFIT_CAP_MM`) is iterated to the end.
PHASE_CANDIDATES = 4
TRIAL_ITERATIONS = 15
MISFIT_CAP_MM = 1.0

#: Largest step of the phase search over the turn (deg); smaller where a cell at the flanks'
#: outer edge is less (then fifths of it about the best; the fit's iterations go on from there).
COARSE_PHASE_DEG = 1.0

#: Size (mm) of the cells of the phase search's occupancy grid: a point counts when it lies in
#: a cell next to one holding a sample of the part (within about one to two cells).
SEARCH_CELL_MM = 0.5

#: The fit's gate on a point's distance from the target (mm): from the first iteration's to the
#: last's.
START_GATE_MM = 5.0
FINAL_GATE_MM = 1.0

#: The scale (mm) of the weights the fit gives points by their distance (Cauchy's, 1/(1 +
#: (d/c)²)): c is three robust standard deviations of the distances, and no less than a quarter
#: of the gate while it shrinks, then halving to this.
FINAL_SOFT_MM = 0.02

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
        RMS distance from the part (mm) of the points within the weights' scale in the last
        iteration (the fit's core: stray points and edges left out).
    used
        How many points those were.
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


class Occupancy:
    """Which cells of a grid of :data:`SEARCH_CELL_MM` hold a sample of a surface, or touch one
    that does: whether a point lies within a cell or two of it, found by a sorted search of the
    cells' keys (a quick measure of fit for the phase search)."""

    def __init__(self, points: Array) -> None:
        self.low = points.min(axis=0) - 4.0 * SEARCH_CELL_MM
        cells = self._cells(points)
        self.size = cells.max(axis=0) + 3
        # the keys of the cells holding a sample and of the 26 about each: the cells next to
        # them along x, then along y, then along z (no key runs off its row: the grid leaves
        # room about the samples)
        occupied = _distinct(self._keys(cells))
        for stride in (self.size[1] * self.size[2], self.size[2], 1):
            occupied = _distinct((occupied[:, None] + np.array([-stride, 0, stride])).ravel())
        self.occupied = occupied

    def _cells(self, points: Array) -> Array:
        return np.floor((points - self.low) / SEARCH_CELL_MM).astype(np.int64)

    def _keys(self, cells: Array) -> Array:
        inside = np.all((cells >= 0) & (cells < self.size), axis=1)
        keys = (cells[:, 0] * self.size[1] + cells[:, 1]) * self.size[2] + cells[:, 2]
        return np.where(inside, keys, -1)

    def hits(self, points: Array) -> int:
        """How many of *points* lie in an occupied cell."""
        # (sorted, the keys are found in a third of the time: each search starts where the
        # last ended)
        keys = np.sort(self._keys(self._cells(points)))
        at = np.clip(np.searchsorted(self.occupied, keys), 0, len(self.occupied) - 1)
        return int(np.count_nonzero((self.occupied[at] == keys) & (keys >= 0)))


class Target:
    """The part as designed, sampled for the fit: points (M, 3, mm) with their unit normals
    (out of the material) and a k-d tree of them; the occupancy of the flanks' nodes (which
    alone tell the phase: the rest of a cam is mostly round) and their largest radius (mm)."""

    def __init__(self, points: Array, normals: Array, flanks: Array, slides: bool = False
                 ) -> None:
        from scipy.spatial import cKDTree

        self.points, self.normals = points, normals
        self.tree = cKDTree(points)
        self.flanks = Occupancy(flanks)
        self.reach = float(np.max(np.hypot(flanks[:, 0], flanks[:, 1])))
        #: A linear cam's plate: its phase is a shift along X over the flanks' length.
        self.slides = slides
        self.length = float(np.ptp(flanks[:, 0]))

    def planes(self, points: Array, bound: float) -> tuple[Array, Array, Array]:
        """The points within *bound* (mm) of a sample (a mask), and their nearest samples'
        points and normals."""
        distance, k = self.tree.query(points, distance_upper_bound=bound, workers=-1)
        near = np.isfinite(distance)
        return near, self.points[k[near]], self.normals[k[near]]


def _distinct(keys: Array) -> Array:
    """The distinct *keys* (integers), sorted: ``np.unique``'s answer, by a sort (numpy 2.4's
    ``unique`` of integers, by hashing, took 20 to 60 times as long on a million keys)."""
    keys = np.sort(keys)
    if len(keys) < 2:
        return keys
    return keys[np.concatenate(([True], keys[1:] != keys[:-1]))]


def target_of(model: ScanModel, samples: tuple[Array, Array, Array] | None = None) -> Target:
    """The flanks' nodes (every other row and column) and the part's mesh faces sampled
    (*samples*: :func:`~camfab.inspect.models.part_mesh.part_samples` of *model*, when already
    made)."""
    points, normals = [], []
    for flank in model.flanks:
        points.append(flank.points[::2, ::2].reshape(-1, 3))
        normals.append(flank.normals[::2, ::2].reshape(-1, 3))
    flanks = np.concatenate([f.points.reshape(-1, 3) for f in model.flanks])
    p, n, _ = part_samples(model) if samples is None else samples
    points.append(p)
    normals.append(n)
    return Target(np.concatenate(points), np.concatenate(normals), flanks,
                  bool(getattr(model, "slides", False)))


def align_scan(points: Array, normals: Array | None, model: ScanModel, *,
               fixtured: bool, samples: tuple[Array, Array, Array] | None = None) -> Alignment:
    """The rigid motion carrying *points* (N, 3, mm, with unit *normals* or None) onto the part
    of *model* (see the module; *samples* as :func:`target_of`'s)."""
    target = target_of(model, samples)
    search = points[_sample(len(points), SEARCH_POINTS)]
    trial = points[_sample(len(points), TRIAL_POINTS)]
    best: tuple[float, Alignment] | None = None
    for rotation, translation, start in _starts(points, normals, search, target, fixtured):
        tried = _iterate(trial, rotation, translation, target, fixtured, start,
                         TRIAL_ITERATIONS)
        misfit = _misfit(search, tried.rotation, tried.translation, target)
        if best is None or misfit < best[0]:
            best = (misfit, tried)
    assert best is not None
    fit = points[_sample(len(points), FIT_POINTS)]
    return _iterate(fit, best[1].rotation, best[1].translation, target, fixtured, best[1].start)


def _sample(count: int, most: int) -> Array:
    """Indices of at most *most* of *count* points, evenly spread through the file's order."""
    if count <= most:
        return np.arange(count)
    return np.linspace(0, count - 1, most).astype(np.int64)


def _turn_z(angle: float) -> Array:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _score(points: Array, target: Target) -> float:
    """Lower is better: the share of *points* away from the flanks."""
    return 1.0 - target.flanks.hits(points) / max(1, len(points))


def _phase_move(target: Target, phase: float) -> tuple[Array, Array]:
    """The rigid motion of a phase: a turn of *phase* rad about Z, or for a plate that slides a
    shift of *phase* mm along X."""
    if target.slides:
        return np.eye(3), np.array([phase, 0.0, 0.0])
    return _turn_z(phase), np.zeros(3)


def _phase_search(points: Array, rotation: Array, translation: Array, target: Target
                  ) -> list[float]:
    """Phases (:func:`_phase_move`), applied after the rigid motion (R, t), that bring the most
    of *points* near the flanks: the :data:`PHASE_CANDIDATES` best local optima of a search
    over the whole turn in steps that move the flanks' outer edge by a cell (or over the
    plate's length in steps of a cell), each refined in fifths of that step."""
    moved = points @ rotation.T + translation
    if target.slides:
        coarse_step = SEARCH_CELL_MM
        coarse = np.arange(-0.5 * target.length, 0.5 * target.length, coarse_step)
    else:
        coarse_step = min(math.radians(COARSE_PHASE_DEG), SEARCH_CELL_MM / target.reach)
        coarse = np.arange(0.0, 2.0 * math.pi, coarse_step)

    def score(phase: float) -> float:
        r, t = _phase_move(target, phase)
        return _score(moved @ r.T + t, target)

    scores = np.array([score(a) for a in coarse.tolist()])
    lowest = (scores <= np.roll(scores, 1)) & (scores <= np.roll(scores, -1))
    order = [int(k) for k in np.argsort(scores, kind="stable") if lowest[k]]
    found = []
    for k in order[:PHASE_CANDIDATES]:
        fine = coarse[k] + np.linspace(-coarse_step, coarse_step, 11)
        found.append(float(fine[int(np.argmin([score(a) for a in fine.tolist()]))]))
    return found


def _misfit(points: Array, rotation: Array, translation: Array, target: Target) -> float:
    """Mean distance (mm, each at most :data:`MISFIT_CAP_MM`) of *points* moved by (R, t) from
    the target samples' tangent planes: how well a candidate fit sits."""
    near, q, n = target.planes(points @ rotation.T + translation, MISFIT_CAP_MM)
    moved = (points @ rotation.T + translation)[near]
    d = np.abs(np.einsum("ij,ij->i", moved - q, n))
    return float((np.sum(np.minimum(d, MISFIT_CAP_MM)) + MISFIT_CAP_MM * (len(points) - len(d)))
                 / max(1, len(points)))


def _starts(points: Array, normals: Array | None, search: Array, target: Target,
            fixtured: bool) -> list[tuple[Array, Array, str]]:
    """Where a fit may start: fixtured, the scan's frame turned by each candidate phase; free,
    also the cam axis and centre the points' normals and circles give, either way up, each
    turned by its candidate phases."""
    starts = [(np.eye(3), np.zeros(3), "the scan's own frame" if fixtured
               else "the scanner's frame")]
    axis_start = None if fixtured else _axis_start(points, normals, target)
    if axis_start is not None:
        for sense in (1.0, -1.0):
            rotation, translation = axis_start(sense)
            starts.append((rotation, translation, "the cam axis and centre found from the "
                           "scan's surfaces of revolution"))
    if target.slides and not fixtured:
        starts = [turned for start in starts for turned in _laid_along(search, start, target)]
    out = []
    for rotation, translation, words in starts:
        for phase in _phase_search(search, rotation, translation, target):
            r, t = _phase_move(target, phase)
            how = (f"shifted {phase:.4g} mm along the plate's travel by a search of its length"
                   if target.slides else f"turned {math.degrees(phase):.4g}° about the cam axis "
                   "by a search of the whole turn")
            out.append((r @ rotation, r @ translation + t, f"{words}, {how}"))
    return out


def _laid_along(points: Array, start: tuple[Array, Array, str], target: Target
                ) -> list[tuple[Array, Array, str]]:
    """A sliding plate's start turned about Z so that the long axis of *points* (moved by it,
    in the XY plane) lies along the part's, either way, their centres together."""
    rotation, translation, words = start
    moved = points @ rotation.T + translation
    scan_angle, scan_centre = _long_axis(moved[:, :2])
    part_angle, part_centre = _long_axis(target.points[:, :2])
    out = []
    for half in (0.0, math.pi):
        turn = _turn_z(part_angle - scan_angle + half)
        centre = turn[:2, :2] @ scan_centre
        shift = np.array([part_centre[0] - centre[0], part_centre[1] - centre[1], 0.0])
        out.append((turn @ rotation, turn @ translation + shift,
                    f"{words}, its long axis laid along the plate's"))
    return out


def _long_axis(xy: Array) -> tuple[float, Array]:
    """The angle (rad) of the principal axis of the points *xy* (N, 2) and their centre."""
    centre = xy.mean(axis=0)
    _, vectors = np.linalg.eigh(np.cov((xy - centre).T))
    return math.atan2(vectors[1, 1], vectors[0, 1]), centre


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
             fixtured: bool, start: str, most: int = 0) -> Alignment:
    """Trimmed point-to-plane iterations from (R, t): each solves the linearised least squares
    for a small turn ω and shift τ (only ω about Z when *fixtured*)."""
    gate, soft = START_GATE_MM, START_GATE_MM
    used, residual, iterations = 0, math.nan, 0
    while iterations < (most or MAX_ITERATIONS):
        iterations += 1
        moved = points @ rotation.T + translation
        near, q, n = target.planes(moved, gate)
        if np.count_nonzero(near) < 6:
            break
        p = moved[near]
        d = np.einsum("ij,ij->i", p - q, n)
        keep = np.abs(d) < gate
        p, n, d = p[keep], n[keep], d[keep]
        if len(d) < 6:
            break
        spread = 3.0 * 1.4826 * float(np.median(np.abs(d - np.median(d))))
        scale = max(spread, soft)
        weight = 1.0 / np.sqrt(1.0 + (d / scale) ** 2)  # √ of Cauchy's weights, on each row
        core = np.abs(d) <= scale
        used = int(np.count_nonzero(core))
        residual = float(np.sqrt(np.mean(d[core] ** 2))) if used else math.nan
        cross = np.cross(p, n)
        slide = fixtured and target.slides
        a = (n[:, 0:1] if slide else cross[:, 2:3]) if fixtured else np.hstack((cross, n))
        step, *_ = np.linalg.lstsq(a * weight[:, None], -d * weight, rcond=None)
        w = np.zeros(3) if slide else np.array([0.0, 0.0, step[0]]) if fixtured else step[:3]
        tau = np.array([step[0], 0.0, 0.0]) if slide else np.zeros(3) if fixtured else step[3:]
        turn = _rodrigues(w)
        rotation, translation = turn @ rotation, turn @ translation + tau
        settled = gate == FINAL_GATE_MM
        gate = max(FINAL_GATE_MM, 0.6 * gate)
        soft = max(FINAL_SOFT_MM, 0.5 * soft) if settled else 0.25 * gate
        small = max(float(np.linalg.norm(w)), float(np.linalg.norm(tau))) < CONVERGED
        if small and settled and soft == FINAL_SOFT_MM:
            break
    return Alignment(rotation, translation, "fixtured" if fixtured else "free", residual, used,
                     iterations, start)
