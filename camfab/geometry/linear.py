"""Linear (translating, wedge or plate) cams: a plate sliding along X under a translating follower.

Conventions
-----------
- The plate lies in the XY plane with its base line, the plate's bottom edge, on y = 0. It moves
  toward −X under a follower that translates along +Y on a fixed vertical line. At travel u
  (0 ≤ u < stroke) the follower stands over the plate's point x = u, and its trace point (a
  roller's centre, a knife's edge) is at ``(u, base_height + s(u))`` in the plate's frame: that
  is the **pitch curve**. At travel 0 the follower stands over x = 0.
- The motion program maps travel to a cycle angle θ = 2π·x/stroke, so ``design.program`` is an
  ordinary motion program over one "turn" that is one stroke, and s′, s″ are per radian of that
  θ: ds/dx = s′·k and d²s/dx² = s″·k² with k = 2π/stroke (rad/mm). ``speed_rpm`` counts strokes
  per minute: ω = 2π·rpm/60, so v = ω·s′ is the follower's true velocity, and the plate
  traverses at stroke·rpm/60 mm/s. Ranges of the checks are in degrees of this cycle angle
  (360° = one stroke), as for every other cam, and their messages also give the travel in mm.
- Beyond [0, stroke) the plate continues the periodic motion (the program wraps), and it runs
  from x = −e to stroke + e with e = max(R, 1 mm) (R the roller radius, 0 for a knife), so the
  follower at either end of its travel rests on the plate under its whole footprint (a knife on
  a land of 1 mm, not on the plate's corner).

Closed forms (vectorised over arrays, no loops over points), with s_x = ds/dx and s_xx = d²s/dx²:

- pitch curve P(x) = (x, h0 + s), tangent (1, s_x)/√(1 + s_x²), normal out of the plate
  n = (−s_x, 1)/√(1 + s_x²);
- radius of curvature ρ = −(1 + s_x²)^{3/2} / s_xx: positive where the curve is convex (bends
  toward the plate's material, a crest), negative in a hollow, infinite where straight;
- working curve (the plate's edge) of a roller W = P − R·n, with ρ_w = ρ − R; a knife's is P;
- pressure angle φ = atan(s_x): from the follower's direction of motion (+Y) to the common
  normal n, counter-clockwise positive (SPEC §2), so positive on a rise — as for a
  counter-clockwise disc cam, whose surface under the follower also moves toward −X;
- undercut where 0 < ρ < R: the envelope folds over itself. The plate is then cut as a cutter
  following the design would leave it: the raw envelope's loops are trimmed away (the region
  the roller never enters is kept) and the follower run over it measures the lift error.

The follower simulation :func:`follower_heights` takes any plate outline of lines and arcs (as
read back from a DXF) and finds, for each travel u, the highest point of the vertical line x = u
at which the follower's circle touches the outline: lines offset along their outward normal
within their span, arcs grown (convex) or shrunk (concave) within their span, and caps of the
roller radius at convex corners. It is exact for lines and arcs.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import shapely

from camfab.arrays import Array, Index, Mask
from camfab.curves.plane import CurvePoints, perp, signed_angle
from camfab.curves.profile import MERGE_DISTANCE, Profile
from camfab.curves.sampling import SAMPLING_SHARE, arc_points, sample_curves
from camfab.geometry.disc_geometry import ANALYSIS_STEP, MIN_TOLERANCE_FACTOR, LiftCheck, Sampled
from camfab.geometry.runs import among, fit_grown, fit_runs
from camfab.geometry.simulate import OffsetPieces
from camfab.geometry.undercut import KeepTest, cut_away, is_simple, trim_loops
from camfab.motion.program import MotionProgram, ProgramSegment

if TYPE_CHECKING:
    from camfab.design import Design

TWO_PI = 2.0 * math.pi

#: The follower is run over the finished plate at least every 0.1° of the cycle and at least
#: every 0.1 mm of travel: finer than any feature a tolerance of 0.001 mm resolves on the lift.
VERIFY_STEP = math.radians(0.1)
VERIFY_MAX_STEP_MM = 0.1

#: How far (mm) beyond the follower's footprint the raw envelope is sampled before the plate's
#: ends are cut square: the envelope then surely crosses the plate's end lines.
END_MARGIN_MM = 1.0

#: The least length (mm) of plate beyond each end of the stroke: a knife at travel 0 then stands
#: on the plate, not on its corner. A roller's plate reaches a roller radius beyond the stroke.
END_LAND_MM = 1.0

#: Queries of the follower simulation measured at once against every piece of the outline.
_BLOCK = 256

#: Slack on spans (rad) and on the fraction along an edge, so contact exactly at a piece's end
#: is not lost to rounding (a knife has no corner caps to catch it).
_SLACK = 1e-9


@dataclass(frozen=True)
class LinearCam:
    """The exact evaluators of a linear cam (mm, rad).

    Attributes
    ----------
    stroke
        The plate's travel over one cycle (mm).
    base_height
        Height of the trace point above the base line at zero lift (mm).
    radius
        The roller radius, 0 for a knife (mm).
    """

    stroke: float
    base_height: float
    radius: float

    @property
    def overhang(self) -> float:
        """How far the plate reaches beyond each end of the stroke: max(R, 1 mm)."""
        return max(self.radius, END_LAND_MM)

    @property
    def k(self) -> float:
        """Cycle angle per millimetre of travel (rad/mm)."""
        return TWO_PI / self.stroke

    def travel(self, theta: Array) -> Array:
        """The travel (mm) at cycle angles *theta* (rad)."""
        return np.asarray(theta, dtype=np.float64) / self.k

    def slopes(self, motion: Array) -> tuple[Array, Array]:
        """ds/dx (mm/mm) and d²s/dx² (1/mm) from s, s′, s″ per radian (*motion*, (4, N))."""
        return motion[1] * self.k, motion[2] * self.k**2

    def pressure_angle(self, motion: Array) -> Array:
        """The signed pressure angle φ = atan(ds/dx) (rad), positive on a rise."""
        return np.arctan(motion[1] * self.k)

    def pitch(self, x: Array, motion: Array) -> CurvePoints:
        """The pitch curve at travels *x* (mm) with *motion* there (4, N); ``speed`` is per radian
        of the cycle angle (the sampling parameter)."""
        sx, sxx = self.slopes(motion)
        root = np.sqrt(1.0 + sx * sx)
        xy = np.stack((np.asarray(x, dtype=np.float64), self.base_height + motion[0]), axis=-1)
        tangent = np.stack((1.0 / root, sx / root), axis=-1)
        with np.errstate(divide="ignore"):
            radius = np.where(sxx == 0.0, np.inf, -(root**3) / np.where(sxx == 0.0, 1.0, sxx))
        return CurvePoints(xy, tangent, root / self.k, radius)

    def working(self, x: Array, motion: Array) -> CurvePoints:
        """The working curve (the plate's edge) at travels *x* (mm): the pitch curve moved R
        along −n; where ρ < R on a crest it runs backwards (the undercut's swallowtail)."""
        pitch = self.pitch(x, motion)
        if self.radius == 0.0:
            return pitch
        xy = pitch.xy - self.radius * perp(pitch.tangent)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(np.isinf(pitch.radius), 1.0,
                             (pitch.radius - self.radius) / pitch.radius)
        return CurvePoints(xy, pitch.tangent * np.sign(ratio)[:, None],
                           pitch.speed * np.abs(ratio), pitch.radius - self.radius)


def linear_cam(design: Design) -> LinearCam:
    """The exact evaluators of a linear-cam design."""
    cam = design.cam
    assert cam.stroke is not None and cam.base_height is not None, "design rules"
    return LinearCam(cam.stroke, cam.base_height, design.follower.trace_radius)


@dataclass(frozen=True)
class LinearDense:
    """Exact values every :data:`ANALYSIS_STEP` of the cycle, segment by segment, both ends of
    each segment included: segment index, cycle angle (rad), travel (mm), s and its
    derivatives (4, N), the pitch and working curves and the signed pressure angle (rad)."""

    segment: Index
    theta: Array
    travel: Array
    motion: Array
    pitch: CurvePoints
    working: CurvePoints
    pressure_angle: Array


@dataclass(frozen=True)
class LinearGeometry:
    """Everything geometric about a linear cam (mm).

    Attributes
    ----------
    cam
        The exact evaluators.
    tolerance
        The chord tolerance the curves were sampled with, and the arc fit's (mm).
    dense
        Exact values on the analysis grid.
    pitch
        The pitch curve over one stroke sampled within the tolerance (``theta``: cycle angle).
    pitch_corners
        Which of its points are kinks (a velocity step): arcs are not fitted across them.
    working
        The raw working curve (envelope, loops included) sampled over the plate's length and a
        little beyond; ``theta`` is the cycle angle of its pitch point, unwrapped (negative
        before travel 0, over 2π beyond the stroke).
    outline
        The plate as cut, counter-clockwise lines and arcs: up the right end, along the working
        curve (its loops trimmed), down the left end and back along the base line.
    chain
        The same plate as the counter-clockwise chain of sampled points it was fitted to (within
        the sampling tolerance of the exact curve), from the bottom right corner.
    folds
        Where the curvature says the envelope folds over (mask over ``dense``).
    self_intersecting
        Whether the raw envelope crosses itself.
    cut
        The raw envelope's points within the stroke that the plate has lost (mask over
        ``working``).
    lift
        The follower run over ``outline``.
    """

    cam: LinearCam
    tolerance: float
    dense: LinearDense
    pitch: Sampled
    pitch_corners: Mask
    working: Sampled
    outline: Profile
    chain: Array
    folds: Mask
    self_intersecting: bool
    cut: Mask
    lift: LiftCheck

    @property
    def undercut(self) -> bool:
        return bool(self.folds.any() or self.self_intersecting or self.cut.any())

    @property
    def plate_length(self) -> float:
        """From x = −e to stroke + e, e = max(R, 1 mm) (mm)."""
        return self.cam.stroke + 2.0 * self.cam.overhang

    def outline_points(self) -> Array:
        """The plate as a closed chain of points (mm), its arcs cut into chords within the
        tolerance."""
        return self.outline.points(self.tolerance)


# -- the follower run over an outline of lines and arcs -----------------------------------------

def _highest(pieces: OffsetPieces, u: Array) -> Array:
    """The highest point (mm) of each vertical line x = u on the offset *pieces*; −inf off
    them."""
    best = np.full(u.size, -np.inf)
    col = u[:, None]
    dx = pieces.q2[:, 0] - pieces.q1[:, 0]
    slanted = dx != 0.0
    if slanted.any():
        q1, q2 = pieces.q1[slanted], pieces.q2[slanted]
        t = (col - q1[:, 0]) / (q2[:, 0] - q1[:, 0])
        y = q1[:, 1] + t * (q2[:, 1] - q1[:, 1])
        inside = (t >= -_SLACK) & (t <= 1.0 + _SLACK)
        best = np.maximum(best, np.max(np.where(inside, y, -np.inf), axis=1))
    arcs = pieces.circles
    if arcs.radius.size:
        across = col - arcs.centre[:, 0]
        with np.errstate(invalid="ignore"):
            rise = np.sqrt(arcs.radius**2 - across**2)
        for sign in (1.0, -1.0):
            up = sign * rise
            angle = np.arctan2(up, across)
            rel = np.where(arcs.sweep >= 0, angle - arcs.start, arcs.start - angle)
            with np.errstate(invalid="ignore"):
                span = np.mod(rel + _SLACK, TWO_PI) <= np.abs(arcs.sweep) + 2 * _SLACK
            y = np.where(span & np.isfinite(rise), arcs.centre[:, 1] + up, -np.inf)
            best = np.maximum(best, np.max(y, axis=1))
    return best


def follower_heights(profile: Profile, radius: float, travel: Array) -> Array:
    """Where a translating follower pressed onto a sliding plate stands at each travel.

    Parameters
    ----------
    profile
        The plate's outline in its own frame (mm): a closed contour of lines and arcs, as read
        back from a DXF.
    radius
        The roller radius (mm), 0 for a knife.
    travel
        Travels u (mm): the follower's vertical line is x = u in the plate's frame.

    Returns
    -------
    Array
        The trace point's height (mm): the highest point of x = u at which the follower's circle
        touches the outline; NaN where it touches nothing.
    """
    pieces = OffsetPieces.of(profile.ccw(), radius)
    u = np.asarray(travel, dtype=np.float64)
    out = np.concatenate([_highest(pieces, u[i:i + _BLOCK]) for i in range(0, u.size, _BLOCK)]
                         or [np.zeros(0)])
    return np.where(np.isfinite(out), out, np.nan)


def verify_angles(stroke: float) -> Array:
    """Cycle angles (rad) over one stroke at which the follower is run: at least every
    :data:`VERIFY_STEP` and every :data:`VERIFY_MAX_STEP_MM` of travel."""
    count = max(round(TWO_PI / VERIFY_STEP), math.ceil(stroke / VERIFY_MAX_STEP_MM))
    return (TWO_PI / count) * np.arange(count, dtype=np.float64)


def lift_check(cam: LinearCam, program: MotionProgram, outline: Profile) -> LiftCheck:
    """Run the follower over *outline* and compare its height with base_height + s."""
    theta = verify_angles(cam.stroke)
    height = follower_heights(outline, cam.radius, cam.travel(theta))
    error = height - cam.base_height - program.evaluate(theta)[0]
    error = np.where(np.isfinite(error), error, np.inf)
    return LiftCheck(theta, error, error)


# -- sampling the curves by tolerance ------------------------------------------------------------

@dataclass(frozen=True)
class _Piece:
    """A stretch of one segment within one cycle: local cycle angles [lo, hi] (rad) into *seg*
    in cycle number *cycle* (0 is the stroke itself)."""

    seg: ProgramSegment
    cycle: int
    lo: float
    hi: float


def _pieces(program: MotionProgram, stroke: float, x_lo: float, x_hi: float) -> list[_Piece]:
    """The segments' stretches covering travels [x_lo, x_hi] (mm), in order."""
    k = TWO_PI / stroke
    out = []
    for cycle in range(math.floor(x_lo / stroke), math.floor(x_hi / stroke) + 1):
        for seg in program.segments:
            a = cycle * stroke + seg.start / k
            lo, hi = max(a, x_lo), min(a + seg.span / k, x_hi)
            if hi > lo:
                out.append(_Piece(seg, cycle, (lo - a) * k, (hi - a) * k))
    return out


Evaluator = Callable[[Array, Array], CurvePoints]


def _sample(cam: LinearCam, program: MotionProgram, pieces: list[_Piece],
            evaluator: Evaluator, tolerances: Array, join_arcs: bool) -> tuple[Sampled, Mask]:
    """The curve over *pieces* (of *program*'s segments) sampled within each segment's
    tolerance (mm), as one chain with its unwrapped cycle angles, and which points are corners
    (a velocity step's kink in a pitch or knife curve). With *join_arcs* (a roller's working
    curve) a velocity step is bridged by the arc the roller rolls over the pitch curve's corner.

    Every piece is sampled in the same rounds (:func:`camfab.curves.sampling.sample_curves`:
    the points each would have alone), its chords densified at once; only the joins go piece
    by piece."""
    count = len(pieces)
    segment = np.array([piece.seg.index for piece in pieces], dtype=np.intp)
    offset = np.array([piece.cycle * TWO_PI + piece.seg.start for piece in pieces])
    lo = np.array([piece.lo for piece in pieces])
    hi = np.array([piece.hi for piece in pieces])

    def curve_at(i: Index, t: Array) -> CurvePoints:
        local = lo[i] + t
        return evaluator((offset[i] + local) / cam.k, program.evaluate_local(segment[i], local))

    owner, t, xy = _densified(curve_at, *sample_curves(curve_at, hi - lo, tolerances[segment]))
    bounds = np.searchsorted(owner, np.arange(count + 1))
    # each piece's tangent where it starts and where it ends; a roller's corner centre
    every = np.arange(count)
    first_tangent = curve_at(every, np.zeros(count)).tangent
    last_tangent = evaluator((offset + hi) / cam.k, program.evaluate_local(segment, hi)).tangent
    centres = (cam.pitch((offset + lo) / cam.k, program.evaluate_local(segment, lo)).xy
               if join_arcs else None)
    thetas: list[Array] = []
    points: list[Array] = []
    corners: list[Mask] = []
    for i in range(count):
        mine = slice(int(bounds[i]), int(bounds[i + 1]))
        base = offset[i] + lo[i]
        piece_t, piece_xy = t[mine], xy[mine]
        corner = np.zeros(len(piece_t), dtype=bool)
        if i > 0:  # the previous piece ends where this one starts
            start, end = points[-1][-1], piece_xy[0]
            if float(np.hypot(*(end - start))) <= MERGE_DISTANCE:
                turn = signed_angle(last_tangent[i - 1][None], first_tangent[i][None])
                corners[-1][-1] |= bool(abs(float(turn[0])) > 1e-9)
                piece_t, piece_xy, corner = piece_t[1:], piece_xy[1:], corner[1:]
            elif centres is not None:
                centre = centres[i]
                sweep = float(signed_angle((start - centre)[None], (end - centre)[None])[0])
                arc = arc_points(centre, start, sweep, float(tolerances[segment[i]]))[1:-1]
                thetas.append(np.full(len(arc), base))
                points.append(arc)
                corners.append(np.zeros(len(arc), dtype=bool))
        thetas.append(base + piece_t)
        points.append(piece_xy)
        corners.append(corner)
    return Sampled(np.concatenate(thetas), np.concatenate(points)), np.concatenate(corners)


#: Exact points added inside every sampled chord before the arc fit: the fit measures only the
#: points it is given, and a straight stretch (a dwell) is sampled sparsely, so without them an
#: arc reaching from a bend into a dwell could bow away from the straight edge between points.
DENSIFY = 4


def _densified(curve_at: Callable[[Index, Array], CurvePoints], owner: Index, t: Array,
               xy: Array) -> tuple[Index, Array, Array]:
    """The samples (*owner* curve, parameter *t*, point *xy*) of many curves with
    :data:`DENSIFY` − 1 exact points added inside each chord of a curve."""
    chord = np.flatnonzero(owner[1:] == owner[:-1])  # a chord from sample k to k + 1
    frac = np.arange(1, DENSIFY) / DENSIFY
    inner = (t[chord, None] + (t[chord + 1] - t[chord])[:, None] * frac).ravel()
    xy_inner = curve_at(np.repeat(owner[chord], DENSIFY - 1), inner).xy
    # each sample, then the points inside the chord it starts
    size = np.ones(t.size, dtype=np.intp)
    size[chord] = DENSIFY
    at = np.cumsum(size) - size
    where = (at[chord, None] + np.arange(1, DENSIFY)).ravel()
    out_owner = np.repeat(owner, size)
    out_t = np.empty(out_owner.size)
    out_xy = np.empty((out_owner.size, 2))
    out_t[at], out_xy[at] = t, xy
    out_t[where], out_xy[where] = inner, xy_inner
    return out_owner, out_t, out_xy


def dense_curves(cam: LinearCam, program: MotionProgram,
                 step: float = ANALYSIS_STEP) -> LinearDense:
    """The exact curves every *step* of the cycle over one stroke, segment by segment."""
    segment, theta, motion = program.segment_grid(step)
    x = cam.travel(theta)
    return LinearDense(segment, theta, x, motion, cam.pitch(x, motion), cam.working(x, motion),
                       cam.pressure_angle(motion))


def segment_tolerances(dense: LinearDense, tolerance: float, count: int) -> Array:
    """The chord tolerance of each segment (mm): the sampling share of *tolerance*, scaled by
    cos φ so the follower's lift error (a deviation δ along the normal moves it δ/cos φ) stays
    within that share."""
    worst = np.ones(count)
    np.minimum.at(worst, dense.segment, np.cos(dense.pressure_angle))
    return tolerance * SAMPLING_SHARE * np.maximum(worst, MIN_TOLERANCE_FACTOR)


# -- the plate ------------------------------------------------------------------------------------

def _outside_sweep(pitch_xy: Array, radius: float, slack: float) -> KeepTest:
    """Points under the pitch curve and at least *radius* − *slack* from it: where the follower's
    circle, its centre running along the pitch curve, never reaches."""
    line = shapely.LineString(pitch_xy)
    # an indexed test: plain distances take faces × pitch points time (minutes for a cam of a
    # thousand segments whose every bump is undercut)
    shapely.prepare(line)

    def keep(points: Array) -> Mask:
        under = points[:, 1] < np.interp(points[:, 0], pitch_xy[:, 0], pitch_xy[:, 1])
        far = ~shapely.dwithin(line, shapely.points(points), radius - slack)
        return np.asarray(under & far, dtype=bool)

    return keep


def fit_open(chain: Array, corners: Mask, tolerance: float) -> Profile:
    """An open chain (a pitch curve) as lines and arcs; the profile's closing edge is not part
    of the curve (see :func:`camfab.geometry.arcfit.fit_arcs`)."""
    vertices, bulges = fit_runs(chain, corners, tolerance)
    return Profile(vertices, bulges)


def _raw_ring(working: Sampled) -> Array:
    """The raw envelope closed down to the base line: a ring that crosses itself where the
    envelope folds over."""
    w = working.xy
    return np.vstack((w, [[w[-1, 0], 0.0], [w[0, 0], 0.0]]))


def _plate_ring(cam: LinearCam, working: Sampled, corners: Mask, pitch: Sampled,
                trim: bool, tolerance: float) -> tuple[Array, Mask]:
    """The plate's outline as a counter-clockwise chain of points starting at the bottom right
    corner, with the corners of its top (where loops were cut, velocity-step kinks) marked.
    With *trim* the raw envelope's loops are cut away first (the region the follower, its
    centre on the sampled *pitch* curve, never enters is kept)."""
    e, stroke = cam.overhang, cam.stroke
    w = working.xy
    ring = _raw_ring(working)
    if trim:
        ring = trim_loops(ring, _outside_sweep(pitch.xy, cam.radius, tolerance))
    top = float(np.max(ring[:, 1])) + 1.0
    region = shapely.clip_by_rect(shapely.Polygon(ring), -e, -1.0, stroke + e, top)
    parts = shapely.get_parts(region)
    largest = parts[int(np.argmax(shapely.area(parts)))]
    exterior = shapely.LinearRing(largest.exterior)
    xy = np.asarray(exterior.coords)[:-1]
    if not exterior.is_ccw:
        xy = xy[::-1]
    start = int(np.argmin(np.hypot(xy[:, 0] - (stroke + e), xy[:, 1])))
    xy = np.roll(xy, -start, axis=0)
    keep = np.hypot(*(np.roll(xy, -1, axis=0) - xy).T) > MERGE_DISTANCE
    xy = xy[keep]
    # a top vertex that is not a sampled point of the envelope is where a loop was cut
    marked = ~among(xy, w) | among(xy, w[corners])
    return xy, marked


def plate_outline(ring: Array, marked: Mask, tolerance: float) -> Profile:
    """The plate's outline as lines and arcs: its two ends and base line straight, its top (the
    working curve) fitted within *tolerance* between its corners."""
    top = ring[1:-1]  # from the top of the right end, right to left, to the top of the left end
    vertices, bulges = fit_runs(top, marked[1:-1], tolerance)
    return Profile(np.vstack((ring[:1], vertices, ring[-1:])),
                   np.concatenate(([0.0], bulges, [0.0])))


def linear_geometry(design: Design) -> LinearGeometry:
    """Build the geometry of a linear-cam design."""
    cam = linear_cam(design)
    program = design.program
    dense = dense_curves(cam, program)
    tolerances = segment_tolerances(dense, design.manufacturing.tolerance,
                                    len(program.segments))
    tolerance = float(tolerances.min())
    pitch, pitch_corners = _sample(cam, program, _pieces(program, cam.stroke, 0.0, cam.stroke),
                                   cam.pitch, tolerances, join_arcs=False)
    reach = cam.overhang + cam.radius + END_MARGIN_MM
    extended = _pieces(program, cam.stroke, -reach, cam.stroke + reach)
    working, corners = _sample(cam, program, extended, cam.working, tolerances,
                               join_arcs=cam.radius > 0.0)
    wide_pitch, _ = _sample(cam, program, extended, cam.pitch, tolerances, join_arcs=False)
    folded = (dense.pitch.radius > 0.0) & (dense.pitch.radius < cam.radius)
    crossing = not is_simple(_raw_ring(working))
    trim = crossing or bool(folded.any())
    chain, marked = _plate_ring(cam, working, corners, wide_pitch, trim, tolerance)
    outline = plate_outline(chain, marked, tolerance)
    within = (working.theta >= 0.0) & (working.theta < TWO_PI)
    cut = np.zeros(len(working.xy), dtype=bool)
    if trim:
        cut[within] = cut_away(working.xy[within], chain, 2.0 * tolerance)
    return LinearGeometry(cam, tolerance, dense, pitch, pitch_corners, working, outline, chain,
                          folded, crossing, cut, lift_check(cam, program, outline))


def offset_plate(chain: Array, distance: float, tolerance: float) -> Profile:
    """The plate through the closed *chain* (mm) grown by *distance* (mm; a laser beam's path
    for kerf/2, a milling cutter's centre path for its radius), with round joins, fitted with
    lines and arcs within *tolerance* (mm)."""
    from camfab.geometry.offset import grow
    from camfab.geometry.plate import OFFSET_SHARE

    grown = max(grow(chain, distance, OFFSET_SHARE * tolerance), key=len)
    return fit_grown(grown, distance, tolerance)
