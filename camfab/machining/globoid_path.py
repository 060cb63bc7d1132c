"""A globoidal cam's groove cut by a cutter whose axis follows the roller's axis relative to the
cam, on a table-table machine: the cam on a rotary A axis, which a B axis tilts as the arm
swings (docs/machining.md, "Globoidal cams").

Frames (mm; angles in radians unless named ``_deg``):

- **the design's frame** (SPEC §2, THEORY §H): the cam's axis Z, the pivot axis parallel to Y
  through P = (C, 0, 0); the arm at ψ = ψ₀ + s(θ) from the line of centres toward +Z; the
  roller's axis Q(ℓ) = P + ℓ·a, a = (−cos ψ, 0, sin ψ), ℓ from the pivot.
- **the cam's frame**: the design's frame turned with the cam; a point p of the design's frame
  at cam angle θ lies on the cam at Rot_z(−σθ)·p (σ = +1 counter-clockwise, −1 clockwise).
- **the machine**, the program's coordinates: the work zero on the cam's axis at its middle
  plane (z = 0, the plane of the pivot); X along the cam's axis (its +z), Z up, the tool
  pointing down. With A = B = 0 the line of centres stands vertical: the pivot above the cam
  for a concave globoid (``u`` = +1), below it for a convex one (``u`` = −1), so that the
  cutter always comes in from outside the blank along the roller's axis. A point p of the cam
  then stands at M₀p = (p_z, −u·p_y, u·p_x). A turns the cam about X by the right-hand rule;
  B turns A and the cam about B's axis, parallel to Y through b = (b_x, 0, b_z), by the
  right-hand rule: the cam's point p stands at b + R_Y(B)·(R_X(A)·M₀p − b).

With A = σθ and B = u·ψ the roller's axis stands vertical, through
K = b + R_Y(uψ)·(M₀P − b) (the pivot's place: fixed when B's axis passes through the pivot,
else X and Z follow it round), the roller's end toward the floor down.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from itertools import pairwise

import numpy as np

from camfab.arrays import Array
from camfab.geometry.globoid import Globoid, to_cam
from camfab.motion.program import MotionProgram

#: Fractions of each move at which the tool's axis, as the control interpolates the axes
#: linearly, is measured against the planned axis (the error of a smooth curve's chord peaks
#: near its middle).
PROBES = np.array([0.25, 0.5, 0.75])
#: The largest step of cam angle between the program's points (rad), however straight the
#: path runs: the inverse-time feeds and the picture stay even.
MAX_STEP = math.radians(1.0)
#: Rounds of halving the moves whose axis strays (each quarters the error).
MOST_HALVINGS = 12
#: Distances along the arm (count) over the groove's depth at which the contact normal's turn
#: is measured for a wall pass.
WALL_ROWS = 17


@dataclass(frozen=True)
class TableTable:
    """The machine (see the module): the globoid's ``inward`` u (+1 concave, −1 convex), the
    cam's turning σ, and B's axis through (``b_x``, 0, ``b_z``) (mm) with A = B = 0."""

    inward: float
    sigma: int
    b_x: float
    b_z: float

    @property
    def b(self) -> Array:
        return np.array([self.b_x, 0.0, self.b_z])

    def to_table(self, p: Array) -> Array:
        """M₀p: points (..., 3) of the cam where they stand with A = B = 0."""
        u = self.inward
        return np.stack((p[..., 2], -u * p[..., 1], u * p[..., 0]), axis=-1)

    def from_table(self, x: Array) -> Array:
        """M₀⁻¹x: the cam's points (..., 3) that stand at *x* with A = B = 0."""
        u = self.inward
        return np.stack((u * x[..., 2], -u * x[..., 1], x[..., 0]), axis=-1)

    def machine(self, frame: Array, psi: Array) -> Array:
        """Where points (..., 3) of the design's frame with the arm at *psi* (rad) stand on the
        machine (X, Y, Z) with A = σθ, B = uψ: b + R_Y(uψ)(M₀p − b) (the turn of the cam and
        A's cancel)."""
        return self.b + rot_y(self.to_table(frame) - self.b, self.inward * np.asarray(psi))

    def on_cam(self, x: Array, a_deg: Array, b_deg: Array) -> Array:
        """The cam's points (..., 3) at machine positions *x* (X, Y, Z) with the axes at
        *a_deg*, *b_deg*: M₀⁻¹ R_X(−A)(b + R_Y(−B)(x − b))."""
        back = self.b + rot_y(x - self.b, -np.radians(b_deg))
        return self.from_table(rot_x(back, -np.radians(a_deg)))

    def axis_on_cam(self, a_deg: Array, b_deg: Array) -> Array:
        """The tool's axis (+Z, from its tip to the spindle) on the cam (..., 3) with the
        axes at *a_deg*, *b_deg*."""
        a_deg, b_deg = np.broadcast_arrays(np.asarray(a_deg, float), np.asarray(b_deg, float))
        up = np.zeros((*a_deg.shape, 3))
        up[..., 2] = 1.0
        return self.from_table(rot_x(rot_y(up, -np.radians(b_deg)), -np.radians(a_deg)))


def rot_y(v: Array, angle: Array) -> Array:
    """*v* (..., 3) turned by *angle* (rad) about +Y by the right-hand rule."""
    c, s = np.cos(angle), np.sin(angle)
    return np.stack((c * v[..., 0] + s * v[..., 2], v[..., 1], -s * v[..., 0] + c * v[..., 2]),
                    axis=-1)


def rot_x(v: Array, angle: Array) -> Array:
    """*v* (..., 3) turned by *angle* (rad) about +X by the right-hand rule."""
    c, s = np.cos(angle), np.sin(angle)
    return np.stack((v[..., 0], c * v[..., 1] - s * v[..., 2], s * v[..., 1] + c * v[..., 2]),
                    axis=-1)


@dataclass(frozen=True)
class Walls:
    """How a cutter smaller than the groove cuts its walls (mm): a pass each side with its
    axis moved ``shift`` off the roller's, square to it, along the contact normal averaged
    over the groove's depth (the middle of its turn); ``left`` the most a wall pass leaves on
    its wall at any cam angle (the contact normal turns along the roller, so the cutter's
    cylinder, which stays inside the roller's, meets the wall exactly only where the normal
    is the averaged one)."""

    shift: float
    left: float
    turn: float  # the normal's largest half-turn over the groove's depth (rad)

    def smallest_tool(self, wall: float, tolerance: float) -> float:
        """The smallest cutter diameter (mm) whose wall passes leave at most *tolerance* on a
        groove of wall radius *wall*: from sqrt(r² + δ² − 2rδ cos h) − (r − δ) = t."""
        t, r = tolerance, wall
        delta = t * (t + 2 * r) / (2 * (t + r * (1 - math.cos(self.turn))))
        return 2 * max(r - delta, 0.0)


def contact_normals(g: Globoid, psi: Array, dpsi: Array, rows: Array) -> tuple[Array, Array]:
    """The contact normal averaged over the distances *rows* along the arm (the middle of its
    turn about the roller's axis) at each swing *psi* (rad) and rate *dpsi* (N,) — (N, 3), in
    the design's frame — and half its turn there (rad, (N,))."""
    n = g.normal(rows[:, None], psi[None, :], dpsi[None, :])
    middle = n[rows.size // 2]
    across = np.cross(g.axis_direction(psi), middle)
    turn = np.arctan2(np.einsum("rni,ni->rn", n, across), np.einsum("rni,ni->rn", n, middle))
    low, high = turn.min(axis=0), turn.max(axis=0)
    centre = 0.5 * (low + high)
    return (np.cos(centre)[:, None] * middle + np.sin(centre)[:, None] * across,
            0.5 * (high - low))


def wall_passes(g: Globoid, program: MotionProgram, rows: Array, tool_radius: float,
                step: float = math.radians(0.25)) -> Walls:
    """The wall passes of a cutter of *tool_radius* in the groove of *g* over the distances
    *rows* along the arm (the groove's depth), measured every *step* of cam angle (rad):
    what each leaves on its wall is sqrt(r² + δ² − 2rδ cos h) − (r − δ) at the normal's
    half-turn h, the largest over the turn."""
    theta = np.arange(0.0, 2 * math.pi, step)
    m = program.evaluate(theta)
    _, half = contact_normals(g, g.rest + m[0], m[1], rows)
    turn = float(half.max())
    r = g.radius
    delta = max(r - tool_radius, 0.0)
    left = math.sqrt(max(r * r + delta * delta - 2 * r * delta * math.cos(turn), 0.0)) - (
        r - delta)
    return Walls(delta, max(left, 0.0), turn)


@dataclass(frozen=True)
class Poses:
    """The cutter at cam angles ``theta`` (rad, as turned: continuous over the passes): the
    arm's swing ``psi`` (rad); the cutter's tip and axis (from the tip to the spindle, unit)
    in the design's frame (N, 3), and the point of its axis at the blank's surface; its tip on
    the machine (X, Y, Z) with A and B (deg); the cam's turning ``sigma``."""

    theta: Array
    psi: Array
    tip: Array
    axis: Array
    top: Array
    xyz: Array
    a_deg: Array
    b_deg: Array
    sigma: int

    def on_cam(self, points: Array) -> Array:
        """*points* (N, 3) of the design's frame at these poses, on the cam."""
        return to_cam(points, self.sigma * self.theta)


@dataclass(frozen=True)
class Cutter:
    """What places the cutter in a globoid's groove: the follower *g*, its program, the
    machine, the blank's surface and floor along the arm (mm from the pivot), the groove's
    ``inward`` u, the wall passes' shift (mm) and the rows along the arm its normal is
    averaged over."""

    g: Globoid
    program: MotionProgram
    table: TableTable
    surface: float
    floor: float
    shift: float
    rows: Array

    def axis(self, theta: Array, side: int) -> tuple[Array, Array, Array]:
        """At cam angles *theta* (rad): the swing ψ (rad), the point of the planned axis at
        the pivot's distance 0 (the pivot moved by the wall pass's shift: (N, 3) in the
        design's frame) and the roller's axis a (N, 3) away from the pivot."""
        g = self.g
        m = self.program.evaluate(theta)
        psi = g.rest + m[0]
        origin = np.broadcast_to(np.array([g.centre, 0.0, 0.0]), (np.size(theta), 3))
        if side != 0 and self.shift > 0.0:
            normal, _ = contact_normals(g, psi, m[1], self.rows)
            origin = origin + side * self.shift * normal
        return psi, origin, g.axis_direction(psi)

    def poses(self, theta: Array, depth: Array, side: int) -> Poses:
        """The cutter's tip *depth* (mm, along the arm from the blank's surface; negative:
        outside it) at cam angles *theta* (rad) on the pass of *side* (0 the middle, ±1 the
        wall on the ± side of the contact normal)."""
        u, sigma = self.table.inward, self.table.sigma
        psi, origin, a = self.axis(theta, side)
        ell = self.surface + u * np.asarray(depth)
        tip = origin + ell[:, None] * a
        xyz = self.table.machine(tip, psi)
        return Poses(theta, psi, tip, -u * a, origin + self.surface * a, xyz,
                     np.degrees(sigma * theta), np.degrees(u * psi), sigma)

    def stray(self, theta: Array, side: int) -> Array:
        """How far (mm) the cutter's axis, the axes interpolated linearly between the poses
        at consecutive *theta* (rad), strays from the planned axis over the groove's depth:
        the largest at :data:`PROBES` of each move (N − 1,)."""
        at = self.poses(theta, np.zeros(theta.size), side)
        f = PROBES[:, None]
        mid_theta = (1 - f) * theta[None, :-1] + f * theta[None, 1:]
        xyz = (1 - f)[..., None] * at.xyz[None, :-1] + f[..., None] * at.xyz[None, 1:]
        a_deg = (1 - f) * at.a_deg[None, :-1] + f * at.a_deg[None, 1:]
        b_deg = (1 - f) * at.b_deg[None, :-1] + f * at.b_deg[None, 1:]
        point = self.table.on_cam(xyz, a_deg, b_deg)
        direction = self.table.axis_on_cam(a_deg, b_deg)
        flat = mid_theta.ravel()
        _, origin, a = self.axis(flat, side)
        worst = np.zeros(flat.size)
        for ell in (self.surface, self.floor):
            planned = to_cam(origin + ell * a, self.table.sigma * flat).reshape(point.shape)
            rel = planned - point
            along = np.einsum("...i,...i->...", rel, direction)[..., None] * direction
            worst = np.maximum(worst, np.linalg.norm(rel - along, axis=-1).ravel())
        return worst.reshape(f.shape[0], -1).max(axis=0)


def revolution_stations(cutter: Cutter, side: int, target: float) -> Array:
    """Cam angles (rad) over one turn, 0 and 2π included, every segment's start among them, at
    most :data:`MAX_STEP` apart, at which the cutter's axis interpolated linearly between
    them strays at most *target* (mm) from the planned axis: moves that stray are halved,
    round after round."""
    starts = np.array([seg.start for seg in cutter.program.segments], dtype=float)
    ends = np.append(starts, 2 * math.pi)
    pieces = [np.linspace(a, b, max(2, math.ceil((b - a) / MAX_STEP) + 1))[:-1]
              for a, b in pairwise(ends)]
    theta = np.append(np.concatenate(pieces), 2 * math.pi)
    return halved(theta, lambda t: cutter.stray(t, side), target)


def halved(theta: Array, stray: Callable[[Array], Array], target: float) -> Array:
    """*theta* (ascending) with every move that *stray* (its error per move, mm) finds over
    *target* (mm) halved, until none does (at most :data:`MOST_HALVINGS` rounds)."""
    for _ in range(MOST_HALVINGS):
        bad = stray(theta) > target
        if not bad.any():
            break
        middle = 0.5 * (theta[:-1] + theta[1:])[bad]
        theta = np.sort(np.concatenate((theta, middle)))
    return theta


def unrolled(stations: Array, start: float, end: float, breaks: Array) -> Array:
    """Cam angles (rad) from *start* to *end* (either way round, over any number of turns)
    through every one of one turn's *stations* (0 to 2π) they pass, and *breaks*: the points
    of a pass."""
    low, high = min(start, end), max(start, end)
    first, last = math.floor(low / (2 * math.pi)), math.ceil(high / (2 * math.pi))
    turns = np.arange(first, last)[:, None] * 2 * math.pi
    every = (stations[None, :-1] + turns).ravel()
    inside = every[(every > low) & (every < high)]
    extra = breaks[(breaks > low) & (breaks < high)]
    points = np.unique(np.concatenate(([low, high], inside, extra)))
    return points if end >= start else points[::-1]


def move_minutes(poses: Poses, feed: float) -> np.ndarray:
    """The time (min) of each move between consecutive *poses* at *feed* (mm/min): as long as
    the faster of the cutter's tip and its axis' point at the blank's surface moves on the cam
    (N − 1,)."""
    lengths = np.zeros(poses.theta.size - 1)
    for points in (poses.tip, poses.top):
        on_cam = poses.on_cam(points)
        lengths = np.maximum(lengths, np.linalg.norm(np.diff(on_cam, axis=0), axis=1))
    return np.maximum(lengths, 1e-6) / feed
