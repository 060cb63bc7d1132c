"""Follower simulation: turn any closed cam profile and find where the follower really is.

This is the independent check of the synthesis (design → profile → lift) and the engine of
profile inspection. It knows nothing of motion laws: the cam is a contour of lines and arcs
(:class:`~camfab.curves.profile.Profile`) and the follower a shape on a path (a line for a
translating follower, a circle about the pivot for an oscillating one). At each cam angle the
follower is pressed onto the cam: its position is the farthest point of its path at which it
still touches the cam, the largest over all the pieces it can touch.

A roller (or mushroom, or knife with radius 0) touches the cam where its centre meets the
profile offset by its radius: every line edge offset along its outward normal, every arc with
its radius grown (convex) or shrunk (concave), and a cap of the roller radius about every convex
corner, spanning the corner's normal cone. A flat face touches corners within their normal cone
and convex arcs within their span. Each piece can only be touched over a window of cam angles
that follows from where it lies, so only (piece, angle) pairs inside those windows are evaluated.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from camfab.arrays import Array, Index, Mask
from camfab.curves.follower import FollowerGeometry
from camfab.curves.plane import perp
from camfab.curves.profile import Profile

TWO_PI = 2.0 * math.pi

#: Pairs evaluated at once; bounds the memory of a simulation to some tens of megabytes.
_CHUNK = 400_000


class SimulationTooLarge(ValueError):
    """The follower would be tried at more (piece, cam angle) pairs than the caller allows: an
    outline so jagged that most of its pieces may touch the follower over wide ranges of angles
    (a smooth outline of any number of points needs a few per piece)."""

    def __init__(self, pairs: int, limit: int) -> None:
        self.pairs = pairs
        self.limit = limit
        super().__init__(f"the follower would be tried at {pairs:,} or more (piece, cam angle) "
                         f"pairs; at most {limit:,} are")

#: Slack on spans and windows (rad) and on the fraction along an edge, so contact exactly at a
#: piece's end is not lost to rounding (a knife has no corner caps to catch it).
_SLACK = 1e-9

#: The first, coarse pass of an oscillating flat face (it finds the range of swing): its cam-angle
#: step, and every how many corners it tries. Missing corners only lowers its estimate by a
#: fraction of the angle between corners; the window it sets is widened by the largest change
#: between coarse steps plus one step, far more than that.
_COARSE_STEP = math.radians(1.0)
_COARSE_THINNING = 8


@dataclass(frozen=True)
class CirclePieces:
    """Circle pieces in the cam frame: centre, radius, start angle and signed sweep (rad)."""

    centre: Array
    radius: Array
    start: Array
    sweep: Array

    def __len__(self) -> int:
        return len(self.radius)

    def bounds(self) -> tuple[Array, Array]:
        """A ball (centre, radius) holding each piece."""
        half = 0.5 * np.abs(self.sweep)
        mid_angle = self.start + 0.5 * self.sweep
        direction = np.stack((np.cos(mid_angle), np.sin(mid_angle)), axis=-1)
        chord_mid = self.centre + (self.radius * np.cos(half))[:, None] * direction
        reach = np.maximum(self.radius * np.sin(half), self.radius * (1.0 - np.cos(half)))
        big = half >= math.pi / 2
        return (np.where(big[:, None], self.centre, chord_mid),
                np.where(big, self.radius, reach) + _SLACK)

    def in_span(self, angle: Array, which: Index) -> Mask:
        """True where direction *angle* (rad, cam frame) from a centre lies within the piece."""
        sweep = self.sweep[which]
        rel = np.where(sweep >= 0, angle - self.start[which], self.start[which] - angle)
        with np.errstate(invalid="ignore"):  # NaN angles (no intersection) are not in any span
            return np.mod(rel + _SLACK, TWO_PI) <= np.abs(sweep) + 2 * _SLACK


def _corners(profile: Profile) -> tuple[Index, Array, Array]:
    """Convex corners: vertex index, the outward normal angle arriving, and the cone's angle."""
    start, end = profile.normal_angles()
    arriving = np.roll(end, 1)
    cone = np.mod(start - arriving + math.pi, TWO_PI) - math.pi
    convex = np.flatnonzero(cone > 0.0)
    return convex, arriving[convex], cone[convex]


@dataclass(frozen=True)
class OffsetPieces:
    """What a circle of radius r about the trace point touches: the profile (counter-clockwise)
    offset by r — its lines as segments from ``q1`` to ``q2``, its arcs grown or shrunk, and caps
    of radius r at its convex corners as ``circles``."""

    circles: CirclePieces
    q1: Array
    q2: Array

    @classmethod
    def of(cls, profile: Profile, r: float) -> OffsetPieces:
        v = profile.vertices
        line = profile.bulges == 0.0
        a, b = v[line], np.roll(v, -1, axis=0)[line]
        d = b - a
        normal = -perp(d) / np.hypot(d[:, 0], d[:, 1])[:, None]
        arcs = profile.arcs()
        grown = arcs.radius + np.where(arcs.sweep > 0, r, -r)
        usable = grown > 0.0
        centres, radii = [arcs.centre[usable]], [grown[usable]]
        starts, sweeps = [arcs.start_angle[usable]], [arcs.sweep[usable]]
        if r > 0.0:
            index, arriving, cone = _corners(profile)
            centres.append(v[index])
            radii.append(np.full(index.size, r))
            starts.append(arriving)
            sweeps.append(cone)
        circles = CirclePieces(np.concatenate(centres), np.concatenate(radii),
                           np.concatenate(starts), np.concatenate(sweeps))
        return cls(circles, a + r * normal, b + r * normal)


class _Grid:
    """The cam angles of a simulation with their rotations, and the best position found so far."""

    def __init__(self, theta: Array, sigma: int, max_pairs: int | None = None) -> None:
        self.theta = theta
        self.sigma = sigma
        self.cos = np.cos(sigma * theta)
        self.sin = np.sin(sigma * theta)
        self.best = np.full(theta.size, -np.inf)
        self.max_pairs = max_pairs
        self.pairs = 0

    def frame(self, points: Array, k: Index) -> Array:
        """Cam-frame *points* seen in the frame at the angles of index *k*."""
        c, s = self.cos[k], self.sin[k]
        return np.stack((c * points[:, 0] - s * points[:, 1],
                         s * points[:, 0] + c * points[:, 1]), axis=-1)

    def to_cam_angle(self, angle: Array, k: Index) -> Array:
        """A frame direction angle as the cam-frame angle at the angles of index *k*."""
        return angle - self.sigma * self.theta[k]

    def window(self, centre: Array, lo_tau: Array, hi_tau: Array) -> Iterator[tuple[Index, Index]]:
        """(piece, angle index) pairs, in chunks, for pieces whose *centre* must be seen at frame
        angles [lo_tau, hi_tau]."""
        alpha = np.arctan2(centre[:, 1], centre[:, 0])
        if self.sigma > 0:
            lo, hi = lo_tau - alpha, hi_tau - alpha
        else:
            lo, hi = alpha - hi_tau, alpha - lo_tau
        count = self.theta.size
        width = np.clip(hi - lo, 0.0, TWO_PI)
        start = np.mod(lo, TWO_PI)
        extended = np.concatenate((self.theta, self.theta + TWO_PI))
        k0 = np.searchsorted(extended, start, side="left")
        k1 = np.searchsorted(extended, start + width, side="right")
        n = np.where(width >= TWO_PI, count, np.minimum(k1 - k0, count))
        self.pairs += int(n.sum())
        if self.max_pairs is not None and self.pairs > self.max_pairs:
            raise SimulationTooLarge(self.pairs, self.max_pairs)
        # the pairs of a run of pieces at a time, about _CHUNK of them: never all at once
        ends = np.cumsum(n)
        cuts = np.searchsorted(ends, np.arange(_CHUNK, int(ends[-1]) if ends.size else 0,
                                               _CHUNK), side="left") + 1
        bounds = np.sort(np.concatenate(([0], cuts, [len(n)])))
        # the distinct bounds (np.unique would import numpy.ma, 7 ms of a build, to do this)
        bounds = bounds[np.concatenate(([True], bounds[1:] != bounds[:-1]))]
        for p0, p1 in zip(bounds[:-1].tolist(), bounds[1:].tolist(), strict=True):
            some = n[p0:p1]
            size = int(some.sum())
            if size == 0:
                continue
            piece = np.repeat(np.arange(p0, p1), some)
            first = np.repeat(k0[p0:p1] - np.concatenate(([0], np.cumsum(some)[:-1])), some)
            yield piece, (first + np.arange(size)) % count

    def turned(self, lo: Array, hi: Array) -> Iterator[tuple[Index, Index]]:
        """(piece, angle index) pairs for pieces active while σθ lies in [lo, hi] (rad)."""
        return self.window(np.tile([1.0, 0.0], (len(lo), 1)), lo - _SLACK, hi + _SLACK)

    def keep(self, k: Index, value: Array) -> None:
        ok = np.isfinite(value)
        np.maximum.at(self.best, k[ok], value[ok])


def simulate(profile: Profile, follower: FollowerGeometry, theta: Array, sigma: int,
             max_pairs: int | None = None) -> Array:
    """Where the follower is at each cam angle of *theta* when pressed onto *profile*.

    Parameters
    ----------
    profile
        The cam contour in the cam frame (mm), drawn at θ = 0, with the cam centre inside.
    follower
        The follower's shape and mounting.
    theta
        Cam angles (rad), increasing, within [0, 2π).
    sigma
        +1 for a counter-clockwise cam, −1 for clockwise.
    max_pairs
        Most (piece, cam angle) pairs to evaluate (None: no limit); the work and memory of a
        simulation grow with them.

    Returns
    -------
    Array
        Translating: the trace point's height (mm; for a flat face, the face's height).
        Oscillating: the arm angle Ψ (rad). NaN where the follower touches nothing.

    Raises
    ------
    SimulationTooLarge
        More than *max_pairs* pairs would be evaluated (found before they are).
    """
    grid = _Grid(np.asarray(theta, dtype=np.float64), sigma, max_pairs)
    prof = profile.ccw()
    if follower.flat and follower.oscillating:
        _swinging_face(prof, follower, grid)
    elif follower.flat:
        _sliding_face(prof, grid)
    elif follower.oscillating:
        _swinging_circle(OffsetPieces.of(prof, follower.radius), follower, grid)
    else:
        _sliding_circle(OffsetPieces.of(prof, follower.radius), follower.offset, grid)
    return np.where(np.isfinite(grid.best), grid.best, np.nan)


# -- translating knife, roller, mushroom: the centre on the line x = e --------------------------

def _line_window(centre: Array, reach: Array, offset: float) -> tuple[Array, Array]:
    """Frame angles at which a ball (centre at radius r, *reach*) can meet the line x = offset
    above the cam centre."""
    r = np.hypot(centre[:, 0], centre[:, 1])
    with np.errstate(divide="ignore", invalid="ignore"):
        lo = np.arccos(np.clip((offset + reach) / r, -1.0, 1.0))
        hi = np.arccos(np.clip((offset - reach) / r, -1.0, 1.0))
        slack = np.arcsin(np.clip(reach / r, 0.0, 1.0))
    full = ~(r > reach)
    return np.where(full, 0.0, lo - slack), np.where(full, TWO_PI, hi + slack)


def _sliding_circle(off: OffsetPieces, e: float, grid: _Grid) -> None:
    circles = off.circles
    if len(circles):
        centre, reach = circles.bounds()
        for f, k in grid.window(centre, *_line_window(centre, reach, e)):
            c = grid.frame(circles.centre[f], k)
            with np.errstate(invalid="ignore"):
                rise = np.sqrt(circles.radius[f] ** 2 - (e - c[:, 0]) ** 2)
            for sign in (1.0, -1.0):
                y = c[:, 1] + sign * rise
                angle = grid.to_cam_angle(np.arctan2(y - c[:, 1], e - c[:, 0]), k)
                grid.keep(k, np.where(circles.in_span(angle, f), y, -np.inf))
    mid, half = 0.5 * (off.q1 + off.q2), 0.5 * np.hypot(*(off.q2 - off.q1).T) + _SLACK
    for f, k in grid.window(mid, *_line_window(mid, half, e)):
        a, b = grid.frame(off.q1[f], k), grid.frame(off.q2[f], k)
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (e - a[:, 0]) / (b[:, 0] - a[:, 0])
        y = a[:, 1] + t * (b[:, 1] - a[:, 1])
        grid.keep(k, np.where((t >= -_SLACK) & (t <= 1.0 + _SLACK), y, -np.inf))


# -- oscillating knife, roller, mushroom: the centre on the arm circle ------------------------

def _ring_windows(centre: Array, reach: Array, pivot: Array,
                  arm: float) -> list[tuple[Array, Array]]:
    """Frame angles at which a ball (centre, *reach*) can meet the circle of radius *arm* about
    *pivot*: two windows, one each side of the pivot's direction."""
    r = np.hypot(centre[:, 0], centre[:, 1])
    a = float(np.hypot(*pivot))
    tau = math.atan2(pivot[1], pivot[0])
    # the ball meets the ring where its centre is within arm ± reach of the pivot: no nearer
    # limit when the ball is wider than the arm is long (a mushroom's face about a dwell)
    inner = np.maximum(arm - reach, 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        near = np.arccos(np.clip((r * r + a * a - inner**2) / (2 * r * a), -1.0, 1.0))
        far = np.arccos(np.clip((r * r + a * a - (arm + reach) ** 2) / (2 * r * a), -1.0, 1.0))
    g1, g2 = np.minimum(near, far), np.maximum(near, far)
    full = ~(r > 1e-12)
    g1, g2 = np.where(full, 0.0, g1), np.where(full, math.pi, g2)
    return [(tau + g1, tau + g2), (tau - g2, tau - g1)]


def arm_angle(points: Array, fol: FollowerGeometry) -> Array:
    """The arm angle Ψ (rad) that puts the trace point at frame *points* ((..., 2), mm); −inf
    below the X axis."""
    psi = np.arctan2(points[..., 1], fol.pivot_distance - fol.pivot_sign * points[..., 0])
    return np.where(points[..., 1] >= 0.0, psi, -np.inf)


def _swinging_circle(off: OffsetPieces, fol: FollowerGeometry, grid: _Grid) -> None:
    pivot = np.array([fol.pivot_sign * fol.pivot_distance, 0.0])
    arm, circles = fol.arm_length, off.circles
    if len(circles):
        centre, reach = circles.bounds()
        for lo, hi in _ring_windows(centre, reach, pivot, arm):
            for f, k in grid.window(centre, lo, hi):
                c = grid.frame(circles.centre[f], k)
                d = c - pivot
                dist = np.hypot(d[:, 0], d[:, 1])
                with np.errstate(divide="ignore", invalid="ignore"):
                    along = (arm * arm - circles.radius[f] ** 2 + dist * dist) / (2 * dist)
                    across = np.sqrt(arm * arm - along * along) / dist
                base = pivot + (along / dist)[:, None] * d
                for sign in (1.0, -1.0):
                    hit = base + (sign * across)[:, None] * perp(d)
                    angle = grid.to_cam_angle(np.arctan2(hit[:, 1] - c[:, 1],
                                                         hit[:, 0] - c[:, 0]), k)
                    grid.keep(k, np.where(circles.in_span(angle, f), arm_angle(hit, fol),
                                          -np.inf))
    mid, half = 0.5 * (off.q1 + off.q2), 0.5 * np.hypot(*(off.q2 - off.q1).T) + _SLACK
    for lo, hi in _ring_windows(mid, half, pivot, arm):
        for f, k in grid.window(mid, lo, hi):
            a = grid.frame(off.q1[f], k)
            d = grid.frame(off.q2[f], k) - a
            rel = a - pivot
            qa = np.einsum("ij,ij->i", d, d)
            qb = 2 * np.einsum("ij,ij->i", d, rel)
            qc = np.einsum("ij,ij->i", rel, rel) - arm * arm
            with np.errstate(invalid="ignore", divide="ignore"):
                root = np.sqrt(qb * qb - 4 * qa * qc)
                for t in ((-qb + root) / (2 * qa), (-qb - root) / (2 * qa)):
                    psi = arm_angle(a + t[:, None] * d, fol)
                    grid.keep(k, np.where((t >= -_SLACK) & (t <= 1.0 + _SLACK), psi, -np.inf))


# -- flat faces: the support of the cam in the face's direction --------------------------------

def _support_pieces(profile: Profile) -> tuple[Array, Array, Array, CirclePieces]:
    """Corners (point, first outward normal angle, cone) and convex arcs: what a face can touch."""
    index, arriving, cone = _corners(profile)
    arcs = profile.arcs()
    convex = arcs.sweep > 0
    circles = CirclePieces(arcs.centre[convex], arcs.radius[convex], arcs.start_angle[convex],
                       arcs.sweep[convex])
    return profile.vertices[index], arriving, cone, circles


def _sliding_face(profile: Profile, grid: _Grid) -> None:
    """A face perpendicular to +Y: its height is the highest point of the cam. A corner is the
    highest point while +Y, seen on the cam at angle π/2 − σθ, lies in its normal cone."""
    corners, arriving, cone, circles = _support_pieces(profile)
    for f, k in grid.turned(math.pi / 2 - arriving - cone, math.pi / 2 - arriving):
        grid.keep(k, grid.frame(corners[f], k)[:, 1])
    if len(circles):
        for f, k in grid.turned(math.pi / 2 - circles.start - circles.sweep,
                                math.pi / 2 - circles.start):
            grid.keep(k, grid.frame(circles.centre[f], k)[:, 1] + circles.radius[f])


def face_angle(points: Array, distance: Array | float, pivot: Array,
                fol: FollowerGeometry) -> Array:
    """The smallest arm angle Ψ (rad) at which the face line, at *distance* from the pivot, clears
    frame *points* ((..., 2), mm): ``(P − A)·n(Ψ) = distance`` with n = (−p sin Ψ, −cos Ψ)
    toward the cam; −inf outside [0, π]."""
    d = points - pivot
    a1, b1 = -fol.pivot_sign * d[..., 0], -d[..., 1]
    with np.errstate(invalid="ignore", divide="ignore"):
        psi = np.arcsin(distance / np.hypot(a1, b1)) - np.arctan2(b1, a1)
    psi = np.mod(psi + math.pi, TWO_PI) - math.pi
    return np.where((psi >= 0.0) & (psi <= math.pi), psi, -np.inf)


def _swinging_face(profile: Profile, fol: FollowerGeometry, grid: _Grid) -> None:
    """A face at ``face_offset`` from the pivot, swinging with the arm. Its normal's direction
    depends on the answer, so a coarse pass over every corner and arc finds the range of swing
    first."""
    pivot = np.array([fol.pivot_sign * fol.pivot_distance, 0.0])
    corners, arriving, cone, circles = _support_pieces(profile)
    coarse = _Grid(np.arange(0.0, TWO_PI, _COARSE_STEP), grid.sigma, grid.max_pairs)
    some = corners[::_COARSE_THINNING]
    _touch_face(coarse, some, circles, fol, pivot, np.full(len(some), -math.pi),
                np.full(len(some), math.pi), np.full(len(circles), -math.pi),
                np.full(len(circles), math.pi))
    swing = coarse.best[np.isfinite(coarse.best)]
    if swing.size == 0:
        return
    margin = float(np.max(np.abs(np.diff(np.append(coarse.best, coarse.best[:1])))))
    margin = min(math.pi, margin + _COARSE_STEP) if np.isfinite(margin) else math.pi
    normal = math.pi / 2 - fol.pivot_sign * np.array([swing.min() - margin, swing.max() + margin])
    low, high = normal.min(), normal.max()
    _touch_face(grid, corners, circles, fol, pivot, low - arriving - cone, high - arriving,
                low - circles.start - circles.sweep, high - circles.start)


def _touch_face(grid: _Grid, corners: Array, circles: CirclePieces, fol: FollowerGeometry,
                pivot: Array, corner_lo: Array, corner_hi: Array, arc_lo: Array,
                arc_hi: Array) -> None:
    """The swinging face against corners and convex arcs, within the windows of σθ given."""
    for f, k in grid.turned(corner_lo, corner_hi):
        grid.keep(k, face_angle(grid.frame(corners[f], k), fol.face_offset, pivot, fol))
    if len(circles):
        for f, k in grid.turned(arc_lo, arc_hi):
            psi = face_angle(grid.frame(circles.centre[f], k),
                              fol.face_offset + circles.radius[f], pivot, fol)
            outward = grid.to_cam_angle(math.pi / 2 - fol.pivot_sign * psi, k)
            grid.keep(k, np.where(circles.in_span(outward, f), psi, -np.inf))
