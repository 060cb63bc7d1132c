"""The exact walls of a drum cam's groove as a radial end mill meets them (numpy only).

Frame: the cam's (:mod:`camfab.geometry.drum`): the drum's axis is Z, a point at radius r and
polar angle ϕ (rad, from +Y counter-clockwise about +Z) lies at axial position z. A tool
position is the tool's axis, the radial line at polar angle β and axial position x, with its
flat end (the tip) at distance h from the drum's axis: a cylinder of radius ρ round that line
from h outward. A point (r, ϕ, z) lies at height r cos(ϕ − β) along the tool's axis,
r sin(ϕ − β) across it and z − x along the drum's axis, so its distance from that axis is
√(r² sin²(ϕ − β) + (z − x)²), and the tool holds it when that is under ρ and the height is not
under h.

The walls are the roller's envelope (:meth:`~camfab.geometry.drum.Drum.walls`, at a velocity
step the roller's own surface round the outside of the bend too), tabled on one grid of polar
angles, ϕ_j = j·2π/n, at rows of radii. Tool positions lie on the same grid, β_i = i·2π/n, so
that a point and a position k steps apart are always ϕ − β = k·2π/n apart: a narrower tool is
placed against the walls (:func:`touching`) and what it leaves is measured from them
(:func:`clearance`) one offset k at a time over the whole turn.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from camfab.arrays import Array, runs
from camfab.geometry.drum import Drum
from camfab.geometry.drum_mesh import fanned
from camfab.motion.program import MotionProgram

TWO_PI = 2.0 * math.pi

#: Step (rad) of the grid on which the walls are tabled and a tool is placed against them:
#: 0.02°. The tool's reach is met at the grid's points, so it may pass the wall between them by
#: the least of a curve of radius ρ between samples, (r·step)²/8ρ: some hundredths of a
#: micrometre at r/ρ = 20.
GRID_STEP = math.radians(0.02)
#: Step (rad) of the grid on which what a tool leaves is measured (every fifth of the walls'):
#: the distance to each lap is least at a grid point and refined by the parabola through its
#: neighbours, within a hundredth of a micrometre of the least between them.
MEASURE_EVERY = 5
#: Rows of the walls (count) from the groove's floor to the drum's surface, both included: a
#: radial tool's error grows steadily from where it touches the wall (the surface) down to the
#: floor, so the ends decide and the rows between show it.
ROWS = 6
#: How far (mm) beyond the tool's radius a wall point is looked for round each tool: a wall
#: left further than this from every tool is reported as this far.
REACH_MM = 0.5


@dataclass(frozen=True)
class Walls:
    """Both walls on the grid of *count* polar angles ϕ_j = j·2π/count: at each of *radii*
    (R,) (mm, floor first) the axial position (R, count) (mm) of the lower and the upper wall,
    and the cam angle (rad) whose roller makes each."""

    radii: Array
    lower: Array
    upper: Array
    theta_lower: Array
    theta_upper: Array

    @property
    def count(self) -> int:
        return self.lower.shape[1]

    def every(self, k: int) -> Walls:
        """Every *k*-th point of the grid (a grid of count/k)."""
        return Walls(self.radii, self.lower[:, ::k], self.upper[:, ::k],
                     self.theta_lower[:, ::k], self.theta_upper[:, ::k])

    def side(self, upper: bool) -> tuple[Array, Array]:
        return (self.upper, self.theta_upper) if upper else (self.lower, self.theta_lower)


@dataclass(frozen=True)
class Laps:
    """Tool positions of laps round the drum on a grid of polar angles β_i = i·2π/n (rad) of
    the tool's axis: the axial position x (L, n) (mm) of each lap's axis there (its straight
    moves between program points sampled) and each lap's tip h (L,) (mm from the drum's
    axis)."""

    x: Array
    tip: Array

    @classmethod
    def of(cls, paths: list[tuple[Array, Array, float]], count: int) -> Laps:
        """The laps through the polylines (polar angles β, rad, any order over a turn; axial
        positions x, mm; the tip, mm), sampled on a grid of *count* angles."""
        beta = grid(count)
        x = [np.interp(beta, b, x, period=TWO_PI) for b, x, _ in paths]
        return cls(np.array(x).reshape(len(paths), count),
                   np.array([tip for _, _, tip in paths], dtype=np.float64))


def grid(count: int) -> Array:
    """*count* polar angles (rad) evenly round the turn from 0."""
    return np.arange(count) * (TWO_PI / count)


def grid_count(step: float) -> int:
    """The count of a grid as near to *step* (rad) apart as divides the turn."""
    return round(TWO_PI / step)


def exact_walls(d: Drum, program: MotionProgram, tolerance: float,
                roller: float | None = None) -> Walls:
    """The walls of the groove of a roller of radius *roller* (mm; default the groove's,
    :attr:`~camfab.geometry.drum.Drum.roller`) at :data:`ROWS` radii from the floor to the
    surface, tabled on the grid of :data:`GRID_STEP` from the closed form at cam angles every
    half that step (and, at a velocity step, the roller's own surface round the outside of the
    bend, within *tolerance*, mm). Each wall, at each radius, runs round the turn as ϕ falls
    (a counter-clockwise drum) or rises with θ; where it turns back (at a velocity step the
    walls swept before and after it cross, and what lies past their crease is inside the
    other's roller) the pieces each way are tabled apart and the groove's widest taken: the
    highest upper wall, the lowest lower one."""
    d = d if roller is None else replace(d, roller=roller)
    count = grid_count(GRID_STEP)
    theta = np.unique(np.mod(program.segment_grid(GRID_STEP / 2)[1], TWO_PI))
    theta, m, _ = fanned(d, program, theta, tolerance)
    theta, m = np.append(theta, theta[0] + TWO_PI), np.append(m, m[:, :1], axis=1)  # closed
    radii = np.linspace(d.root, d.radius, ROWS)
    found = d.walls(theta[None], m[0][None], m[1][None], radii[:, None])
    tabled = []
    for phi, z, widest in ((found.phi_lower, found.z_lower, np.minimum),
                           (found.phi_upper, found.z_upper, np.maximum)):
        rows = [_tabled(phi[i], z[i], theta, count, widest) for i in range(radii.size)]
        tabled.append((np.array([z for z, _ in rows]), np.array([t for _, t in rows])))
    return Walls(radii, tabled[0][0], tabled[1][0], tabled[0][1], tabled[1][1])


def _tabled(phi: Array, z: Array, theta: Array, count: int, widest: np.ufunc) -> tuple[Array,
                                                                                     Array]:
    """A wall's axial positions (mm) and cam angles (rad) at the grid's polar angles, from its
    points (polar angle *phi*, rad, *z*, mm) in the order of cam angle *theta* over a turn:
    the pieces along which ϕ runs the wall's way tabled each, the widest taken."""
    phi = np.unwrap(phi)
    step = np.diff(phi)
    way = np.sign(phi[-1] - phi[0])
    out = np.full(count, np.inf if widest is np.minimum else -np.inf)
    cams = np.zeros(count)
    angles = grid(count)
    for start, stop in runs(way * step > 0.0):
        piece = slice(start, stop + 1)
        p, zp, tp = phi[piece][::int(way)], z[piece][::int(way)], theta[piece][::int(way)]
        first = math.floor((p[0] - angles[0]) / TWO_PI)
        for turn in range(first, math.ceil((p[-1] - angles[0]) / TWO_PI) + 1):
            at = angles + turn * TWO_PI
            inside = (at >= p[0]) & (at <= p[-1])
            if not inside.any():
                continue
            value = np.interp(at[inside], p, zp)
            better = widest(value, out[inside]) == value
            out[inside] = np.where(better, value, out[inside])
            cams[inside] = np.where(better, np.interp(at[inside], p, tp), cams[inside])
    return out, cams


def touching(walls: Walls, radius: float, tip: float, upper: bool) -> tuple[Array, Array]:
    """The axial position (mm) at which a tool of *radius* with its tip at *tip* (mm from the
    drum's axis), its axis at each of the grid's polar angles β_i, touches a wall (the upper
    one with *upper*) without crossing it: for each point of the wall it holds across its axis
    (at heights from *tip* out), k steps off, the tool's reach along the drum's axis there,
    √(ρ² − (r sin kΔ)²), must not pass the point; the tool is moved along the drum's axis
    until the nearest such point stops it (the upper wall from below, the lower from above).
    Second, the height (mm along the tool's axis) of the point that stops it (of equal ones,
    the outermost)."""
    wall, _ = walls.side(upper)
    sign = 1.0 if upper else -1.0
    count = walls.count
    step = TWO_PI / count
    out = np.full(count, np.inf)
    height = np.full(count, np.nan)
    for row in range(walls.radii.size - 1, -1, -1):
        r = float(walls.radii[row])
        reach = math.floor(math.asin(min(1.0, radius / r)) / step)
        padded = np.concatenate((wall[row, -reach - 1:], wall[row], wall[row, :reach + 1]))
        signed = sign * padded
        for k in range(-reach, reach + 1):
            across, along = r * math.sin(k * step), r * math.cos(k * step)
            if abs(across) >= radius or along < tip:
                continue
            bound = signed[reach + 1 + k: reach + 1 + k + count] - math.sqrt(
                radius * radius - across * across)
            better = bound < out
            out[better] = bound[better]
            height[better] = along
    return sign * out, height


def clearance(walls: Walls, upper: bool, laps: Laps, radius: float) -> tuple[Array, Array]:
    """For each point of a wall (the upper one with *upper*; (R, n), on the laps' grid): its
    distance (mm) from the nearest of the tools (cylinders of *radius* round the radial axes of
    *laps*, each from its tip out), negative inside one, or :data:`REACH_MM` where no tool
    comes nearer; and its height (mm) along that nearest tool's axis. Each lap's nearest grid
    position is refined by the parabola through it and its neighbours (the distance along a
    lap is smooth where it is least)."""
    wall, _ = walls.side(upper)
    count = walls.count
    step = TWO_PI / count
    gap = np.full(wall.shape, REACH_MM)
    height = np.full(wall.shape, np.nan)
    for row in range(walls.radii.size):
        r = float(walls.radii[row])
        reach = math.ceil(math.asin(min(1.0, (radius + REACH_MM) / r)) / step) + 1
        offsets = np.arange(-reach - 1, reach + 2)
        for lap in range(laps.x.shape[0]):
            x = np.concatenate((laps.x[lap, -reach - 1:], laps.x[lap],
                                laps.x[lap, :reach + 1]))
            distance = np.full((offsets.size, count), np.inf)
            for n, k in enumerate(offsets):
                if r * math.cos(k * step) < laps.tip[lap]:
                    continue
                along = x[reach + 1 + k: reach + 1 + k + count]
                distance[n] = np.hypot(r * math.sin(k * step), wall[row] - along)
            least, at = _vertex(distance - radius)
            better = least < gap[row]
            gap[row] = np.where(better, least, gap[row])
            height[row] = np.where(better, r * np.cos(offsets[at] * step), height[row])
    return gap, height


def _vertex(values: Array) -> tuple[Array, Array]:
    """The least of each column of *values* and its row, the least refined by the parabola
    through it and its neighbours when both are finite and the parabola opens upward."""
    at = np.argmin(values, axis=0)
    inner = np.clip(at, 1, values.shape[0] - 2)
    columns = np.arange(values.shape[1])
    before, middle, after = (values[inner + k, columns] for k in (-1, 0, 1))
    least = values[at, columns]
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        curve = before - 2.0 * middle + after
        fitted = middle - (after - before) ** 2 / (8.0 * curve)
    usable = (at == inner) & np.isfinite(before) & np.isfinite(after) & (curve > 0.0)
    return np.where(usable, np.minimum(least, fitted), least), at


def chords(a: Array, x: Array, tolerance: float) -> Array:
    """Which of the dense points (*a* ascending, *x*) to keep (indices) so that the straight
    lines between the kept ones pass within *tolerance* of every dense point (both ends
    kept): the points halfway along every stretch that strays further are added, all at once,
    until none does."""
    keep = np.zeros(a.size, dtype=bool)
    keep[[0, -1]] = True
    while True:
        kept = np.flatnonzero(keep)
        stray = np.abs(np.interp(a, a[kept], x[kept]) - x) > tolerance
        if not stray.any():
            return kept
        piece = np.unique(np.searchsorted(kept, np.flatnonzero(stray), side="right") - 1)
        keep[(kept[piece] + kept[piece + 1]) // 2] = True
