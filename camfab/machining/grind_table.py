"""The cam grinding table: the radius X of a grinding wheel's centre against the cam angle C.

On a cam grinder (or a lathe turning a cam on a C axis) the cam turns on C and the wheel's centre
moves on a fixed line through the cam's axis, X its distance from the axis (a radius: no
diameter mode). A wheel of radius R touches the cam where a roller of that radius would, so its
centre runs on the pitch curve of a translating roller of radius R with no offset: the profile
moved R outward along its normal, read in polar coordinates about the cam's axis.

C is the cam angle θ of the design's frame (SPEC §2): at C the wheel's line is the frame's +Y
(a translating follower's direction), which on the cam is the ray ``Rot(−σC)·(0, 1)``; C grows
as the cam turns in its rotation. For a radial roller follower as large as the wheel, X(C) is
the follower's pitch radius ``Rp + s(C)``.

The profile is the exact working curve of each motion segment
(:meth:`~camfab.geometry.disc.DiscCam.working`), joined where the motion's velocity steps by what
the follower's shape makes there: a flat face's straight edge, a knife's corner (the wheel rolls
round it) or a roller's hollow (which the wheel fits only if it is no larger than the roller).
The wheel can grind the whole profile only while X(C) is one radius per angle: where a concave
part is tighter than the wheel, or the profile turns so far that its normal no longer faces the
wheel's line, the wheel's path runs backwards in C and the table is refused, naming where
(:class:`WheelCannot`).

The rows are placed by tolerance (as :mod:`camfab.curves.sampling` places a curve's points):
the exact X and C between every two rows, at a quarter, half and three quarters of the way in
the curve's parameter, are held against X interpolated straight between the rows, and a pair
that strays further than :data:`GRIND_SHARE` of the tolerance is split, round after round.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camfab.angles import Range, ranges_deg
from camfab.arrays import Array, Index, spaced
from camfab.curves.plane import cross, offset_inward, perp, rotate, signed_angle
from camfab.curves.profile import MERGE_DISTANCE
from camfab.curves.sampling import MAX_STEP, probes_within
from camfab.geometry.disc import DiscCam
from camfab.geometry.disc_geometry import DenseCurves
from camfab.motion.program import MotionProgram

#: The share of ``manufacturing.tolerance`` spent on the straight interpolation of X between
#: the table's rows; the rest is left to the rounding of the written numbers (0.1 µm of X,
#: 0.0001° of C: under 0.1 µm more where X changes 50 mm per radian) and to what the probes
#: between two rows miss of the worst point between them.
GRIND_SHARE = 0.5

#: Rounds of splitting; each halves the offending intervals.
_MAX_ROUNDS = 40

#: Bisection steps that find where the table starts (C = its start angle): 60 halvings of an
#: interval of at most a few degrees reach the rounding of the angle.
_START_STEPS = 60


class WheelCannot(ValueError):
    """The wheel cannot grind the profile: ``reason`` says why and where (cam angles, deg)."""

    def __init__(self, reason: str, ranges: tuple[Range, ...] = ()) -> None:
        super().__init__(reason)
        self.reason = reason
        self.ranges = ranges


@dataclass(frozen=True)
class GrindTable:
    """The wheel centre's radius against the cam angle, rows in increasing C over one turn,
    the first at C = 0 and the last a turn on (the same position closing the table).

    Attributes
    ----------
    c
        (N,) cam angles C (rad), from 0 to 2π.
    x
        (N,) the wheel centre's distance from the cam's axis (mm).
    contact
        (N, 2) where the wheel touches the profile (mm, in the cam's frame).
    theta
        (N,) the design's cam angle of that profile point (rad): where the follower touches it.
    length
        (N − 1,) the distance the contact travels over the cam's surface from each row to the
        next (mm): the chord of the profile between the contact points, or where the contact
        rests on a corner the wheel rolls round, the chord of the wheel centre's path.
    """

    c: Array
    x: Array
    contact: Array
    theta: Array
    length: Array


@dataclass(frozen=True)
class _Bridges:
    """What joins the wheel's path over the profile of two motion segments where the
    velocity steps, one row per joint with a gap: after segment ``after`` at cam angle
    ``theta`` (rad). An arc (``line`` False) turns the unit ``normal`` by ``sweep`` (rad)
    about ``centre``, the wheel's centre ``reach`` (mm, signed) along it and the contact
    ``touch`` along it; a line runs straight from ``centre`` (the wheel's centre) by
    ``chord`` (mm, (B, 2)), the contact from ``touch_start`` by ``touch_chord``."""

    after: Index
    theta: Array
    line: Array
    centre: Array
    normal: Array
    sweep: Array
    reach: Array
    touch: Array
    chord: Array
    touch_start: Array
    touch_chord: Array
    span: Array


class WheelPath:
    """The exact path of the centre of a wheel of *radius* (mm) round the plate cam *cam*
    driving its follower through *program*, as pieces in the order of the turn: each motion
    segment, then what bridges the joint after it (a corner rolled round, a flat face's edge),
    if anything. Piece p is evaluated at parameters 0 ≤ t ≤ ``span[p]`` (rad of cam angle for
    a segment, of turn for an arc, of the angle the line subtends at the axis for a line).

    Raises
    ------
    WheelCannot
        A joint of the profile has a hollow the wheel cannot enter.
    """

    def __init__(self, cam: DiscCam, program: MotionProgram, radius: float) -> None:
        self.cam, self.program, self.radius = cam, program, radius
        table = program.table
        self.bridges = _bridges(cam, program, radius)
        count = len(table.span)
        has = np.zeros(count, dtype=bool)
        has[self.bridges.after] = True
        # the chain: each segment then its bridge (-1 where the piece is not one)
        per = 1 + has.astype(np.intp)
        first = np.cumsum(per) - per
        size = int(per.sum())
        self.segment = np.full(size, -1, dtype=np.intp)
        self.segment[first] = np.arange(count)
        self.bridge = np.full(size, -1, dtype=np.intp)
        self.bridge[first[self.bridges.after] + 1] = np.arange(len(self.bridges.after))
        self.span = np.where(self.segment >= 0, table.span[np.maximum(self.segment, 0)],
                             self.bridges.span[np.maximum(self.bridge, 0)]
                             if len(self.bridges.after) else 0.0)

    def at(self, piece: Index, t: Array) -> tuple[Array, Array, Array]:
        """The wheel's centre (mm), the contact (mm) and the design's cam angle of the
        contact (rad) at parameters *t* of pieces *piece* (both (N,))."""
        cam, table = self.cam, self.program.table
        centre, touch, theta = np.empty((len(t), 2)), np.empty((len(t), 2)), np.empty(len(t))
        on = self.segment[piece] >= 0
        if on.any():
            k = self.segment[piece[on]]
            angle = table.start[k] + t[on]
            working = cam.working(angle, self.program.evaluate_local(k, t[on]))
            touch[on] = working.xy
            centre[on] = working.xy + cam.sigma * self.radius * perp(working.tangent)
            theta[on] = angle
        off = ~on
        if off.any():
            b, bridges = self.bridge[piece[off]], self.bridges
            share = t[off] / bridges.span[b]
            normal = rotate(bridges.normal[b], share * bridges.sweep[b])
            straight = bridges.line[b][:, None]
            centre[off] = np.where(straight, bridges.centre[b] + share[:, None] * bridges.chord[b],
                                   bridges.centre[b] + bridges.reach[b][:, None] * normal)
            touch[off] = np.where(straight, bridges.touch_start[b]
                                  + share[:, None] * bridges.touch_chord[b],
                                  bridges.centre[b] + bridges.touch[b][:, None] * normal)
            theta[off] = bridges.theta[b]
        return centre, touch, theta


def _bridges(cam: DiscCam, program: MotionProgram, radius: float) -> _Bridges:
    """The bridges of the wheel's path over the joints where the velocity steps (see
    :class:`_Bridges`): the profile's one-sided ends at each joint, and what the follower's
    shape makes between them."""
    table, sigma, fol = program.table, cam.sigma, cam.follower
    count = len(table.span)
    after = np.arange(count)
    ahead = np.roll(after, -1)
    theta = table.start + table.span
    left = cam.working(theta, program.evaluate_local(after, table.span))
    right = cam.working(table.start[ahead], program.evaluate_local(ahead, np.zeros(count)))
    n_left, n_right = sigma * perp(left.tangent), sigma * perp(right.tangent)
    o_left = left.xy + radius * n_left
    o_right = right.xy + radius * n_right
    gap = np.hypot(*(o_right - o_left).T) > MERGE_DISTANCE
    k = np.flatnonzero(gap)
    turn = signed_angle(n_left[k], n_right[k])
    # along a convex stretch of the profile its outward normal turns the way −σ says
    convex = -sigma * turn > 0.0
    line = np.full(k.size, fol.flat)
    if not fol.flat:
        hollow = ~convex if fol.radius == 0.0 else ~convex & (fol.radius < radius)
        if hollow.any():
            spots = _spots(theta[k][hollow])
            shape = ("a sharp hollow of the profile (the velocity of the motion steps there)"
                     if fol.radius == 0.0 else
                     f"the hollow a roller of radius {fol.radius:.4g} mm rolls where the "
                     "velocity of the motion steps, tighter than the wheel")
            raise WheelCannot(f"the wheel cannot reach into {shape} at {_where(spots)}", spots)
        if fol.radius > 0.0 and convex.any():  # the envelope crossed itself: undercut
            spots = _spots(theta[k][convex])
            raise WheelCannot(f"the profile is undercut at {_where(spots)}", spots)
    pitch = left.xy[k] + fol.radius * n_left[k]  # the knife's corner, or the roller's centre
    chord = o_right[k] - o_left[k]
    subtended = np.abs(signed_angle(o_left[k], o_right[k]))
    return _Bridges(
        after=k, theta=theta[k], line=line,
        centre=np.where(line[:, None], o_left[k], pitch), normal=n_left[k],
        sweep=np.where(line, 0.0, turn),
        reach=np.full(k.size, radius - fol.radius), touch=np.full(k.size, -fol.radius),
        chord=chord, touch_start=left.xy[k], touch_chord=right.xy[k] - left.xy[k],
        span=np.maximum(np.where(line, subtended, np.abs(turn)), 1e-12))


def _cam_angle(centre: Array, sigma: int) -> Array:
    """The cam angle C (rad, in (−π, π] before unwrapping) at which the wheel's line passes
    through each of *centre* (mm, cam frame): the ray ``Rot(−σC)·(0, 1)`` points at it."""
    return sigma * (math.pi / 2 - np.arctan2(centre[:, 1], centre[:, 0]))


def _near(angle: Array, reference: Array) -> Array:
    """*angle* (rad) moved by whole turns to within half a turn of *reference*."""
    return reference + np.mod(angle - reference + math.pi, 2 * math.pi) - math.pi


def unreachable(cam: DiscCam, dense: DenseCurves, folds: Array, radius: float) -> None:
    """Refuse a profile the wheel cannot follow over the dense grid of its exact curves: a
    concave part tighter than the wheel, or a stretch whose normal turns its back to the
    wheel's line (its path in C runs backwards there).

    Raises
    ------
    WheelCannot
        With where, in cam angles (deg).
    """
    working = dense.working
    tight = (working.radius < 0.0) & ~folds & (-working.radius < radius)
    if tight.any():
        spots = ranges_deg(dense.theta, tight)
        smallest = float(np.min(-working.radius[tight]))
        raise WheelCannot(f"the profile is concave tighter than the wheel's radius "
                          f"{radius:.4g} mm at {_where(spots)} (its concave radius falls to "
                          f"{smallest:.4g} mm): a wheel under {2 * smallest:.4g} mm across "
                          "fits it", spots)
    centre = offset_inward(working, cam.sigma, -radius)
    backwards = -cam.sigma * cross(centre.xy, centre.tangent) <= 0.0
    if backwards.any():
        spots = ranges_deg(dense.theta, backwards)
        raise WheelCannot(f"the profile turns away from the wheel's line at {_where(spots)}: "
                          "a wheel moving on a line through the cam's axis cannot reach it",
                          spots)


def _where(ranges: tuple[Range, ...]) -> str:
    from camfab.analysis.cam_checks import where

    return f"cam angles {where(ranges)}"


def grind_table(path: WheelPath, tolerance: float, start: float = 0.0) -> GrindTable:
    """The table of the wheel's centre radius X against the cam angle C along *path*, its rows
    placed so X interpolated straight between two rows stays within :data:`GRIND_SHARE` of
    *tolerance* (mm) of the exact X; its C measured from *start* (rad: the table's row 0 is the
    path's C = *start*).

    Raises
    ------
    WheelCannot
        The path runs backwards in C somewhere (the wheel cannot follow the profile there).
    """
    limit = GRIND_SHARE * tolerance
    counts = np.maximum(2, np.ceil(path.span / MAX_STEP).astype(np.intp) + 1)
    piece, t = spaced(np.maximum(path.span, 1e-12), counts)
    centre, touch, theta = path.at(piece, t)
    c = np.unwrap(_cam_angle(centre, path.cam.sigma))
    piece, t, c, centre, touch, theta = _refine(path, piece, t, c, centre, touch, theta, limit,
                                                np.ones(len(t) - 1, dtype=bool))
    if not math.isclose(c[-1] - c[0], 2 * math.pi, abs_tol=1e-6):
        raise WheelCannot("the wheel's path does not go once round the cam's axis")
    piece, t, c, centre, touch, theta = _start_at(path, piece, t, c, centre, touch, theta,
                                                  start, limit)
    # a piece's end and the next one's start are one position: keep one of them
    joint = (piece[1:] != piece[:-1]) & (np.hypot(*np.diff(centre, axis=0).T)
                                         <= 2 * MERGE_DISTANCE)
    keep = np.append(~joint, True)
    c, centre, touch, theta = c[keep], centre[keep], touch[keep], theta[keep]
    step = np.hypot(*np.diff(touch, axis=0).T)
    rolled = np.hypot(*np.diff(centre, axis=0).T)
    length = np.where(step > MERGE_DISTANCE, step, rolled)
    return GrindTable(c, np.hypot(*centre.T), touch, np.mod(theta, 2 * math.pi), length)


def _refine(path: WheelPath, piece: Index, t: Array, c: Array, centre: Array, touch: Array,
            theta: Array, limit: float, fresh: Array) -> tuple[Array, ...]:
    """Split every interval between two rows (of one piece) whose straight X strays further
    than *limit* (mm) from the exact X at the probes, round after round, measuring only the
    intervals made in the round before (*fresh*); refuse a path that runs backwards in C."""
    sigma = path.cam.sigma
    fresh = fresh & (piece[1:] == piece[:-1])
    for _ in range(_MAX_ROUNDS):
        at = np.flatnonzero(fresh)
        if not at.size:
            break
        inner = probes_within(t, at)
        per = len(inner) // len(at)
        probe_centre, probe_touch, probe_theta = path.at(np.repeat(piece[at], per), inner)
        c_lo, c_hi = c[at], c[at + 1]
        probe_c = _near(_cam_angle(probe_centre, sigma), np.repeat(c_lo, per)).reshape(len(at),
                                                                                       per)
        order = np.column_stack((c_lo, probe_c, c_hi))  # C must grow through the interval
        backwards = np.any(np.diff(order, axis=1) <= 0.0, axis=1)
        if backwards.any():
            spots = _spots(theta[at[backwards]])
            raise WheelCannot(f"the wheel's path runs backwards at {_where(spots)}: a wheel "
                              "moving on a line through the cam's axis cannot follow the "
                              "profile there", spots)
        x_lo, x_hi = np.hypot(*centre[at].T), np.hypot(*centre[at + 1].T)
        share = (probe_c - c_lo[:, None]) / (c_hi - c_lo)[:, None]
        straight = x_lo[:, None] + share * (x_hi - x_lo)[:, None]
        exact = np.hypot(*probe_centre.T).reshape(len(at), -1)
        split = np.max(np.abs(exact - straight), axis=1) > limit
        fresh[at[~split]] = False
        where = at[split] + 1
        middle = per // 2 + per * np.flatnonzero(split)  # the half-way probe of each
        t = np.insert(t, where, inner[middle])
        c = np.insert(c, where, probe_c[split, 1])
        centre = np.insert(centre, where, probe_centre[middle], axis=0)
        touch = np.insert(touch, where, probe_touch[middle], axis=0)
        theta = np.insert(theta, where, probe_theta[middle])
        piece = np.insert(piece, where, piece[at[split]])
        fresh = np.insert(fresh, where, True)
    return piece, t, c, centre, touch, theta


def _spots(theta: Array) -> tuple[Range, ...]:
    """Cam angles *theta* (rad) as the ranges of a message (deg, in one turn): each one a
    point."""
    deg = np.unique(np.round(np.round(np.degrees(theta), 9) % 360.0, 4))
    return tuple((float(a), float(a)) for a in deg)


def _start_at(path: WheelPath, piece: Index, t: Array, c: Array, centre: Array, touch: Array,
              theta: Array, start: float, limit: float) -> tuple[Array, ...]:
    """The rows turned to begin at C = *start* (rad, by whole turns the first at or after
    the path's first C) and measured from it, a row placed there exactly (bisection on the
    piece that crosses it) and the intervals either side of it measured again."""
    target = start + 2 * math.pi * math.ceil((c[0] - start) / (2 * math.pi) - 1e-12)
    i = int(np.searchsorted(c, target, side="right")) - 1
    if not math.isclose(c[i], target, rel_tol=0.0, abs_tol=1e-12):
        if piece[i] != piece[i + 1]:  # a joint's two rows: the one after it starts a piece
            i += 1
        lo, hi = float(t[i]), float(t[i + 1])
        p = piece[i:i + 1]
        for _ in range(_START_STEPS):
            mid = 0.5 * (lo + hi)
            point = path.at(p, np.array([mid]))[0]
            if _near(_cam_angle(point, path.cam.sigma), np.array([c[i]]))[0] < target:
                lo = mid
            else:
                hi = mid
        mid = 0.5 * (lo + hi)
        new_centre, new_touch, new_theta = path.at(p, np.array([mid]))
        t, c = np.insert(t, i + 1, mid), np.insert(c, i + 1, target)
        centre = np.insert(centre, i + 1, new_centre, axis=0)
        touch = np.insert(touch, i + 1, new_touch, axis=0)
        theta = np.insert(theta, i + 1, new_theta)
        piece = np.insert(piece, i + 1, piece[i])
        fresh = np.zeros(len(t) - 1, dtype=bool)
        fresh[i:i + 2] = True
        piece, t, c, centre, touch, theta = _refine(path, piece, t, c, centre, touch, theta,
                                                    limit, fresh)
        i = int(np.flatnonzero(np.isclose(c, target, rtol=0.0, atol=1e-12))[0])
    # rows i .. end, then rows 1 .. i a turn on (row 0 is the last row a turn back)
    turn = 2 * math.pi
    order = np.concatenate((np.arange(i, len(t)), np.arange(1, i + 1)))
    c = np.concatenate((c[i:], c[1:i + 1] + turn))
    return (piece[order], t[order], c - target, centre[order], touch[order], theta[order])
