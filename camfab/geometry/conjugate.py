"""The second contact of a cam that holds its follower without a spring (THEORY §F).

A conjugate pair drives one translating follower through two rollers ``roller_spacing`` apart
along it: roller a rides cam a from above (the design's motion s), roller b rides cam b from below
the shaft. Turned half a turn, cam b is an ordinary plate cam whose follower rises as the other
falls: its roller sits on the line ``x = −offset`` with the motion ``h − s(θ)``, its prime circle
through the trace point's lowest position ``L − y₀ − h`` (y₀: roller a's height at zero lift).
So cam b is built in that half-turned frame with the disc cam's exact curves, and turned back by
half a turn for its files.

A constant-breadth cam holds a yoke of two parallel faces (or, constant-diameter, two rollers on a
line through the cam centre) with one cam: the lower contact at θ is the upper one at θ + π, so
the breadth ``y(θ) + y(θ + π)`` must stay the yoke's.

Either way the pair holds the follower when the two contacts, each found by running its follower
over its cam, stay exactly their spacing apart: the :class:`Hold` measures the gap (positive:
the follower is free to rattle) or the interference (negative: the cams jam it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from camfab.arrays import Array
from camfab.curves.profile import Profile
from camfab.geometry.disc import DiscCam
from camfab.geometry.simulate import simulate

if TYPE_CHECKING:
    from camfab.design import Design
    from camfab.geometry.disc_geometry import DiscGeometry


def half_turned(points: Array) -> Array:
    """(N, 2) points turned half a turn about the cam centre."""
    return -np.asarray(points)


def mirrored(points: Array) -> Array:
    """(N, 2) points mirrored in the X axis (the line of centres)."""
    return np.asarray(points) * np.array([1.0, -1.0])


def partner_cam(design: Design, cam_a: DiscCam) -> tuple[DiscCam, float]:
    """Cam b of a conjugate pair in the frame it is computed in, and the spacing that joins the
    two trace points: the rollers' distance L (mm), or the angle between the arms (rad).

    Translating: turned half a turn, roller b on the line x = −e with its lowest trace point
    ``L − y₀ − h`` from the centre. Oscillating: mirrored in the line of centres (the cam turning
    the other way), arm b on the same pivot with its rest angle ``γ − Ψ₀ − h``. The design rules
    check :func:`partner_base_radius` first.
    """
    fol = design.follower
    base = partner_base_radius(design, cam_a)
    if fol.oscillating:
        return DiscCam(cam_a.follower, base, -cam_a.sigma), fol.arm_angle or 0.0
    follower = replace(cam_a.follower, offset=-cam_a.follower.offset)
    return DiscCam(follower, base, cam_a.sigma), fol.roller_spacing or 0.0


def partner_base_radius(design: Design, cam_a: DiscCam) -> float:
    """Cam b's base radius (mm), or −inf when its follower would not reach a cam: translating,
    ``√((L − y₀ − h)² + e²) − Rr``; oscillating, arm b at its rest angle ``γ − Ψ₀ − h``,
    ``√(a² + l² − 2al·cos(γ − Ψ₀ − h)) − Rr``."""
    fol = cam_a.follower
    if fol.oscillating:
        rest = (design.follower.arm_angle or 0.0) - cam_a.rest - design.program.max_lift
        if rest <= 0.0:
            return -math.inf
        a, arm = fol.pivot_distance, fol.arm_length
        return math.sqrt(a * a + arm * arm - 2 * a * arm * math.cos(rest)) - fol.radius
    low = (design.follower.roller_spacing or 0.0) - cam_a.rest - design.program.max_lift
    if low <= 0.0:
        return -math.inf
    return math.hypot(low, fol.offset) - fol.radius


def breadth(cam: DiscCam, lift: float) -> float:
    """A constant-breadth cam's yoke: the distance between its faces (flat) or its rollers'
    centres (mm): twice the rest height plus the lift."""
    return 2.0 * cam.rest + lift


@dataclass(frozen=True)
class Hold:
    """How the two contacts hold the follower at each cam angle *theta* (rad): ``gap`` (mm) is
    the spacing less the two contacts' distance, positive where the follower is free to move
    (it would rattle) and negative where the cams overlap its rollers or faces (they jam)."""

    theta: Array
    gap: Array

    @property
    def max_gap(self) -> float:
        return max(0.0, float(self.gap.max()))

    @property
    def max_interference(self) -> float:
        return max(0.0, float(-self.gap.min()))

    @property
    def worst(self) -> float:
        """The largest departure either way (mm)."""
        return float(np.max(np.abs(self.gap)))

    @property
    def worst_at_deg(self) -> float:
        return math.degrees(float(self.theta[int(np.argmax(np.abs(self.gap)))]))


def hold(theta: Array, spacing: float, a: tuple[Profile, DiscCam], b: tuple[Profile, DiscCam],
         b_shift: float = 0.0) -> Hold:
    """Run each follower over its cam (the profile in the frame its cam is computed in) at the
    cam angles *theta* (rad) — contact b at θ + *b_shift* — and compare the two positions with
    the *spacing* (mm, or rad between two arms) that joins them. The gap is in mm at the trace
    point (an angle times the arm length)."""
    ya = simulate(a[0], a[1].follower, theta, a[1].sigma)
    shifted = np.mod(theta + b_shift, 2.0 * math.pi)
    order = np.argsort(shifted, kind="stable")  # the simulation walks the angles in order
    yb = np.empty_like(ya)
    yb[order] = simulate(b[0], b[1].follower, shifted[order], b[1].sigma)
    scale = a[1].follower.arm_length if a[1].follower.oscillating else 1.0
    return Hold(theta, (spacing - ya - yb) * scale)


def to_made_frame(profile: Profile, mirror: bool) -> Profile:
    """A cam b outline moved between the frame it is computed in and the frame it is made in
    (the move is its own inverse): turned half a turn, or *mirror*-ed in the line of centres
    (counter-clockwise again)."""
    if not mirror:
        return Profile(half_turned(profile.vertices), profile.bulges.copy())
    return Profile(mirrored(profile.vertices), -profile.bulges).ccw()


def made_geometry(geom: DiscGeometry, mirror: bool) -> DiscGeometry:
    """Cam b's geometry moved into the frame it is made in: its sampled curves and outline (what
    its files draw); the exact evaluators stay in the frame it is computed in."""
    from camfab.geometry.disc_geometry import Sampled

    move = mirrored if mirror else half_turned

    def moved(sampled: Sampled) -> Sampled:
        return Sampled(sampled.theta, move(sampled.xy))

    return replace(geom, pitch=moved(geom.pitch), working=moved(geom.working),
                   profile=to_made_frame(geom.profile, mirror))
