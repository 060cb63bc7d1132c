"""Cams defined by their shape (THEORY §D): the circular-arc cam and the tangent cam.

Both are symmetric: a base circle of radius r1, a nose circle of radius rn whose centre Q lies at
OQ = r1 + h − rn from the cam centre O (h: the lift), and two flanks joining them, each touching
both circles. The flanks of a circular-arc cam are convex arcs of radius R about a centre P on
the far side of O (OP = R − r1); those of a tangent cam are straight lines. A top dwell, when
given, is an arc of radius r1 + h about O between the two halves of the nose.

The cam is drawn at θ = 0 (SPEC §2): the follower, along +Y, is about to leave the base circle
at (0, r1). A counter-clockwise cam meets the rise flank first and has the nose centre of the
rise at the polar angle 90° − α (α: the angle of ascent); the return half mirrors the rise half
about the polar angle 90° − α − (top dwell)/2. A clockwise cam is the mirror image in the Y axis.
Lengths are millimetres and angles radians.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Literal

import numpy as np

from camfab.arrays import Array
from camfab.curves.plane import rotate
from camfab.curves.profile import Profile

ShapeKind = Literal["circular-arc", "tangent"]

#: The largest sweep (rad) of one arc edge in an outline: a longer arc (the base circle of a
#: cam with a short angle of action) is written as two, so no edge is nearly a full circle.
MAX_ARC_SWEEP = math.pi


class ShapeError(ValueError):
    """Dimensions that give no cam of the kind: *field* is the ``cam`` key to change."""

    def __init__(self, field: str, problem: str) -> None:
        self.field = field
        self.problem = problem
        super().__init__(f"cam.{field}: {problem}")


@dataclass(frozen=True)
class Piece:
    """One edge of a cam outline (mm), run counter-clockwise from *start* to *end*: an arc of
    *radius* about *centre*, or a line when *centre* is None. *label* names it in reports
    (``flank``, ``nose``, ``base circle``, ``top circle``)."""

    label: str
    start: Array
    end: Array
    centre: Array | None = None
    radius: float = 0.0

    @property
    def sweep(self) -> float:
        """The arc's counter-clockwise sweep (rad, in (0, 2π)); 0 for a line."""
        if self.centre is None:
            return 0.0
        a = self.start - self.centre
        b = self.end - self.centre
        turn = math.atan2(a[0] * b[1] - a[1] * b[0], a[0] * b[0] + a[1] * b[1])
        return turn % (2.0 * math.pi) or 2.0 * math.pi

    def normal_at(self, point: Array) -> Array:
        """The outward unit normal (the side away from the cam) at *point* on the piece."""
        if self.centre is None:
            d = self.end - self.start
            return np.array([d[1], -d[0]]) / math.hypot(d[0], d[1])
        rel = point - self.centre
        return rel / math.hypot(rel[0], rel[1])

    def mirrored(self, angle: float) -> Piece:
        """The piece reflected in the line through O at polar *angle* (rad), run
        counter-clockwise again (its ends swap)."""
        def reflect(p: Array) -> Array:
            c, s = math.cos(2.0 * angle), math.sin(2.0 * angle)
            return np.array([c * p[0] + s * p[1], s * p[0] - c * p[1]])

        centre = None if self.centre is None else reflect(self.centre)
        return replace(self, start=reflect(self.end), end=reflect(self.start), centre=centre)


def _polar(radius: float, angle: float) -> Array:
    return np.array([radius * math.cos(angle), radius * math.sin(angle)])


@dataclass(frozen=True)
class ShapedCam:
    """A circular-arc or tangent cam from its principal dimensions (mm, rad).

    Build one with :meth:`circular_arc` or :meth:`tangent`, which derive the dimension not given
    and raise :class:`ShapeError` for dimensions no such cam has.
    """

    kind: ShapeKind
    base_radius: float
    lift: float
    nose_radius: float
    lift_angle: float
    top_dwell: float = 0.0

    @classmethod
    def circular_arc(cls, base_radius: float, lift: float, lift_angle: float,
                     nose_radius: float | None = None, flank_angle: float | None = None,
                     top_dwell: float = 0.0) -> ShapedCam:
        """A circular-arc cam from its nose radius, or from *flank_angle*: the cam angle over
        which a flat follower rides the flank (the rest of the ascent it rides the nose).

        From the triangle O P Q (angles π − α at O, φ at P, α − φ at Q) and the sine rule,
        PQ = h sin α / (sin φ + sin(α − φ) − sin α) and rn = r1 − PQ (1 − sin(α − φ)/sin α).
        """
        r1, h, alpha = base_radius, lift, lift_angle
        _check_angles(alpha, top_dwell, math.pi, "below 180°")
        if nose_radius is None:
            if flank_angle is None:
                raise ShapeError("nose_radius", "required (or flank_angle)")
            if not 0.0 < flank_angle < alpha:
                raise ShapeError("flank_angle", "must lie between 0 and the lift angle "
                                 f"({math.degrees(alpha):.6g}°)")
            pq = h * math.sin(alpha) / (math.sin(flank_angle) + math.sin(alpha - flank_angle)
                                        - math.sin(alpha))
            nose_radius = r1 - pq * (1.0 - math.sin(alpha - flank_angle) / math.sin(alpha))
            if not 0.0 < nose_radius < r1:
                raise ShapeError("flank_angle", f"gives a nose radius of {nose_radius:.6g} mm, "
                                 f"not between 0 and the base radius ({r1:.6g} mm)")
        elif flank_angle is not None:
            raise ShapeError("flank_angle", "give either nose_radius or flank_angle, not both")
        cam = cls("circular-arc", r1, h, nose_radius, alpha, top_dwell)
        cam._check_nose()
        c, oq = r1 - nose_radius, cam.nose_distance
        if not c > oq * math.cos(alpha):
            raise ShapeError(
                "nose_radius", "leaves no convex circular-arc flank: need base_radius − "
                f"nose_radius > (base_radius + lift − nose_radius)·cos(lift_angle), here "
                f"{c:.6g} ≤ {oq * math.cos(alpha):.6g} mm; use a smaller nose radius, a smaller "
                "lift or a larger lift angle")
        return cam

    @classmethod
    def tangent(cls, base_radius: float, lift: float, lift_angle: float | None = None,
                nose_radius: float | None = None, top_dwell: float = 0.0) -> ShapedCam:
        """A tangent cam from its lift angle (rn = (r1 − (r1 + h) cos α)/(1 − cos α)) or from
        its nose radius (cos α = (r1 − rn)/(r1 + h − rn))."""
        r1, h = base_radius, lift
        if lift_angle is None:
            if nose_radius is None:
                raise ShapeError("lift_angle", "required (or nose_radius)")
            if not 0.0 < nose_radius < r1:
                raise ShapeError("nose_radius", f"must be smaller than the base radius "
                                 f"({r1:.6g} mm)")
            lift_angle = math.acos((r1 - nose_radius) / (r1 + h - nose_radius))
        elif nose_radius is not None:
            raise ShapeError("nose_radius", "give either lift_angle or nose_radius, not both")
        else:
            # for the tiny angles of a tiny lift cos α rounds to 1: there 1 − cos α is taken
            # as 2 sin²(α/2)
            tiny = h / (r1 + h) < 1e-8
            least = (2.0 * math.asin(math.sqrt(h / (2.0 * (r1 + h)))) if tiny
                     else math.acos(r1 / (r1 + h)))
            if not least < lift_angle < math.pi / 2:
                raise ShapeError(
                    "lift_angle", f"must lie between {math.degrees(least):.6g}° (a nose of radius "
                    "0) and 90° (flanks parallel) for this base radius and lift")
            cos_a = math.cos(lift_angle)
            if tiny:
                nose_radius = r1 - h * cos_a / (2.0 * math.sin(lift_angle / 2.0) ** 2)
            else:
                nose_radius = (r1 - (r1 + h) * cos_a) / (1.0 - cos_a)
        _check_angles(lift_angle, top_dwell, math.pi / 2, "below 90°")
        cam = cls("tangent", r1, h, nose_radius, lift_angle, top_dwell)
        cam._check_nose()
        return cam

    def _check_nose(self) -> None:
        if not 0.0 < self.nose_radius < self.base_radius:
            raise ShapeError("nose_radius", f"must be smaller than the base radius "
                             f"({self.base_radius:.6g} mm)")

    @property
    def nose_distance(self) -> float:
        """OQ: cam centre to nose centre (mm)."""
        return self.base_radius + self.lift - self.nose_radius

    @property
    def flank_centre_distance(self) -> float | None:
        """OP = (OQ² − c²)/(2(c − OQ cos α)), c = r1 − rn: cam centre to the flank arc's centre
        (mm; None for a tangent cam)."""
        if self.kind != "circular-arc":
            return None
        oq, c = self.nose_distance, self.base_radius - self.nose_radius
        return (oq * oq - c * c) / (2.0 * (c - oq * math.cos(self.lift_angle)))

    @property
    def flank_radius(self) -> float | None:
        """R = r1 + OP: the flank arcs' radius (mm; None for a tangent cam)."""
        op = self.flank_centre_distance
        return None if op is None else self.base_radius + op

    @property
    def base_dwell(self) -> float:
        """The cam angle (rad) the follower rests on the base circle."""
        return 2.0 * math.pi - 2.0 * self.lift_angle - self.top_dwell

    def rise_half(self) -> list[Piece]:
        """The nose and flank met during the rise, counter-clockwise (ccw cam at θ = 0)."""
        r1, rn, alpha = self.base_radius, self.nose_radius, self.lift_angle
        q = _polar(self.nose_distance, math.pi / 2 - alpha)
        apex = _polar(self.nose_distance + rn, math.pi / 2 - alpha)
        foot = np.array([0.0, r1])
        op = self.flank_centre_distance
        if op is None:  # the flank is the line y = r1, touching the nose at its top
            joint = q + np.array([0.0, rn])
            flank = Piece("flank", joint, foot)
        else:
            p = np.array([0.0, -op])
            towards = (q - p) / math.hypot(*(q - p))
            joint = q + rn * towards
            flank = Piece("flank", joint, foot, p, r1 + op)
        return [Piece("nose", apex, joint, q, rn), flank]

    def pieces(self) -> list[Piece]:
        """The whole outline counter-clockwise from the foot of the return flank (ccw cam at
        θ = 0): return flank, nose, top circle (with a top dwell), nose, rise flank, base
        circle — arcs longer than :data:`MAX_ARC_SWEEP` in two."""
        rise = self.rise_half()
        axis = math.pi / 2 - self.lift_angle - self.top_dwell / 2
        back = [piece.mirrored(axis) for piece in reversed(rise)]
        origin = np.zeros(2)
        top: list[Piece] = []
        if self.top_dwell > 0.0:
            top = [Piece("top circle", back[-1].end, rise[0].start, origin,
                         self.base_radius + self.lift)]
        base = Piece("base circle", rise[-1].end, back[0].start, origin, self.base_radius)
        return [piece for whole in [*back, *top, *rise, base] for piece in _split(whole)]

    def profile(self, sigma: int = 1) -> Profile:
        """The exact outline as a contour of lines and arcs (counter-clockwise, mm), drawn at
        θ = 0 for a cam turning counter-clockwise (*sigma* = 1) or clockwise (−1)."""
        pieces = self.pieces()
        vertices = np.array([piece.start for piece in pieces])
        bulges = np.array([math.tan(piece.sweep / 4.0) for piece in pieces])
        if sigma > 0:
            return Profile(vertices, bulges)
        return Profile(vertices * np.array([-1.0, 1.0]), -bulges).ccw()


def _check_angles(lift_angle: float, top_dwell: float, most: float, wording: str) -> None:
    if not 0.0 < lift_angle < most:
        raise ShapeError("lift_angle", f"must be {wording}")
    if 2.0 * lift_angle + top_dwell >= 2.0 * math.pi:
        raise ShapeError("top_dwell", f"leaves no base circle: twice the lift angle plus the top "
                         f"dwell is {math.degrees(2 * lift_angle + top_dwell):.6g}° (below 360°)")


def _split(piece: Piece) -> list[Piece]:
    """An arc longer than :data:`MAX_ARC_SWEEP` as two halves; other pieces as they are."""
    if piece.centre is None or piece.sweep <= MAX_ARC_SWEEP:
        return [piece]
    middle = piece.centre + rotate(piece.start - piece.centre, piece.sweep / 2.0)
    return [replace(piece, end=middle), replace(piece, start=middle)]
