"""The follower's motion on a convex outline of arcs and lines, piece by piece in closed form.

THEORY §D's one rule: while a radial translating follower touches a circular arc of the cam
(centre c at distance d and polar angle γ in the cam frame, radius Ra), turning the cam by θ
(counter-clockwise) puts the centre at ψ = γ + θ, and

    flat face:          y = d sin ψ + Ra
    circle of radius r: y = d sin ψ + √((Ra + r)² − d² cos² ψ)   (knife: r = 0; roller, mushroom)

while a circle touching a line of the cam (outward normal at polar angle β, distance p from O)
is at y = (p + r)/sin(β + θ). Each is differentiated here in closed form to the third
derivative, so the motion it gives is exact. The follower passes from one piece to the next
where the outline's common normal at their joint points at it: a flat face when the normal is
+Y, a circle when its centre, r along the normal from the joint, lies on +Y. A flat face never
rides a line (it meets the whole line at one instant), so a line gives it no segment.

This serves cams drawn from their shape (:mod:`camfab.curves.shaped`): a convex outline,
tangent-continuous, drawn for a counter-clockwise cam at θ = 0 with the follower about to
leave the base circle. A clockwise cam is its mirror image and moves the follower the same way.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from camfab.arrays import Array
from camfab.curves.shaped import Piece
from camfab.motion.law import Law, as_unit_array
from camfab.motion.laws import DWELL
from camfab.motion.program import TWO_PI, MotionProgram, ProgramSegment

#: Samples per segment behind a contact law's peak coefficients; the peaks of these motions lie
#: at the ends of their pieces (included) or are smooth maxima that this resolves to ~1e-7.
PEAK_SAMPLES = 4097

#: A piece the follower rides over a smaller cam angle than this (rad) gives no segment: a line
#: under a flat face, or a joint's rounding.
MIN_SPAN = 1e-12


@dataclass(frozen=True)
class Contact:
    """The follower (a flat face, or a circle of *radius* about the trace point) on *piece*."""

    piece: Piece
    radius: float
    flat: bool

    def height(self, theta: Array) -> Array:
        """y, y′, y″, y‴ of the trace point (mm, per radian of cam angle) at cam angles
        *theta* (rad): shape (4, N)."""
        piece = self.piece
        if piece.centre is None:
            normal = piece.normal_at(piece.start)
            beta = math.atan2(normal[1], normal[0])
            return (float(normal @ piece.start) + self.radius) * _cosecant(beta + theta)
        d = math.hypot(*piece.centre)
        psi = math.atan2(piece.centre[1], piece.centre[0]) + theta
        sin, cos = np.sin(psi), np.cos(psi)
        out = np.stack((d * sin, d * cos, -d * sin, -d * cos))
        if self.flat:
            out[0] += piece.radius
            return out
        reach = piece.radius + self.radius
        sin2, cos2 = np.sin(2 * psi), np.cos(2 * psi)
        q = (reach * reach - d * d * cos * cos, d * d * sin2, 2 * d * d * cos2,
             -4 * d * d * sin2)
        return out + _square_root(q)

    def joint_angle(self, point: Array, after: Piece) -> float:
        """The cam angle (rad, in [0, 2π)) at which the follower passes *point*, the joint of
        this piece with the piece *after* it. The outline's normal there is both pieces'; it is
        taken from the flatter one (a line, or the larger arc), whose direction from its centre
        rounding moves least."""
        flatter = max((self.piece, after),
                      key=lambda p: math.inf if p.centre is None else p.radius)
        normal = flatter.normal_at(point)
        at = normal if self.flat else point + self.radius * normal
        return (math.pi / 2 - math.atan2(at[1], at[0])) % TWO_PI


#: A piece over which the follower moves less than this fraction of its rest height is a dwell:
#: its lift is rounding (an arc about the cam centre, or a cam with a lift of nanometres).
FLAT_PIECE = 1e-12

#: How far (rad) a joint's computed angle may fall before the previous joint's and still be
#: taken as the same angle (both come from the same point of the outline).
_UNWRAP = 1e-9


def _square_root(q: tuple[Array, Array, Array, Array]) -> Array:
    """g = √q and its derivatives from q's: 2g g′ = q′, 2g g″ = q″ − 2g′², 2g g‴ = q‴ − 6g′g″."""
    g = np.sqrt(q[0])
    g1 = q[1] / (2 * g)
    g2 = (q[2] - 2 * g1 * g1) / (2 * g)
    g3 = (q[3] - 6 * g1 * g2) / (2 * g)
    return np.stack((g, g1, g2, g3))


def _cosecant(angle: Array) -> Array:
    """csc and its derivatives: −csc cot, csc(cot² + csc²), −csc cot(cot² + 5 csc²)."""
    csc = 1.0 / np.sin(angle)
    cot = np.cos(angle) * csc
    return np.stack((csc, -csc * cot, csc * (cot * cot + csc * csc),
                     -csc * cot * (cot * cot + 5 * csc * csc)))


class ContactLaw(Law):
    """The normalised motion of one contact: f(u) = (y(θ₀ + uβ) − y(θ₀))/Δ over the segment's
    span β and lift Δ = y(θ₀ + β) − y(θ₀)."""

    def __init__(self, contact: Contact, start: float, span: float) -> None:
        self.contact = contact
        self.name = contact.piece.label
        self.start = start
        self.span = span
        ends = contact.height(np.array([start, start + span]))[0]
        self.y0 = float(ends[0])
        self.delta = float(ends[1] - ends[0])

    def evaluate(self, u: ArrayLike) -> Array:
        y = self.contact.height(self.start + self.span * as_unit_array(u))
        y[0] -= self.y0
        return y * (self.span ** np.arange(4) / self.delta)[:, None]

    def _peaks(self) -> tuple[float, float, float]:
        values = np.abs(self.evaluate(np.linspace(0.0, 1.0, PEAK_SAMPLES)))
        return (float(values[1].max()), float(values[2].max()), float(values[3].max()))


def contact_program(pieces: Sequence[Piece], radius: float, flat: bool) -> MotionProgram:
    """The follower's motion program over the outline *pieces* (counter-clockwise, starting
    anywhere; the follower leaves the piece ending at +Y at θ = 0): one segment per piece it
    rides, a dwell for arcs about the cam centre, a rise or return for the others.

    *radius* is the follower's circle (roller or mushroom; 0 for a knife) unless *flat*.
    Lifts are measured from the follower's height at θ = 0.
    """
    # as the cam turns counter-clockwise the follower meets the pieces clockwise
    order = list(reversed(pieces))
    first = next(i for i, p in enumerate(order) if np.allclose(p.end, [0.0, np.hypot(*p.end)]))
    order = order[first:] + order[:first]
    contacts = [Contact(piece, radius, flat) for piece in order]
    starts = [0.0]
    for contact, after in zip(contacts[:-1], order[1:], strict=True):
        # the next joint, at or after the last one (a joint a rounding error before it is at it)
        joint = contact.joint_angle(contact.piece.start, after)
        ahead = (joint - starts[-1] + _UNWRAP) % TWO_PI
        starts.append(min(starts[-1] + max(ahead - _UNWRAP, 0.0), TWO_PI))
    ends = [*starts[1:], TWO_PI]
    # at rest on the base circle, the last piece before the rise (an arc about the centre)
    rest = float(contacts[-1].height(np.zeros(1))[0, 0])
    segments: list[ProgramSegment] = []
    for contact, start, end in zip(contacts, starts, ends, strict=True):
        span = end - start
        if span < MIN_SPAN:
            continue
        law = ContactLaw(contact, start, span)
        s0 = law.y0 - rest
        centred = contact.piece.centre is not None and np.hypot(*contact.piece.centre) == 0.0
        if centred or abs(law.delta) <= FLAT_PIECE * rest:
            segments.append(ProgramSegment(len(segments), "dwell", "dwell", DWELL, start, span,
                                           s0, 0.0))
            continue
        kind = "rise" if law.delta > 0.0 else "return"
        segments.append(ProgramSegment(len(segments), kind, contact.piece.label, law, start,
                                       span, s0, law.delta))
    return MotionProgram(_settled(segments))


def _settled(segments: list[ProgramSegment]) -> list[ProgramSegment]:
    """Consecutive dwells (an arc about the centre drawn in two) as one, and dwell levels as
    exact as the lifts around them: the base circle at 0, a later level where the segment
    before it ends (rounding of 1e-15 mm, not a step)."""
    out: list[ProgramSegment] = []
    for seg in segments:
        start, span = seg.start, seg.span
        if seg.kind == "dwell" and out and out[-1].kind == "dwell":
            start, span = out[-1].start, seg.end - out[-1].start
            out.pop()
        if seg.kind == "dwell":
            level = 0.0 if not out or abs(seg.s0) < 1e-9 else out[-1].s1
            seg = ProgramSegment(seg.index, "dwell", "dwell", DWELL, start, span, level, 0.0)
        out.append(seg)
    return [ProgramSegment(i, s.kind, s.law_name, s.law, s.start, s.span, s.s0, s.delta)
            for i, s in enumerate(out)]
