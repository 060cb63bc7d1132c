"""A disc with a face groove (positive drive, THEORY §F): the roller runs in a groove milled into
the plate's face, so the cam drives the follower both ways without a spring.

The groove's walls are the pitch curve offset along its normal by R = roller radius + half the
groove clearance: inward, the inner wall (a disc cam's working curve for a roller of radius R, so
``base_radius`` is the inner wall's smallest radius and the prime radius is base_radius + R), and
outward, the outer wall. A wall folds over where the pitch curve bends more sharply than R: the
inner wall on convex stretches (ρ_p < R, the disc cam's undercut), the outer wall on concave ones
(|ρ_p| < R).

The inner wall pushes the follower away from the cam centre and the outer wall pulls it back: the
force the cam supplies along the follower's motion is F = m·ω²·s″ (no spring, no load), so the
roller bears on the inner wall where s″ > 0 and on the outer wall where s″ < 0. Where s″ changes
sign, contact passes to the other wall across the clearance and the roller reverses its spin.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from camfab.arrays import Array, Mask
from camfab.curves.plane import CurvePoints
from camfab.curves.profile import Profile
from camfab.geometry.disc import DiscCam
from camfab.geometry.disc_geometry import (
    ANALYSIS_STEP,
    VERIFY_STEP,
    DiscGeometry,
    LiftCheck,
    disc_cam,
    lift_check,
    outer_wall,
    sample_closed,
    segment_tolerances,
)
from camfab.geometry.offset import quad_segments
from camfab.geometry.plate import fit_chain
from camfab.geometry.undercut import is_simple
from camfab.motion.program import MotionProgram

if TYPE_CHECKING:
    from camfab.design import Design

#: The rim of material outside the outer wall when ``outer_radius`` is not given: the roller's
#: radius, and at least 3 mm, so the rim is as stiff as the roller is wide and survives milling
#: or printing. The default outer radius is rounded up to a whole millimetre.
MIN_RIM_MM = 3.0

#: An acceleration s″ smaller in size than this share of its largest value counts as zero (a
#: dwell, or a uniform-velocity stretch): no force, so no wall carries the roller there. 1e-9
#: is far above the rounding of a law's s″ and far below any acceleration that matters.
ZERO_ACCELERATION = 1e-9

#: Bisection rounds that place a wall change: each halves a bracket of at most 0.05°, so 40
#: rounds reach far below the rounding of an angle.
_BISECTIONS = 40

#: Wall names by contact sign: +1 the inner wall, −1 the outer wall.
WALL_NAMES = {1: "inner", -1: "outer"}


@dataclass(frozen=True)
class WallContact:
    """Which wall the roller bears on over the cycle.

    Attributes
    ----------
    theta
        Cam angles (rad) of the dense grid (a joint appears twice).
    wall
        +1 where the inner wall carries the roller (s″ > 0), −1 the outer wall (s″ < 0), 0 where
        no force is needed (s″ = 0).
    changes
        The cam angles (rad, ascending in [0, 2π)) where contact passes to the other wall: a zero
        of s″ (or a step of s″ through zero at a joint), or, after a stretch without force, where
        the other wall first carries the roller.
    onto
        The wall contact passes onto at each change (+1 inner, −1 outer).
    force_N
        The force along the follower's motion (N, + on the inner wall) at ``theta``, with a
        follower mass and a speed; else None.
    """

    theta: Array
    wall: Array
    changes: Array
    onto: Array
    force_N: Array | None

    @property
    def changes_deg(self) -> list[float]:
        return [round(math.degrees(float(a)), 9) + 0.0 for a in self.changes]


def wall_contact(program: MotionProgram, mass_kg: float | None = None,
                 omega: float | None = None, metres_per_unit: float = 1e-3,
                 step: float = ANALYSIS_STEP) -> WallContact:
    """Where the roller bears on each wall, from the sign of s″ on a grid of *step* (rad).

    Parameters
    ----------
    program
        The motion s(θ).
    mass_kg, omega
        The follower's mass (kg) and the cam's speed (rad/s), for the force in newtons.
    metres_per_unit
        Metres of the follower's motion per unit of lift (1e-3 for mm; the arm length in
        metres for an oscillating follower's radians of swing).
    step
        The largest cam-angle step (rad) of the grid.
    """
    _, theta, m = program.segment_grid(step)
    acc = m[2]
    zero = ZERO_ACCELERATION * max(float(np.max(np.abs(acc))), 1e-300)
    wall = np.where(acc > zero, 1.0, np.where(acc < -zero, -1.0, 0.0))
    changes, onto = _changes(program, theta, wall)
    force = None
    if mass_kg is not None and omega is not None:
        force = mass_kg * omega**2 * acc * metres_per_unit
    return WallContact(theta, wall, changes, onto, force)


def _changes(program: MotionProgram, theta: Array, wall: Array) -> tuple[Array, Array]:
    """The cam angles where the loaded wall changes, found on the grid and placed by bisection
    on the exact s″: the first angle at which the new wall carries the roller."""
    loaded = np.flatnonzero(wall)
    if loaded.size == 0:
        return np.zeros(0), np.zeros(0)
    # the first loaded grid point again, one turn on, closes the cycle
    index = np.concatenate((loaded, loaded[:1]))
    sign = wall[index]
    flip = np.flatnonzero(sign[1:] != sign[:-1])
    onto = sign[flip + 1]
    after = index[flip + 1]
    hi = theta[after] + np.where(flip + 1 == len(loaded), 2 * math.pi, 0.0)
    # bracket: the grid point before the first one loaded the new way (the last grid point,
    # at 2π, precedes the first)
    lo = np.where(after > 0, theta[after - 1], theta[-1] - 2 * math.pi)
    lo = lo + np.where(flip + 1 == len(loaded), 2 * math.pi, 0.0)
    for _ in range(_BISECTIONS):
        mid = 0.5 * (lo + hi)
        acc = program.evaluate(mid)[2]
        new = np.sign(acc) == onto
        lo, hi = np.where(new, lo, mid), np.where(new, mid, hi)
    at = np.mod(hi, 2 * math.pi)
    at = np.where(at > 2 * math.pi - 1e-12, 0.0, at)
    order = np.argsort(at, kind="stable")
    return at[order], onto[order]


@dataclass(frozen=True)
class GrooveWalls:
    """A groove cam's walls and what the report needs of them (lengths in mm).

    Attributes
    ----------
    radius
        R: the roller radius plus half the groove clearance; the walls lie R either side of the
        pitch curve, so the groove is 2R wide across it.
    roller_radius, clearance
        The roller's radius and the groove clearance.
    depth, thickness
        The groove's depth from the plate's face, and the plate's thickness.
    outer_radius, outer_radius_given
        The plate's radius, and whether the design gave it (else the outer wall's largest
        radius plus the rim, rounded up to a whole millimetre).
    inner, outer
        The walls as closed contours of lines and arcs within the sampling tolerance (ccw); a
        wall that folds is the boundary of the roller's sweep (the loops trimmed).
    inner_points, outer_points
        The walls as closed chains of points within the sampling tolerance (ccw).
    outer_dense
        The exact outer wall on the analysis grid (``geom.dense``), loops included.
    inner_folds, outer_folds
        Where the inner (convex ρ_p < R) and outer (concave |ρ_p| < R) walls fold (dense mask).
    inner_trimmed
        Whether the inner wall is trimmed (it folds, or crosses itself: the disc cam's
        undercut).
    outer_crossing
        Whether the raw outer wall crosses itself (two stretches of the groove closer than its
        width).
    contact
        Which wall carries the roller, and where that changes.
    pitch_radius
        The pitch curve's signed radius of curvature on the dense grid (convex positive).
    dense_theta
        The dense grid's cam angles (rad).
    """

    radius: float
    roller_radius: float
    clearance: float
    depth: float
    thickness: float
    outer_radius: float
    outer_radius_given: bool
    inner: Profile
    outer: Profile
    inner_points: Array
    outer_points: Array
    outer_dense: CurvePoints
    inner_folds: Mask
    outer_folds: Mask
    inner_trimmed: bool
    outer_crossing: bool
    contact: WallContact
    pitch_radius: Array
    dense_theta: Array

    @property
    def width(self) -> float:
        """The groove's width across the pitch curve (mm)."""
        return 2.0 * self.radius

    @property
    def folded(self) -> bool:
        """True when a wall folds over or the outer wall crosses itself."""
        return bool(self.inner_trimmed or self.outer_folds.any() or self.outer_crossing)

    @property
    def outer_wall_max_radius(self) -> float:
        return float(np.max(np.hypot(*self.outer_points.T)))

    def report_geometry(self) -> dict[str, Any]:
        """The groove's numbers for the JSON report's geometry block (mm, deg, N)."""
        from camfab.angles import extreme, ranges_deg

        theta, rho = self.dense_theta, self.pitch_radius
        outer_rho = self.outer_dense.radius
        concave = extreme(theta, -outer_rho, (outer_rho < 0) & ~self.outer_folds,
                          largest=False)
        convex = extreme(theta, outer_rho, (outer_rho > 0) & ~self.outer_folds, largest=False)
        smallest = extreme(theta, np.abs(rho), None, largest=False)
        contact = self.contact
        out: dict[str, Any] = {
            "max_radius_mm": self.outer_radius,
            "groove_width_mm": self.width,
            "groove_half_width_mm": self.radius,
            "groove_depth_mm": self.depth,
            "groove_clearance_mm": self.clearance,
            "roller_radius_mm": self.roller_radius,
            "thickness_mm": self.thickness,
            "floor_thickness_mm": self.thickness - self.depth,
            "outer_radius_mm": self.outer_radius,
            "outer_radius_given": self.outer_radius_given,
            "rim_mm": self.outer_radius - self.outer_wall_max_radius,
            "inner_wall_min_radius_mm": float(np.min(np.hypot(*self.inner_points.T))),
            "inner_wall_max_radius_mm": float(np.max(np.hypot(*self.inner_points.T))),
            "outer_wall_min_radius_mm": float(np.min(np.hypot(*self.outer_points.T))),
            "outer_wall_max_radius_mm": self.outer_wall_max_radius,
            "outer_wall_min_radius_of_curvature_mm": convex.value,
            "outer_wall_min_radius_of_curvature_at_deg": convex.at_deg,
            "outer_wall_min_concave_radius_mm": concave.value,
            "outer_wall_min_concave_radius_at_deg": concave.at_deg,
            "pitch_min_abs_radius_of_curvature_mm": smallest.value,
            "pitch_min_abs_radius_of_curvature_at_deg": smallest.at_deg,
            "groove_folds": self.folded,
            "inner_wall_fold_ranges_deg": [list(r) for r in ranges_deg(theta, self.inner_folds)],
            "outer_wall_fold_ranges_deg": [list(r) for r in ranges_deg(theta, self.outer_folds)],
            "inner_wall_entities": len(self.inner.vertices),
            "outer_wall_entities": len(self.outer.vertices),
            "wall_changes_deg": contact.changes_deg,
            "wall_changes": [{"cam_angle_deg": deg, "onto": WALL_NAMES[int(to)],
                              "from": WALL_NAMES[-int(to)]}
                             for deg, to in zip(contact.changes_deg, contact.onto, strict=True)],
            "wall_change_count": len(contact.changes),
            "inner_wall_contact_ranges_deg": [list(r) for r in
                                              ranges_deg(contact.theta, contact.wall > 0)],
            "outer_wall_contact_ranges_deg": [list(r) for r in
                                              ranges_deg(contact.theta, contact.wall < 0)],
        }
        force = contact.force_N
        inner_force = outer_force = None
        if force is not None:
            inner_force = extreme(contact.theta, force, force > 0, largest=True)
            outer_force = extreme(contact.theta, -force, force < 0, largest=True)
        out.update({
            "max_inner_wall_force_N": None if inner_force is None else inner_force.value,
            "max_inner_wall_force_at_deg": None if inner_force is None else inner_force.at_deg,
            "max_outer_wall_force_N": None if outer_force is None else outer_force.value,
            "max_outer_wall_force_at_deg": None if outer_force is None else outer_force.at_deg,
        })
        return out


def wall_lift_check(cam: DiscCam, program: MotionProgram, radius: float, inner: Profile,
                    outer: Profile, step: float = VERIFY_STEP) -> LiftCheck:
    """The follower's displacement error each wall would cause, the worst at each cam angle.

    Three measures at every *step* (rad): the roller of *radius* (mm) pressed onto *inner* from
    outside (the follower simulation), and the exact roller centre's distance from *inner* and
    from *outer*, less *radius*, over cos φ (a wall δ off along its normal moves the follower
    δ/cos φ along its path). The outer wall pulls the roller back and cannot be pressed onto from
    outside, so the distance is its measure. ``error_mm`` is at the trace point; ``error`` in
    the lift's unit (rad for an oscillating follower).
    """
    pressed = lift_check(cam, program, inner, step)
    theta = pressed.theta
    m = program.evaluate(theta)
    centre = cam.pitch(theta, m).xy
    cos = np.cos(cam.pressure_angle(theta, m))
    # a wall too far from the roller centre lets the follower sink (inner) or rise (outer)
    errors = np.stack((pressed.error_mm,
                       -(inner.distance(centre) - radius) / cos,
                       (outer.distance(centre) - radius) / cos))
    errors = np.where(np.isfinite(errors), errors, np.inf)
    worst = errors[np.argmax(np.abs(errors), axis=0), np.arange(theta.size)]
    scale = cam.follower.arm_length if cam.follower.oscillating else 1.0
    return LiftCheck(theta, worst / scale, worst)


def default_outer_radius(outer_wall_max_radius: float, roller_radius: float) -> float:
    """The plate's radius when the design gives none (mm): the outer wall's largest radius plus
    a rim of the roller radius, at least :data:`MIN_RIM_MM`, rounded up to a whole mm."""
    return float(math.ceil(outer_wall_max_radius + max(MIN_RIM_MM, roller_radius) - 1e-9))


def outer_wall_reach(design: Design) -> float:
    """The outer wall's largest radius (mm) on the analysis grid, from the design alone (the
    design rules check ``outer_radius`` against it)."""
    cam = disc_cam(design, design.follower.groove_clearance / 2)
    _, theta, m = design.program.segment_grid(ANALYSIS_STEP)
    return float(np.max(np.hypot(*outer_wall(cam, theta, m).xy.T)))


def _swept_outline(pitch_xy: Array, radius: float, tolerance: float) -> Array:
    """The outer boundary (ccw points, mm) of the band a circle of *radius* sweeps along the
    closed pitch polyline: the outer wall a cutter following the roller leaves where the offset
    folds (GEOS trims the loops)."""
    import shapely

    band = shapely.LinearRing(pitch_xy).buffer(radius,
                                               quad_segs=quad_segments(radius, tolerance))
    ring = shapely.LinearRing(band.exterior)
    coords = np.asarray(ring.coords)[:-1]
    return coords if ring.is_ccw else coords[::-1].copy()


def groove_walls(design: Design, geom: DiscGeometry) -> GrooveWalls:
    """Both walls of a groove cam whose disc geometry (the inner wall) is *geom*."""
    cam, fol, program = design.cam, design.follower, design.program
    assert cam.thickness is not None and cam.groove_depth is not None
    disc = geom.cam
    radius = disc.follower.radius
    dense = geom.dense
    tolerances = segment_tolerances(disc, dense, design.manufacturing.tolerance,
                                    len(program.segments))
    raw = sample_closed(disc, program, "outer", tolerances)
    outer_dense = outer_wall(disc, dense.theta, dense.motion)
    rho = dense.pitch.radius
    outer_folds = (rho < 0.0) & (-rho < radius)
    crossing = not is_simple(raw.xy)
    outer_xy = raw.xy
    if outer_folds.any() or crossing:
        outer_xy = _swept_outline(geom.pitch.xy, radius, 0.25 * geom.tolerance)
    outer_points = Profile.from_points(outer_xy).ccw().vertices
    inner_points = geom.profile.vertices
    reach = float(np.max(np.hypot(*outer_points.T)))
    given = cam.outer_radius is not None
    outer_radius = (cam.outer_radius if cam.outer_radius is not None else
                    default_outer_radius(reach, fol.roller_radius or 0.0))
    scale = (fol.arm_length or 0.0) / 1000.0 if fol.oscillating else 1e-3
    contact = wall_contact(program, fol.mass, cam.omega, scale)
    return GrooveWalls(
        radius=radius, roller_radius=fol.roller_radius or 0.0, clearance=fol.groove_clearance,
        depth=cam.groove_depth, thickness=cam.thickness, outer_radius=outer_radius,
        outer_radius_given=given,
        inner=fit_chain(inner_points, geom.tolerance),
        outer=fit_chain(outer_points, geom.tolerance),
        inner_points=inner_points, outer_points=outer_points, outer_dense=outer_dense,
        inner_folds=geom.folds, outer_folds=outer_folds, inner_trimmed=geom.undercut,
        outer_crossing=crossing,
        contact=contact, pitch_radius=rho, dense_theta=dense.theta)
