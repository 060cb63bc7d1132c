"""A disc cam built from its design: exact curves on a dense grid for the analysis, sampled curves
for the exports, the cam that is really cut (undercut loops trimmed), and the lift a follower
really gets on it.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from functools import partial
from typing import TYPE_CHECKING, Literal

import numpy as np

from camfab.arrays import Array, Index, Mask
from camfab.curves.follower import FollowerGeometry
from camfab.curves.plane import CurvePoints, offset_inward, signed_angle
from camfab.curves.profile import MERGE_DISTANCE, Profile
from camfab.curves.sampling import arc_points, sample_curves
from camfab.geometry.disc import DiscCam, FaceLines
from camfab.geometry.runs import among
from camfab.geometry.simulate import simulate
from camfab.geometry.undercut import (
    KeepTest,
    below_face_lines,
    crossings,
    cut_away,
    is_simple,
    outside_circle_sweep,
    trim_loops,
)
from camfab.motion.program import MotionProgram, cycle_angles

if TYPE_CHECKING:
    from camfab.design import Design

#: Cam-angle step of the dense exact evaluation behind every reported extreme (pressure angle,
#: radius of curvature): 0.05° puts a smooth extreme within about 1e-6 of its value.
ANALYSIS_STEP = math.radians(0.05)

#: Cam-angle step at which the follower is run over the finished profile: 0.1°, finer than any
#: feature of a cam a tolerance of 0.001 mm can resolve on its lift.
VERIFY_STEP = math.radians(0.1)


@dataclass(frozen=True)
class DenseCurves:
    """Exact values on a fine grid, segment by segment, both ends of each segment included (the
    one-sided values at a joint). ``lines`` and ``face_contact`` are None unless the follower
    is flat."""

    segment: Index
    theta: Array
    motion: Array
    pitch: CurvePoints
    working: CurvePoints
    pressure_angle: Array
    lines: FaceLines | None
    face_contact: Array | None


@dataclass(frozen=True)
class Sampled:
    """A closed curve sampled within the tolerance, in θ order: (M,) angles and (M, 2) points."""

    theta: Array
    xy: Array


@dataclass(frozen=True)
class LiftCheck:
    """The follower run over a profile: its lift error against the design at each angle.

    ``error`` is in the lift's unit (mm, or rad for an oscillating follower); ``error_mm`` is the
    same measured at the trace point (rad × arm length for an oscillating follower).
    """

    theta: Array
    error: Array
    error_mm: Array

    @property
    def max_mm(self) -> float:
        return float(np.max(np.abs(self.error_mm)))

    @property
    def at_deg(self) -> float:
        return float(np.degrees(self.theta[int(np.argmax(np.abs(self.error_mm)))]))


@dataclass(frozen=True)
class DiscGeometry:
    """Everything geometric about a disc cam.

    Attributes
    ----------
    cam
        The exact evaluators.
    tolerance
        The chord tolerance the curves were sampled with (mm).
    pitch, working
        The sampled pitch curve and raw working curve (envelope, loops included).
    profile
        The cam that is cut: the working curve, its loops trimmed if it folds over (ccw).
    folds
        Where the curvature says the envelope folds over (dense grid mask).
    self_intersecting
        Whether the raw working curve crosses itself.
    cut
        The raw working-curve points the trimmed profile has lost (mask over ``working``).
    lift
        The follower run over ``profile``.
    exact
        True when ``profile`` is the cam's exact outline of lines and arcs (a cam drawn from
        its shape), not the working curve sampled within the tolerance.
    """

    cam: DiscCam
    tolerance: float
    dense: DenseCurves
    pitch: Sampled
    working: Sampled
    profile: Profile
    folds: Mask
    self_intersecting: bool
    cut: Mask
    lift: LiftCheck
    exact: bool = False

    def outline_points(self) -> Array:
        """The cut profile as a closed chain of points (mm) within the sampling tolerance: the
        profile's own points, or its arcs cut into chords when it is exact."""
        return self.profile.points(self.tolerance) if self.exact else self.profile.vertices

    @property
    def undercut(self) -> bool:
        return bool(self.folds.any() or self.self_intersecting or self.cut.any())

    @property
    def corners(self) -> Mask:
        """The profile's vertices where loops of the envelope were cut away (those that are not
        sampled points of the working curve), over ``profile.vertices``: the trimmed cam's
        corners, which its fit with lines and arcs keeps (none on an exact outline or a cam that
        was not trimmed)."""
        vertices = self.profile.vertices
        if self.exact or not self.undercut:
            return np.zeros(len(vertices), dtype=bool)
        return ~among(vertices, self.working.xy)


def dense_curves(cam: DiscCam, program: MotionProgram, step: float = ANALYSIS_STEP) -> DenseCurves:
    """The exact curves at every *step* of cam angle, segment by segment."""
    segment, theta, motion = program.segment_grid(step)
    lines = cam.face_lines(theta, motion) if cam.follower.flat else None
    contact = None if lines is None else cam.face_contact(theta, motion, lines)
    return DenseCurves(segment, theta, motion, cam.pitch(theta, motion),
                       cam.working(theta, motion, lines),
                       cam.pressure_angle(theta, motion, lines), lines, contact)


def sample_closed(cam: DiscCam, program: MotionProgram,
                  curve: Literal["pitch", "working", "outer"],
                  tolerance: float | Array) -> Sampled:
    """The closed pitch or working curve sampled within *tolerance* (mm; one value, or one per
    segment), segment by segment (every segment sampled at once); ``outer`` is the pitch curve
    offset outward by the follower's radius (a groove cam's outer wall).

    Where a roller's pitch curve has a corner (a velocity step at a joint), the working curve is
    joined by the arc the roller rolls over the corner; a flat face's contact points are joined
    by the straight edge between them.
    """
    evaluators: dict[str, Callable[[Array, Array], CurvePoints]] = {
        "pitch": cam.pitch, "working": cam.working, "outer": partial(outer_wall, cam)}
    evaluator = evaluators[curve]
    table = program.table
    tolerances = np.broadcast_to(np.asarray(tolerance, dtype=np.float64), table.span.shape)

    def curve_at(index: Index, t: Array) -> CurvePoints:
        return evaluator(table.start[index] + t, program.evaluate_local(index, t))

    index, t, xy = sample_curves(curve_at, table.span, tolerances)
    theta = table.start[index] + t
    if curve != "pitch" and cam.follower.radius > 0.0:
        theta, xy = _corner_arcs(cam, program, evaluator, index, theta, xy, tolerances)
    step = np.hypot(*(np.roll(xy, -1, axis=0) - xy).T)
    keep = step > MERGE_DISTANCE
    return Sampled(theta[keep], xy[keep])


def _corner_arcs(cam: DiscCam, program: MotionProgram,
                 evaluator: Callable[[Array, Array], CurvePoints], index: Index, theta: Array,
                 xy: Array, tolerances: Array) -> tuple[Array, Array]:
    """The sampled curve (θ in rad, points in mm, segment by segment; segment *index*) with the
    arc the roller rolls over each corner of the pitch curve put after the segment before it:
    where a segment's last point and the next segment's first are further apart than
    :data:`MERGE_DISTANCE`, the arc about the pitch point of the joint, within that segment's
    tolerance (mm), its ends left out."""
    count = len(program.segments)
    after = np.roll(np.arange(count), -1)  # the segment each joint starts
    joint = program.table.start[after]
    m_right = program.evaluate_local(after, np.zeros(count))
    last = np.flatnonzero(np.append(index[1:] != index[:-1], True))  # each segment's last point
    start = xy[last]
    end = evaluator(joint, m_right).xy
    corner = np.flatnonzero(np.hypot(*(end - start).T) > MERGE_DISTANCE)
    if not corner.size:
        return theta, xy
    centre = cam.pitch(joint[corner], m_right[:, corner]).xy
    sweep = signed_angle(start[corner] - centre, end[corner] - centre)
    arcs = [arc_points(centre[k], start[i], float(sweep[k]), float(tolerances[i]))[1:-1]
            for k, i in enumerate(corner)]
    sizes = [len(arc) for arc in arcs]
    where = np.repeat(last[corner] + 1, sizes)
    return (np.insert(theta, where, np.repeat(joint[corner], sizes)),
            np.insert(xy, where, np.concatenate(arcs), axis=0))


def outer_wall(cam: DiscCam, theta: Array, m: Array) -> CurvePoints:
    """The pitch curve moved the follower's radius outward along its normal: the outer wall of
    a groove (its radius of curvature ρ_p + radius, running backwards where a concave ρ_p is
    smaller in size than the radius)."""
    return offset_inward(cam.pitch(theta, m), cam.sigma, -cam.follower.radius)


def _keep_test(cam: DiscCam, pitch: Sampled, dense: DenseCurves, slack: float) -> KeepTest:
    """Where the follower never enters: outside the sweep of its circle, or below every face."""
    if dense.lines is not None:
        return below_face_lines(dense.lines.normal, dense.lines.h, slack)
    return outside_circle_sweep(pitch.xy, cam.follower.radius, slack)


def cut_cam(cam: DiscCam, program: MotionProgram, dense: DenseCurves, pitch: Sampled,
            working: Sampled, tolerance: float) -> Array:
    """The cam a cutter following the design leaves (mm): the sampled *working* curve, its
    loops trimmed away (the faces of it the follower, run along the sampled *pitch* curve or
    under the face lines of *dense*, never enters), both sampled within *tolerance* (mm); its
    corners, where two branches of the envelope cross, where the exact branches cross
    (:func:`exact_crossings`), not where two of their chords do."""
    xy = trim_loops(working.xy, _keep_test(cam, pitch, dense, tolerance))
    added = np.flatnonzero(~among(xy, working.xy))
    if added.size:
        xy = xy.copy()
        xy[added] = exact_crossings(cam, program, working, xy[added])
    return xy


#: Newton steps that solve for a crossing of two branches of the envelope: from the crossing of
#: their chords (within the sampling tolerance of it) the error squares at each step.
CROSSING_STEPS = 8


def exact_crossings(cam: DiscCam, program: MotionProgram, working: Sampled,
                    points: Array) -> Array:
    """Where the exact working curve crosses itself near each of *points* (mm), crossings of
    chords of the sampled *working* curve: W(θa) = W(θb) solved by Newton's method from the
    chords' parameters, θa and θb each within its chord's span of cam angle. A point whose
    chords are not both pieces of the envelope between two cam angles (a roller's arc over a
    corner of the pitch curve), or whose solution leaves the spans, stays as it is."""
    first, second = crossings(working.xy, points)
    paired = (first >= 0) & (second >= 0)
    first, second = np.where(paired, first, 0), np.where(paired, second, 0)
    theta, count = working.theta, len(working.theta)
    spans = np.stack([np.stack((theta[c], theta[(c + 1) % count]), axis=-1)
                      for c in (first, second)], axis=1)  # (K, 2 chords, 2 ends)
    spans[..., 1] = np.where(spans[..., 1] < spans[..., 0], spans[..., 1] + 2 * math.pi,
                             spans[..., 1])  # the chord across θ = 0
    width = spans[..., 1] - spans[..., 0]
    ends = np.stack([working.xy[c] for c in (first, second)], axis=1)
    following = np.stack([working.xy[(c + 1) % count] for c in (first, second)], axis=1)
    # the parameters where the chords' crossing falls, as shares of each chord
    share = np.clip(np.sum((points[:, None] - ends) * (following - ends), axis=-1)
                    / np.maximum(np.sum((following - ends) ** 2, axis=-1), 1e-300), 0.0, 1.0)
    t = spans[..., 0] + share * width
    for _ in range(CROSSING_STEPS):
        curve = cam.working(t.ravel(), program.evaluate(t.ravel()))
        w = curve.xy.reshape(-1, 2, 2)
        dw = (curve.tangent * curve.speed[:, None]).reshape(-1, 2, 2)
        gap = w[:, 0] - w[:, 1]
        # the 2 × 2 system [dW(θa), −dW(θb)] · step = gap by Cramer's rule, which (unlike a
        # batched solve) leaves a singular one (parallel tangents) to itself: no step there
        a, b, c, d = dw[:, 0, 0], -dw[:, 1, 0], dw[:, 0, 1], -dw[:, 1, 1]
        with np.errstate(divide="ignore", invalid="ignore"):
            det = a * d - b * c
            step = np.stack(((d * gap[:, 0] - b * gap[:, 1]) / det,
                             (a * gap[:, 1] - c * gap[:, 0]) / det), axis=-1)
        t = t - np.where(np.isfinite(step), step, 0.0)
    found = cam.working(t.ravel(), program.evaluate(t.ravel())).xy.reshape(-1, 2, 2)
    slack = 1e-9 * np.maximum(width, 1e-12)
    good = (paired & np.all(width > 0.0, axis=1)
            & np.all((t >= spans[..., 0] - slack) & (t <= spans[..., 1] + slack), axis=1)
            & np.all(np.isfinite(found), axis=(1, 2))
            & (np.hypot(*(found[:, 0] - found[:, 1]).T) <= 1e-9 * (1.0 + np.abs(found).max())))
    return np.where(good[:, None], 0.5 * (found[:, 0] + found[:, 1]), points)


def folds(cam: DiscCam, dense: DenseCurves) -> Mask:
    """Where the envelope folds over: a convex pitch radius below the roller or mushroom radius,
    or a flat face's radius ρ = Rb + s + s″ (and its oscillating counterpart) at or below 0."""
    if cam.follower.flat:
        return ~(dense.working.radius > 0.0)
    radius = dense.pitch.radius
    return (radius > 0.0) & (radius < cam.follower.radius)


def lift_check(cam: DiscCam, program: MotionProgram, profile: Profile,
               step: float = VERIFY_STEP) -> LiftCheck:
    """Run the follower over *profile* and compare its lift with *program*'s."""
    theta = cycle_angles(step)
    position = simulate(profile, cam.follower, theta, cam.sigma)
    error = position - cam.rest - program.evaluate(theta)[0]
    scale = cam.follower.arm_length if cam.follower.oscillating else 1.0
    return LiftCheck(theta, error, error * scale)


def disc_cam(design: Design, clearance: float = 0.0) -> DiscCam:
    """The exact evaluators of a disc-cam design, the follower's radius grown by *clearance*
    (mm: a groove's half clearance, so that the working curve is the groove's inner wall)."""
    base = design.cam.base_radius
    assert base is not None, "disc cams have a base radius (design rules)"
    follower = FollowerGeometry.from_design(design)
    if clearance:
        follower = replace(follower, radius=follower.radius + clearance)
    return DiscCam(follower, base, design.cam.sigma)


#: The smallest factor by which a steep pressure angle may shrink the sampling tolerance.
MIN_TOLERANCE_FACTOR = 0.01

#: The share of ``manufacturing.tolerance`` (times the pressure angle's factor) a plate cam's
#: sampled curves take. Its outline is written as arcs that hold the chords between these points
#: within twice this (:data:`camfab.geometry.plate.ARC_FACTOR`), so within three times it of the
#: exact curve, and a kerf's or cutter's offset and the reading back of the part a beam leaves
#: take a quarter of it each (:data:`camfab.geometry.plate.OFFSET_SHARE`): in all 15/16 of the
#: tolerance, the rest left to the rounding of the files.
PLATE_SAMPLING_SHARE = 0.25


def segment_tolerances(cam: DiscCam, dense: DenseCurves, tolerance: float,
                       count: int) -> Array:
    """The chord tolerance of each segment (mm): a plate's sampling share of *tolerance*
    (:data:`PLATE_SAMPLING_SHARE`), scaled so the follower's lift error stays within that share.

    A profile that strays δ along its normal moves a trace point δ/cos φ along its path. An
    oscillating flat face turns by δ/l about its pivot (l: the contact's distance along the face),
    which moves the arm's trace point δ·L/l.
    """
    factor = np.cos(dense.pressure_angle)
    fol = cam.follower
    if fol.flat and fol.oscillating and dense.face_contact is not None:
        factor = np.minimum(1.0, np.abs(dense.face_contact) / fol.arm_length)
    worst = np.ones(count)
    np.minimum.at(worst, dense.segment, factor)
    # a floor keeps the point count finite near φ = 90° (a follower jammed in its guide, which
    # the pressure-angle check reports); up to φ = 89.4° the lift error stays within the share
    return tolerance * PLATE_SAMPLING_SHARE * np.maximum(worst, MIN_TOLERANCE_FACTOR)


def disc_geometry(design: Design, clearance: float = 0.0,
                  exact: Profile | None = None) -> DiscGeometry:
    """Build the geometry of a disc-cam design (the follower's radius grown by *clearance*, mm,
    see :func:`disc_cam`); *exact* is the cam's exact outline when it is drawn from its shape."""
    return plate_geometry(disc_cam(design, clearance), design.program,
                          design.manufacturing.tolerance, exact)


def plate_geometry(cam: DiscCam, program: MotionProgram, tolerance: float,
                   exact: Profile | None = None) -> DiscGeometry:
    """The geometry of the plate cam *cam* driving its follower through *program*, its curves
    sampled within *tolerance* (mm); *exact* is the cam's exact outline when it is drawn from
    its shape (the follower run over it checks the motion)."""
    dense = dense_curves(cam, program)
    tolerances = segment_tolerances(cam, dense, tolerance, len(program.segments))
    tolerance = float(tolerances.min())
    pitch = sample_closed(cam, program, "pitch", tolerances)
    working = sample_closed(cam, program, "working", tolerances)
    folded = folds(cam, dense)
    crossing = not is_simple(working.xy)
    xy = working.xy
    cut = np.zeros(len(working.xy), dtype=bool)
    if folded.any() or crossing:
        xy = cut_cam(cam, program, dense, pitch, working, tolerance)
        cut = cut_away(working.xy, xy, 2 * tolerance)
    profile = Profile.from_points(xy).ccw() if exact is None else exact
    return DiscGeometry(cam, tolerance, dense, pitch, working, profile, folded, crossing,
                        cut, lift_check(cam, program, profile), exact is not None)
