"""Exact curve values at a set of parameters, and the plane helpers every curve module uses.

Conventions (SPEC §2): points are (N, 2) arrays in millimetres; θ is the cam angle in radians in
the direction of rotation, σ = +1 for a counter-clockwise cam and −1 for clockwise; a point fixed
in the frame appears on the cam at ``Rot(−σθ)·P``. Derivatives are per radian of cam angle. A
radius of curvature is positive where the curve is convex (bends toward the cam centre) and
infinite where it is straight.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from camfab.arrays import Array


def rotate(points: Array, angle: Array | float) -> Array:
    """Rotate (N, 2) *points* counter-clockwise by *angle* (rad, scalar or per point)."""
    c, s = np.cos(angle), np.sin(angle)
    x, y = points[..., 0], points[..., 1]
    return np.stack((c * x - s * y, s * x + c * y), axis=-1)


def perp(vectors: Array) -> Array:
    """Each vector turned 90° counter-clockwise (the left normal): (x, y) -> (−y, x)."""
    return np.stack((-vectors[..., 1], vectors[..., 0]), axis=-1)


def cross(a: Array, b: Array) -> Array:
    """The z component of a × b for (N, 2) vectors."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def dot(a: Array, b: Array) -> Array:
    """Row-wise dot product of (N, 2) vectors."""
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1]


def unit(vectors: Array) -> Array:
    """Vectors scaled to length 1 (zero vectors stay zero)."""
    length = np.hypot(vectors[..., 0], vectors[..., 1])
    return vectors / np.where(length > 0.0, length, 1.0)[..., None]


def signed_angle(u: Array, v: Array) -> Array:
    """The angle (rad) from *u* to *v*, counter-clockwise positive, in (−π, π]."""
    return np.arctan2(cross(u, v), dot(u, v))


@dataclass(frozen=True)
class CurvePoints:
    """A curve's exact values at N parameters, in the cam frame.

    Attributes
    ----------
    xy
        (N, 2) points, mm.
    tangent
        (N, 2) unit tangents in the direction of increasing θ (zero where the curve stops).
    speed
        (N,) |dC/dθ|, mm/rad.
    radius
        (N,) signed radius of curvature, mm (convex positive, ±inf straight).
    """

    xy: Array
    tangent: Array
    speed: Array
    radius: Array


#: A curve is straight where C′ and C″ are parallel to within this sine of the angle between
#: them: the rounding of a straight piece's cross product (a tangent cam's flank) is ~1e-16,
#: while a bend of any radius a cam has turns them far more.
STRAIGHT_SINE = 1e-10


def curve_from_frame(theta: Array, sigma: int, f: Array, df: Array, ddf: Array) -> CurvePoints:
    """The cam-frame curve ``C = Rot(−σθ)·F`` of a frame point F(θ) with derivatives F′, F″.

    With J the 90° turn, ``C′ = Rot(−σθ)(F′ − σJF)`` and ``C″ = Rot(−σθ)(F″ − 2σJF′ − F)``; the
    curvature is computed from these in the frame (rotation does not change it) and made convex
    positive: the cam-frame curve of a ccw cam runs clockwise (THEORY §B, generic definitions).
    """
    d1, speed, radius = _frame_radius(sigma, f, df, ddf)
    xy = rotate(f, -sigma * theta)
    tangent = rotate(unit(d1), -sigma * theta)
    return CurvePoints(xy, tangent, speed, radius)


def _frame_radius(sigma: int, f: Array, df: Array, ddf: Array) -> tuple[Array, Array, Array]:
    """C′ (in the frame), |C′| and the signed radius of curvature (see :func:`curve_from_frame`)."""
    d1x, d1y, d2x, d2y = frame_derivatives(sigma, f[:, 0], f[:, 1], df[:, 0], df[:, 1],
                                           ddf[:, 0], ddf[:, 1])
    speed, radius = radius_from(sigma, d1x, d1y, d2x, d2y)
    return np.stack((d1x, d1y), axis=-1), speed, radius


def frame_derivatives(sigma: int, fx: Array | float, fy: Array | float, dfx: Array | float,
                      dfy: Array | float, ddfx: Array | float, ddfy: Array | float
                      ) -> tuple[Array, Array, Array, Array]:
    """C′ = F′ − σJF and C″ = F″ − 2σJF′ − F in the frame (see :func:`curve_from_frame`) by
    component, (x′, y′, x″, y″) in mm/rad and mm/rad², from the components of a frame point F
    (mm) and of F′ and F″ (arrays, or floats for those that stay the same)."""
    twice = 2 * sigma
    return (dfx - sigma * -fy, dfy - sigma * fx, (ddfx - twice * -dfy) - fx,
            (ddfy - twice * dfx) - fy)


def radius_from(sigma: int, d1x: Array, d1y: Array, d2x: Array, d2y: Array
                ) -> tuple[Array, Array]:
    """|C′| (mm/rad) and the signed radius of curvature (mm) of the cam-frame curve whose C′ and
    C″, in the frame, have the components *d1x*, *d1y* and *d2x*, *d2y* (mm/rad, mm/rad²; see
    :func:`curve_from_frame`)."""
    speed = np.hypot(d1x, d1y)
    bend = d1x * d2y - d1y * d2x  # cross(C′, C″)
    straight = np.abs(bend) <= STRAIGHT_SINE * speed * np.hypot(d2x, d2y)
    with np.errstate(divide="ignore", invalid="ignore"):
        radius = np.where(straight, np.inf, -sigma * speed**3 / bend)
    return speed, radius


def offset_inward(curve: CurvePoints, sigma: int, distance: float) -> CurvePoints:
    """The curve moved *distance* (mm) along its inward normal (toward the cam material).

    The inward normal of the cam-frame curve is ``−σ·perp(T)``; the offset's radius is
    ``ρ − distance`` (a convex radius shrinks, a concave one grows in size), and where that
    changes sign (ρ < distance on a convex part) the offset runs backwards: the swallowtail of an
    undercut cam.
    """
    if distance == 0.0:
        return curve
    xy = curve.xy - sigma * distance * perp(curve.tangent)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(np.isinf(curve.radius), 1.0, (curve.radius - distance) / curve.radius)
    return CurvePoints(xy, curve.tangent * np.sign(ratio)[:, None], curve.speed * np.abs(ratio),
                       curve.radius - distance)
