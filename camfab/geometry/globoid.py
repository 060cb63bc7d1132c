"""Globoidal cams: the exact flanks of the groove a cylindrical roller on an oscillating arm
runs in (the notes' globoidal cam; docs/THEORY.md §H).

Frame: the cam axis is Z; the follower's pivot axis is parallel to Y through (C, 0, 0), C the
centre distance; the arm's angle ψ = ψ₀ + s(θ) is measured from the line of centres (toward +Z
as it grows); the roller's axis runs along the arm, a = (−cos ψ, 0, sin ψ), and its point at
distance ℓ from the pivot is Q = (C − ℓ cos ψ, 0, ℓ sin ψ), ℓ over the roller's length. The cam
turns by σθ about Z; a point fixed in the frame appears on the cam at Rot_z(−σθ)·P.

Per radian of cam angle the point Q of the roller moves relative to the cam (in the frame) by
v = (ψ′ℓ sin ψ, −σD, ψ′ℓ cos ψ) with D = C − ℓ cos ψ. A cylinder's normal at a point of contact
is perpendicular to its axis, and the contact condition asks it to be perpendicular to the
relative velocity too (the rotation of the roller adds nothing along the normal): so

    n = a × v / |a × v| = (σD sin ψ, ψ′ℓ, σD cos ψ) / √(D² + ψ′²ℓ²),   P± = Q ± r·n,

the two flanks. The pressure angle, between n and the direction Q moves in as the arm turns,
(sin ψ, 0, cos ψ), is tan α = |ψ′|ℓ / |D|. A flank is regular where J = (∂P/∂ℓ × ∂P/∂θ)·n
keeps the sign it has on the axis surface (r = 0, where it is |a × v| > 0); J is a quadratic in
r, and the smallest positive root over the flank is the largest roller radius that does not
undercut it.

Lengths are millimetres, angles radians (s, s′, s″ per radian of cam angle: the arm's swing).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camfab.arrays import Array, signed_volume


@dataclass(frozen=True)
class Globoid:
    """A globoidal cam's follower and turning (mm, rad).

    Attributes
    ----------
    centre
        C: from the cam axis to the pivot axis.
    arm
        L: from the pivot to the middle of the roller, along the arm.
    length
        The roller's length along its axis.
    radius
        The wall's distance from the roller's axis: its radius plus half the clearance.
    rest
        ψ₀: the arm's angle at zero lift, from the line of centres.
    sigma
        +1 counter-clockwise about Z, −1 clockwise.
    """

    centre: float
    arm: float
    length: float
    radius: float
    rest: float
    sigma: int = 1

    @property
    def concave(self) -> bool:
        """True when the roller lies between the pivot and the cam axis (ℓ < C): the hourglass
        globoid; else the barrel."""
        return self.arm < self.centre

    def ells(self, count: int) -> Array:
        """*count* distances ℓ (mm) along the roller, end to end."""
        half = self.length / 2.0
        return np.linspace(self.arm - half, self.arm + half, count)

    # -- the roller's axis and the contact normal, in the frame at cam angle θ -------------------

    def axis_point(self, ell: Array, psi: Array) -> Array:
        """Q (..., 3): the roller axis' point at distance *ell* from the pivot, arm at *psi*."""
        ell, psi = np.broadcast_arrays(ell, psi)
        return np.stack((self.centre - ell * np.cos(psi), np.zeros_like(ell),
                         ell * np.sin(psi)), axis=-1)

    @staticmethod
    def axis_direction(psi: Array) -> Array:
        """a (..., 3): the roller axis' unit direction, away from the pivot, arm at *psi*."""
        psi = np.asarray(psi)
        return np.stack((-np.cos(psi), np.zeros_like(psi), np.sin(psi)), axis=-1)

    def relative_velocity(self, ell: Array, psi: Array, dpsi: Array) -> Array:
        """v (..., 3): how Q moves against the cam per radian of cam angle (in the frame)."""
        ell, psi, dpsi = np.broadcast_arrays(ell, psi, dpsi)
        d = self.centre - ell * np.cos(psi)
        return np.stack((dpsi * ell * np.sin(psi), -self.sigma * d, dpsi * ell * np.cos(psi)),
                        axis=-1)

    def normal(self, ell: Array, psi: Array, dpsi: Array) -> Array:
        """n (..., 3): the unit contact normal a × v / |a × v| (in the frame)."""
        ell, psi, dpsi = np.broadcast_arrays(ell, psi, dpsi)
        d = self.centre - ell * np.cos(psi)
        n = np.stack((self.sigma * d * np.sin(psi), dpsi * ell, self.sigma * d * np.cos(psi)),
                     axis=-1)
        return n / np.hypot(d, dpsi * ell)[..., None]

    def pressure_angle(self, ell: Array, psi: Array, dpsi: Array) -> Array:
        """|α| (rad) along the contact line: tan α = |ψ′|ℓ / |C − ℓ cos ψ|."""
        ell, psi, dpsi = np.broadcast_arrays(ell, psi, dpsi)
        return np.arctan2(np.abs(dpsi) * ell, np.abs(self.centre - ell * np.cos(psi)))

    # -- the flanks on the cam ------------------------------------------------------------------

    def flank(self, theta: Array, ell: Array, motion: Array, side: int,
              radius: float | None = None) -> Array:
        """P (..., 3) on the cam: the flank on *side* (+1 along n, −1 against it) of a roller of
        *radius* (default the wall's) at cam angles *theta* (motion (4, ...): s, s′, s″, s‴ of
        the swing) and distances *ell* along the roller, broadcast together."""
        return self.across(theta, ell, motion, side, radius)

    def across(self, theta: Array, ell: Array, motion: Array, u: Array,
               radius: float | None = None) -> Array:
        """P (..., 3) on the cam: the point *u* times *radius* (default the wall's) along the
        contact normal from the roller axis' point *ell*, at cam angles *theta* (motion as for
        :meth:`flank`), all broadcast together: u = ±1 on the flanks, between them across the
        groove (its floor, its top)."""
        r = self.radius if radius is None else radius
        psi, dpsi = self.rest + motion[0], motion[1]
        p = self.axis_point(ell, psi) + (r * np.asarray(u))[..., None] * self.normal(
            ell, psi, dpsi)
        return to_cam(p, self.sigma * np.asarray(theta))


def to_cam(points: Array, turned: Array) -> Array:
    """Frame *points* (..., 3) as seen on a cam turned by *turned* (rad) about Z: Rot_z(−turned)."""
    return turned_back(points[..., 0], points[..., 1], points[..., 2], np.cos(turned),
                       np.sin(turned))


def turned_back(x: Array, y: Array, z: Array, c: Array, s: Array) -> Array:
    """The points (*x*, *y*, *z*) (mm) turned back about Z by the angle whose cosine and sine
    are *c* and *s* (:func:`to_cam`, its sine and cosine given), stacked (..., 3)."""
    return np.stack((c * x + s * y, -s * x + c * y, z), axis=-1)


def undercut_radius(globoid: Globoid, theta: Array, ell: Array, motion: Array,
                    motion_ahead: Array, motion_behind: Array, step: float) -> float:
    """The largest roller radius (mm) with which no flank folds at the cam angles *theta*
    (their motion, and the motion *step* rad ahead and behind) and distances *ell* (both
    broadcast): the least of :func:`undercut_radii`."""
    radii = undercut_radii(globoid, theta, ell, motion, motion_ahead, motion_behind, step)
    return float(np.min(radii)) if radii.size else math.inf


def undercut_radii(globoid: Globoid, theta: Array, ell: Array, motion: Array,
                   motion_ahead: Array, motion_behind: Array, step: float) -> Array:
    """The largest roller radius (mm) with which neither flank folds, at each point of the
    broadcast cam angles *theta* and distances *ell* (inf where none folds): the smallest
    positive root of J(r) = J₀ + J₁r + J₂r² over both flanks, the coefficients from the exact
    axis point and normal (central differences in θ, *step* rad, and in ℓ)."""
    j0, j1, j2 = flank_coefficients(globoid, theta, ell, motion, motion_ahead, motion_behind,
                                    step)
    return np.minimum(_smallest_positive_root(j2, j1, j0), _smallest_positive_root(j2, -j1, j0))


def flank_coefficients(globoid: Globoid, theta: Array, ell: Array, motion: Array,
                       motion_ahead: Array, motion_behind: Array,
                       step: float) -> tuple[Array, Array, Array]:
    """J₀, J₁, J₂ of the flanks' regularity J(r) = J₀ + sJ₁r + J₂r² (s the side) at the
    broadcast cam angles *theta* and distances *ell*: J = ((q_ℓ + s r n_ℓ) × (q_θ + s r n_θ))·n
    from the exact axis point q and normal n, differentiated centrally in θ (*step* rad, the
    motion given there) and in ℓ. J₀ = |a × v| > 0. The flank on side s is the axis surface
    moved s·r along n, so J(r)/J₀ = (1 − r κ₁)(1 − r κ₂) in the axis surface's principal
    curvatures toward that side."""
    g = globoid
    theta = np.asarray(theta, dtype=np.float64)

    def frames(m: Array, t: Array, e: Array) -> tuple[Array, Array]:
        q = to_cam(g.axis_point(e, g.rest + m[0]), g.sigma * t)
        n = to_cam(g.normal(e, g.rest + m[0], m[1]), g.sigma * t)
        return q, n

    h = 1e-5
    _, n0 = frames(motion, theta, ell)
    qa, na = frames(motion_ahead, theta + step, ell)
    qb, nb = frames(motion_behind, theta - step, ell)
    qe1, ne1 = frames(motion, theta, ell + h)
    qe0, ne0 = frames(motion, theta, ell - h)
    q_t, n_t = (qa - qb) / (2 * step), (na - nb) / (2 * step)
    q_l, n_l = (qe1 - qe0) / (2 * h), (ne1 - ne0) / (2 * h)
    j0 = np.einsum("...i,...i->...", np.cross(q_l, q_t), n0)
    j1 = np.einsum("...i,...i->...", np.cross(n_l, q_t) + np.cross(q_l, n_t), n0)
    j2 = np.einsum("...i,...i->...", np.cross(n_l, n_t), n0)
    return j0, j1, j2


def flank_curvature(j0: Array, j1: Array, j2: Array, side: Array | int,
                    radius: float) -> Array:
    """The sum of the principal curvatures (1/mm, convex positive as the cam's material sees
    it) of the flank on *side* of a roller of *radius* (mm), from its regularity's coefficients
    (:func:`flank_coefficients`): the flank's curvatures are the axis surface's κᵢ/(1 − rκᵢ),
    whose sum is −J′(r)/J(r). Along the contact line the roller and the flank curve alike, so
    this sum is the flank's curvature across the line."""
    side = np.asarray(side, dtype=np.float64)
    value = j0 + side * j1 * radius + j2 * radius * radius
    slope = side * j1 + 2.0 * j2 * radius
    with np.errstate(divide="ignore", invalid="ignore"):
        return -slope / value


def _smallest_positive_root(a: Array, b: Array, c: Array) -> Array:
    """Elementwise, the smallest positive root of a r² + b r + c (inf where none)."""
    a, b, c = (np.asarray(v, dtype=np.float64) for v in (a, b, c))
    out = np.full(np.broadcast(a, b, c).shape, np.inf)
    disc = b * b - 4 * a * c
    with np.errstate(divide="ignore", invalid="ignore"):
        sq = np.sqrt(np.maximum(disc, 0.0))
        quad = np.abs(a) > 1e-12 * (np.abs(b) + np.abs(c) + 1e-300)
        r1 = np.where(quad, (-b - sq) / (2 * a), -c / b)
        r2 = np.where(quad, (-b + sq) / (2 * a), np.inf)
    real = (disc >= 0) | ~quad
    for r in (r1, r2):
        good = real & np.isfinite(r) & (r > 0)
        out = np.where(good, np.minimum(out, r), out)
    return out


def groove_tube(globoid: Globoid, theta: Array, motion: Array, rows: Array,
                across: int = 8) -> tuple[Array, Array]:
    """The groove as one closed tube on the cam (mm): at each cam angle of *theta* (its
    *motion* (4, N), the cycle's stations, the last not repeating the first) the section
    bounded by the two flanks over the distances *rows* along the arm (the first outside the
    blank, the last the floor, past the roller's far end), the floor across from one flank to
    the other in *across* steps, and the top across back; consecutive sections joined by quads
    split into triangles, wound so that the normals point out of the tube. Returns (V, 3)
    vertices and (F, 3) faces."""
    g = globoid
    ell = np.asarray(rows, dtype=np.float64)
    top, floor = float(ell[0]), float(ell[-1])
    u = np.linspace(1.0, -1.0, across + 1)
    # the section: flank + (u = 1) from top to floor, the floor, flank − back, the top
    loop_ell = np.concatenate((ell, np.full(across - 1, floor), ell[::-1],
                               np.full(across - 1, top)))
    loop_u = np.concatenate((np.ones(ell.size), u[1:-1], -np.ones(ell.size), u[::-1][1:-1]))
    points = g.across(np.asarray(theta)[:, None], loop_ell[None, :], motion[:, :, None],
                      loop_u[None, :])
    stations, size = points.shape[:2]
    index = np.arange(stations * size).reshape(stations, size)
    a = index
    b = np.roll(index, -1, axis=1)
    c = np.roll(index, -1, axis=0)
    d = np.roll(c, -1, axis=1)
    faces = np.concatenate((np.stack((a, c, b), -1).reshape(-1, 3),
                            np.stack((b, c, d), -1).reshape(-1, 3)))
    vertices = points.reshape(-1, 3)
    if signed_volume(vertices, faces) < 0.0:
        faces = faces[:, ::-1]
    return vertices, faces
