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
from typing import TYPE_CHECKING, Any

import numpy as np

from camfab.arrays import Array
from camfab.geometry.disc import DiscCam
from camfab.geometry.profile import Profile
from camfab.geometry.simulate import simulate

if TYPE_CHECKING:
    from camfab.analysis.cam_checks import CamNumbers
    from camfab.design import Design
    from camfab.geometry.disc_geometry import DiscGeometry
    from camfab.geometry.groove import WallContact
    from camfab.motion.program import MotionProgram


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


@dataclass(frozen=True)
class Partner:
    """What holds a positive-drive plate cam's follower on the other side.

    Attributes
    ----------
    kind
        ``conjugate`` (a second cam) or ``constant-breadth`` (the same cam half a turn on).
    spacing
        Conjugate: the rollers' distance along the follower (mm), or the angle between the
        bell-crank's arms (rad). Constant breadth: the distance between the yoke's faces or its
        rollers' centres (mm).
    hold
        The follower run over both contacts of the cams as sampled.
    geometry, program, numbers
        Conjugate only: cam b's geometry in the frame it is computed in, its motion ``h − s``
        and its key numbers.
    mirror
        Conjugate only: cam b is computed mirrored in the line of centres (an oscillating pair),
        not turned half a turn.
    contact
        Which side carries the follower over the cycle (+1 cam a or the upper face or roller,
        −1 the other), by the sign of its acceleration, with the force given a mass and speed.
    flat
        Constant breadth: the yoke's contacts are flat faces (else rollers).
    """

    kind: str
    spacing: float
    hold: Hold
    geometry: DiscGeometry | None = None
    program: MotionProgram | None = None
    numbers: CamNumbers | None = None
    mirror: bool = False
    contact: WallContact | None = None
    flat: bool = False

    @property
    def sides(self) -> dict[int, str]:
        """The contact carrying the follower by the sign of s″: +1 pushes it away from the cam
        centre, −1 pulls it back."""
        if self.kind == "conjugate":
            return {1: "cam a", -1: "cam b"}
        return {1: "upper face", -1: "lower face"} if self.yoke_faces else {
            1: "upper roller", -1: "lower roller"}

    @property
    def yoke_faces(self) -> bool:
        """True for a constant-breadth cam between two flat faces."""
        return self.geometry is None and self.flat

    @property
    def hold_kind(self) -> str:
        """What holds the follower: ``conjugate`` rollers, a ``bell-crank``'s or a yoke."""
        return "bell-crank" if self.mirror else self.kind

    def report_geometry(self) -> dict[str, Any]:
        """The JSON report's geometry keys of the second contact (mm, deg)."""
        out: dict[str, Any] = {}
        if self.kind == "constant-breadth":
            out["breadth_mm"] = self.spacing
        elif self.mirror:
            out["arm_angle_deg"] = math.degrees(self.spacing)
        else:
            out["roller_spacing_mm"] = self.spacing
        from camfab.analysis.cam_checks import extreme

        out.update({"hold_max_gap_mm": self.hold.max_gap,
                    "hold_max_interference_mm": self.hold.max_interference})
        contact = self.contact
        if contact is not None:
            sides = self.sides
            out["load_changes"] = [{"cam_angle_deg": deg, "from": sides[-int(to)],
                                    "onto": sides[int(to)]}
                                   for deg, to in zip(contact.changes_deg, contact.onto,
                                                      strict=True)]
            force = contact.force_N
            for sign in (1, -1):
                key = sides[sign].replace(" ", "_")
                worst = (None if force is None else
                         extreme(contact.theta, sign * force, sign * force > 0, largest=True))
                out[f"max_{key}_force_N"] = None if worst is None else worst.value
                out[f"max_{key}_force_at_deg"] = None if worst is None else worst.at_deg
        geom, numbers = self.geometry, self.numbers
        if geom is None or numbers is None:
            return out
        out.update({
            "cam_b_base_radius_mm": geom.cam.base_radius,
            "cam_b_prime_radius_mm": geom.cam.prime_radius,
            "cam_b_max_radius_mm": numbers.max_radius_mm,
            "cam_b_pitch_min_radius_of_curvature_mm": numbers.pitch_min_convex.value,
            "cam_b_profile_min_radius_of_curvature_mm": numbers.profile_min_convex.value,
            "cam_b_profile_min_concave_radius_mm": numbers.profile_min_concave.value,
            "cam_b_pressure_angle_max_deg": numbers.pressure_angle.value,
            "cam_b_pressure_angle_max_at_deg": numbers.pressure_angle.at_deg,
            "cam_b_undercut": geom.undercut,
        })
        return out


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
