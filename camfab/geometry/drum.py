"""Cylindrical (drum) cams: the exact groove of a cylindrical roller with a radial axis (THEORY §C).

Frame: the cam axis is Z; the follower moves along +Z; at θ = 0 the roller's axis is the radial
line along +Y. In the cam frame the roller's axis at cam angle θ is the radial line at polar
angle α = −σθ, measured from +Y counter-clockwise about +Z (a point at polar angle ϕ and radius r
is (−r sin ϕ, r cos ϕ)), at height z = start + s(θ).

A wall point at radius r and polar angle ϕ = α + δ lies on the roller's surface,
r²sin²δ + (z − s)² = R², where the roller is tangent to it as it moves (the envelope condition
σ r² sin δ cos δ = (z − s) s′). Per radius this gives w = r sin δ from
w⁴ − (s′² + r²) w² + R² s′² = 0 (the smaller root) and z − s = ±√(R² − w²): the upper wall
(z > s) has w of the sign of σs′, the lower wall is its reflection through the axis. Here R is
the roller radius plus half the groove clearance, so the groove is 2R wide.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from camfab.arrays import Array, Index

#: Cam-angle step of the dense evaluation of pressure angle and curvature (as for disc cams).
ANALYSIS_STEP = math.radians(0.05)

if TYPE_CHECKING:
    from camfab.design import Design
    from camfab.motion.program import MotionProgram


@dataclass(frozen=True)
class Walls:
    """Both groove walls at the given cam angles and radii (arrays broadcast together): polar
    angles ϕ (rad, from +Y counter-clockwise) and heights z (mm)."""

    phi_lower: Array
    z_lower: Array
    phi_upper: Array
    z_upper: Array


@dataclass(frozen=True)
class Drum:
    """A drum cam's dimensions (mm) and rotation.

    Attributes
    ----------
    radius, depth, length
        Outer radius, groove depth and length of the drum.
    start
        Height of the roller centre at zero lift.
    roller
        The wall's distance from the roller axis: roller radius + half the groove clearance.
    sigma
        +1 counter-clockwise, −1 clockwise.
    bore
        Bore radius (0 without a bore).
    """

    radius: float
    depth: float
    length: float
    start: float
    roller: float
    sigma: int
    bore: float = 0.0

    @property
    def root(self) -> float:
        """Radius of the groove's floor."""
        return self.radius - self.depth

    @property
    def pitch(self) -> float:
        """The mean radius of the groove, where the pitch curve is reported."""
        return self.radius - self.depth / 2.0

    def axis_angle(self, theta: Array) -> Array:
        """Polar angle α = −σθ of the roller's axis in the cam frame (rad)."""
        return -self.sigma * np.asarray(theta, dtype=np.float64)

    def walls(self, theta: Array, s: Array, ds: Array, r: Array | float) -> Walls:
        """The exact wall points at cam angles *theta* (with lift *s*, mm, and s′, mm/rad) and
        radii *r* (mm), broadcast together."""
        big = self.roller
        ds = np.asarray(ds, dtype=np.float64)
        r = np.asarray(r, dtype=np.float64)
        a = ds * ds + r * r
        # the smaller root of U² − aU + R²s′² = 0, written without cancellation: U = 2R²s′²/(a + √…)
        u = 2.0 * big * big * ds * ds / (a + np.sqrt(np.maximum(a * a - 4.0 * big * big * ds * ds,
                                                                0.0)))
        w = np.sign(self.sigma * ds) * np.sqrt(u)
        delta = np.arcsin(np.clip(w / r, -1.0, 1.0))
        rise = np.sqrt(np.maximum(big * big - u, 0.0))
        alpha = self.axis_angle(theta)
        z = self.start + np.asarray(s, dtype=np.float64)
        return Walls(alpha - delta, z - rise, alpha + delta, z + rise)

    def pressure_angle(self, ds: Array, r: float) -> Array:
        """Signed pressure angle at radius *r* (rad): tan φ = s′/r."""
        return np.arctan2(ds, r)

    def flank_curvature(self, ds: Array, dds: Array, r: Array | float, lower: bool,
                        radius: float | None = None) -> Array:
        """The sum of the principal curvatures (1/mm, convex positive as the cam's material
        sees it) of the lower (*lower*) or upper flank of a roller of *radius* (default the
        wall's) where its axis is at radius *r* (mm), with s′ (mm/rad) and s″ (mm/rad²).

        The roller's axis sweeps the surface q(θ, r) = r·e_r(α) + (start + s)·ẑ, whose normal
        is n = −(σr ẑ + s′ e_t)/W (W = √(r² + s′²)) and whose principal curvatures along n have
        the sum H = −σ r s″/W³ and the product K = −s′²/W⁴; a flank is that surface moved
        ±R along n (the lower one +σ: toward it the sum is H_f = σH = −r s″/W³, toward the upper
        one r s″/W³), so its curvatures are κᵢ/(1 − Rκᵢ), whose sum is
        (H_f − 2RK)/(1 − R H_f + R²K). Along the contact line the roller and the flank curve
        alike, so this sum is the flank's curvature across it."""
        big = self.roller if radius is None else radius
        ds = np.asarray(ds, dtype=np.float64)
        square = r * r + ds * ds
        width = np.sqrt(square)
        toward = -1.0 if lower else 1.0
        mean = toward * r * np.asarray(dds, dtype=np.float64) / (square * width)
        gauss = -ds * ds / (square * square)
        with np.errstate(divide="ignore", invalid="ignore"):
            return (mean - 2.0 * big * gauss) / (1.0 - big * mean + big * big * gauss)

    def developed_radius(self, ds: Array, dds: Array, r: float) -> Array:
        """Signed radius of curvature (mm) of the pitch curve developed at radius *r*,
        (r² + s′²)^{3/2} / (r s″); ±inf where s″ = 0."""
        with np.errstate(divide="ignore"):
            return (r * r + ds * ds) ** 1.5 / (r * dds)


#: Radii (from the groove's floor to the drum's surface) at which pressure angle and curvature are
#: evaluated: both change monotonically with the radius, so the ends decide; the steps between
#: show the trend.
ANALYSIS_RADII = 5


@dataclass(frozen=True)
class DrumDense:
    """Exact values on a fine grid of cam angle, segment by segment (joints twice, one-sided),
    at :data:`ANALYSIS_RADII` radii from the floor (row 0) to the surface (last row).

    ``pressure_angle`` (rad, signed) and ``developed_radius`` (mm, signed, ±inf where straight)
    have shape (radii, N).
    """

    drum: Drum
    segment: Index
    theta: Array
    motion: Array
    radii: Array
    pressure_angle: Array
    developed_radius: Array


def drum_dense(d: Drum, program: MotionProgram, step: float | None = None) -> DrumDense:
    """Pressure angle and developed curvature of the groove over the cycle."""
    segment, theta, motion = program.segment_grid(step or ANALYSIS_STEP)
    radii = np.linspace(d.root, d.radius, ANALYSIS_RADII)
    phi = np.stack([d.pressure_angle(motion[1], r) for r in radii])
    rho = np.stack([d.developed_radius(motion[1], motion[2], r) for r in radii])
    return DrumDense(d, segment, theta, motion, radii, phi, rho)


def drum(design: Design) -> Drum:
    """The drum of a cylindrical-cam design (mm)."""
    cam, fol = design.cam, design.follower
    assert cam.radius is not None and cam.length is not None and cam.groove_depth is not None
    lift = design.program.max_lift
    start = cam.groove_start if cam.groove_start is not None else (cam.length - lift) / 2.0
    roller = (fol.roller_radius or 0.0) + fol.groove_clearance / 2.0
    return Drum(cam.radius, cam.groove_depth, cam.length, start, roller, cam.sigma,
                (cam.bore or 0.0) / 2.0)


def polar_to_xy(r: Array | float, phi: Array) -> Array:
    """Cam-frame (x, y) (mm) of points at radius *r* and polar angle *phi* from +Y."""
    return np.stack(np.broadcast_arrays(-r * np.sin(phi), r * np.cos(phi)), axis=-1)

