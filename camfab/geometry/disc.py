"""Disc cams: exact pitch and working curves, pressure angle and face contact at any θ.

Every evaluator takes the cam angles θ (N,) and the motion at them, ``m = (s, s′, s″, s‴)`` as a
(4, N) array (mm or rad of swing, per radian of cam angle), and returns exact values: closed forms
of THEORY §B in the conventions of SPEC §2, no finite differences. The pitch curve is the path of
the trace point in the cam frame; the working curve (the cam profile) is the envelope of the
follower's contact shape: the pitch curve offset along its normal for knife, roller and mushroom
followers, the envelope of the face lines for flat faces.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camfab.arrays import Array
from camfab.curves.follower import FollowerGeometry
from camfab.curves.plane import (
    CurvePoints,
    curve_from_frame,
    dot,
    frame_derivatives,
    offset_inward,
    perp,
    radius_from,
    rotate,
    signed_angle,
    unit,
)


@dataclass(frozen=True)
class FaceLines:
    """The face line of a flat follower in the cam frame, as an envelope family.

    ``h`` is the line's distance from the cam centre along its outward normal at angle ``beta``;
    ``h_beta`` and ``h_beta2`` are dh/dβ and d²h/dβ², ``dbeta`` is dβ/dθ. The contact point is
    ``h·n + h_β·t`` and the radius of curvature ``h + h_ββ`` (positive: convex).
    """

    h: Array
    beta: Array
    h_beta: Array
    h_beta2: Array
    dbeta: Array

    @property
    def normal(self) -> Array:
        """(N, 2) unit outward normals of the face lines (cam frame)."""
        return np.stack((np.cos(self.beta), np.sin(self.beta)), axis=-1)

    def contact(self) -> Array:
        n = self.normal
        return self.h[:, None] * n + self.h_beta[:, None] * perp(n)

    def curve(self) -> CurvePoints:
        n = self.normal
        radius = self.h + self.h_beta2
        rate = radius * self.dbeta
        tangent = perp(n) * np.sign(rate)[:, None]
        return CurvePoints(self.contact(), tangent, np.abs(rate), radius)


@dataclass(frozen=True)
class PitchParts:
    """The trace point's direction of motion on a rise (mx, my) and the pitch curve's C′ (d1x,
    d1y, mm/rad) and C″ (d2x, d2y, mm/rad²) in the frame, of a cam turning in sense *sigma*
    (:meth:`DiscCam.pitch_parts`); a translating follower's direction is the scalar (0, 1)."""

    sigma: int
    mx: Array | float
    my: Array | float
    d1x: Array
    d1y: Array
    d2x: Array
    d2y: Array

    def pressure_angle(self) -> Array:
        """The signed angle (rad) from the direction of motion to the common normal σ·perp(C′)
        (:meth:`DiscCam.pressure_angle` for a follower that is not a flat face)."""
        sigma, mx, my = self.sigma, self.mx, self.my
        nx, ny = sigma * -self.d1y, sigma * self.d1x
        return np.arctan2(mx * ny - my * nx, mx * nx + my * ny)  # signed_angle(moving, normal)

    def radius(self) -> Array:
        """The pitch curve's signed radius of curvature (mm; :meth:`DiscCam.pitch_radius`)."""
        return radius_from(self.sigma, self.d1x, self.d1y, self.d2x, self.d2y)[1]


class DiscCam:
    """A disc cam of *base_radius* (mm) turning in sense *sigma* with *follower*."""

    def __init__(self, follower: FollowerGeometry, base_radius: float, sigma: int) -> None:
        self.follower = follower
        self.base_radius = base_radius
        self.sigma = sigma
        self.rest = follower.rest_position(base_radius)

    @property
    def prime_radius(self) -> float:
        """Rp: base radius plus the roller or mushroom radius (mm)."""
        return self.base_radius + self.follower.radius

    @property
    def pivot(self) -> Array:
        fol = self.follower
        return np.array([fol.pivot_sign * fol.pivot_distance, 0.0])

    # -- the trace point in the frame ---------------------------------------------------------

    def trace(self, m: Array) -> tuple[Array, Array, Array, Array]:
        """The trace point in the frame: F, F′, F″ and the unit direction it moves in on a rise."""
        fx, fy, dfx, dfy, ddfx, ddfy, mx, my = self._trace_parts(m)

        def points(x: Array | float, y: Array | float) -> Array:
            return np.stack(np.broadcast_arrays(x, y), axis=-1)

        return points(fx, fy), points(dfx, dfy), points(ddfx, ddfy), points(mx, my)

    def _trace_parts(self, m: Array) -> tuple[Array | float, ...]:
        """:meth:`trace` by component: (x, y) of F (mm), F′ (mm/rad), F″ (mm/rad²) and the
        direction of motion, those of a translating follower that stay the same as floats."""
        fol = self.follower
        s, v, a = m[0], m[1], m[2]
        if not fol.oscillating:  # F = (e, y₀ + s), F′ = (0, s′), F″ = (0, s″), along +Y
            return fol.offset, self.rest + s, 0.0, v, 0.0, a, 0.0, 1.0
        p, arm = fol.pivot_sign, fol.arm_length
        psi = self.rest + s
        c, sn = np.cos(psi), np.sin(psi)
        mx, my = p * sn, c  # the direction; the turn is (p·c, −sn)
        rate, square = arm * v, v * v
        return (p * (fol.pivot_distance - arm * c), arm * sn, rate * mx, rate * my,
                arm * (a * mx + square * (p * c)), arm * (a * my + square * -sn), mx, my)

    def pitch_parts(self, m: Array) -> PitchParts:
        """The trace point's direction of motion and the pitch curve's C′ and C″ at the motion
        *m*, by component (:class:`PitchParts`): what :meth:`trace` and
        :func:`~camfab.curves.plane.curve_from_frame` compute, on the components instead of
        stacked points (the same arithmetic: the same values to the bit, signed zeros too), for
        the pressure angle and the radius of curvature, which the sizing measures some hundreds
        of times a design."""
        fx, fy, dfx, dfy, ddfx, ddfy, mx, my = self._trace_parts(m)
        return PitchParts(self.sigma, mx, my,
                          *frame_derivatives(self.sigma, fx, fy, dfx, dfy, ddfx, ddfy))

    def face_lines(self, theta: Array, m: Array) -> FaceLines:
        """The flat face's line family in the cam frame (THEORY §B, flat faces)."""
        fol, sigma = self.follower, self.sigma
        s, v, a = m[0], m[1], m[2]
        if not fol.oscillating:
            h, h1, h2 = self.base_radius + s, v, a
            beta_f, b1, b2 = np.full_like(s, math.pi / 2), np.zeros_like(s), np.zeros_like(s)
        else:
            p, dist = fol.pivot_sign, fol.pivot_distance
            psi = self.rest + s
            c, sn = np.cos(psi), np.sin(psi)
            h = dist * sn - fol.face_offset
            h1 = dist * c * v
            h2 = dist * (c * a - sn * v * v)
            beta_f, b1, b2 = math.pi / 2 - p * psi, -p * v, -p * a
        dbeta = b1 - sigma
        with np.errstate(divide="ignore", invalid="ignore"):
            h_beta = h1 / dbeta
            h_beta2 = (h2 * dbeta - h1 * b2) / dbeta**3
        return FaceLines(h, beta_f - sigma * theta, h_beta, h_beta2, dbeta)

    # -- curves ---------------------------------------------------------------------------------

    def pitch(self, theta: Array, m: Array) -> CurvePoints:
        """The pitch curve: the trace point's path in the cam frame.

        For a flat face the trace point is where the face meets the stem axis (translating) or
        the arm's trace point (oscillating).
        """
        f, df, ddf, _ = self.trace(m)
        return curve_from_frame(theta, self.sigma, f, df, ddf)

    def pitch_radius(self, m: Array) -> Array:
        """The pitch curve's signed radius of curvature (mm) at the motion *m*, as
        :meth:`pitch` gives it, without the curve's points."""
        return self.pitch_parts(m).radius()

    def working(self, theta: Array, m: Array, lines: FaceLines | None = None) -> CurvePoints:
        """The working curve (cam profile): the envelope of the follower's contact shape.

        A flat face's *lines* at (θ, m) may be passed when already computed.
        """
        if self.follower.flat:
            return (lines or self.face_lines(theta, m)).curve()
        return offset_inward(self.pitch(theta, m), self.sigma, self.follower.radius)

    def pressure_angle(self, theta: Array, m: Array, lines: FaceLines | None = None) -> Array:
        """Signed pressure angle (rad): from the trace point's direction of motion to the common
        normal at contact (pointing out of the cam), counter-clockwise positive.

        For a translating roller this is ``atan((σs′ − e)/(d + s))`` (THEORY §B); for a
        translating flat face it is 0; for an oscillating flat face ``atan(f/l_c)``.
        """
        sigma, fol = self.sigma, self.follower
        if fol.flat:
            if not fol.oscillating:
                return np.zeros_like(theta)
            lines = lines or self.face_lines(theta, m)
            contact = rotate(lines.contact(), sigma * theta)
            normal = rotate(lines.normal, sigma * theta)
            moving = unit(-fol.pivot_sign * perp(contact - self.pivot))
            return signed_angle(moving, normal)
        return self.pitch_parts(m).pressure_angle()

    def face_contact(self, theta: Array, m: Array, lines: FaceLines | None = None) -> Array:
        """Where a flat face touches the cam, along the face (mm).

        Translating: from the stem axis, positive toward +X (``σs′ − e``). Oscillating: from
        the pivot's foot on the face line, along the face toward the cam centre side (l_c).
        """
        fol = self.follower
        if not fol.oscillating:
            return self.sigma * m[1] - fol.offset
        lines = lines or self.face_lines(theta, m)
        contact = rotate(lines.contact(), self.sigma * theta)
        psi = self.rest + m[0]
        along = np.stack((-fol.pivot_sign * np.cos(psi), np.sin(psi)), axis=-1)
        return dot(contact - self.pivot, along)
