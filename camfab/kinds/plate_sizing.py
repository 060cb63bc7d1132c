"""A plate cam's limits at a base radius, for the sizing (:mod:`camfab.analysis.sizing`).

The limits are the build's checks (:mod:`camfab.analysis.cam_checks`,
:mod:`camfab.analysis.groove_checks`), judged as they judge them on the same exact curves: the
pressure angle, the envelope's folding (``undercut``, or both walls of a groove: ``groove``), the
profile's convex radius against ``limits.min_radius_of_curvature``, the face width a flat face
needs, the contact stress and the roller bearing's life where the design limits them; and the
part's fit as the design file's rules judge it: the bore and keyway inside the base circle, the
follower's line inside the prime circle, an arm that reaches it, cam b of a conjugate pair with a
base circle round the bore. Lengths are millimetres and angles degrees.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from camfab.analysis.sizing import (
    SEARCH_FACTOR,
    Grid,
    LimitValue,
    SizeProblem,
    grids,
    passes,
)
from camfab.arrays import Array
from camfab.curves.follower import FollowerGeometry
from camfab.design.rules import MIN_WALL_MM, oscillating_fit, wall_need
from camfab.geometry.disc import DiscCam, PitchParts
from camfab.motion.mirror import opposite
from camfab.speed.life_sizing import LifeLimit, LifeSide, life_limit, offset_rolling
from camfab.speed.stress_sizing import StressLimit, plate_sides, stress_limit

if TYPE_CHECKING:
    from camfab.design import Design
    from camfab.motion.program import MotionProgram


@dataclass(frozen=True)
class CamLimits:
    """What one plate is held to: the pressure-angle limit (deg), the curvature margin (mm), the
    flat face's width (mm, or None), whether it is a groove (both walls must be offsets), the
    contact stress and the roller bearing's life (None: not held to one)."""

    pressure_deg: float
    margin: float
    face_width: float | None
    groove: bool
    stress: StressLimit | None = None
    life: LifeLimit | None = None

    def at(self, cam: DiscCam, grid: Grid, suffix: str = "", until: bool = False,
           fine: bool = False, carries: int = 1) -> list[LimitValue]:
        """The limits of *cam* on *grid* (the sizing's finer grid when *fine*); ids end in
        *suffix* (``_b`` for cam b of a pair, which carries the follower where the force
        along its motion is negative: *carries* −1). With *until*, the limits up to the
        first that fails (all a bisection needs)."""
        fol = cam.follower
        theta, motion = grid.theta, grid.motion
        lines = cam.face_lines(theta, motion) if fol.flat else None
        out: list[LimitValue] = []

        def stop() -> bool:
            return until and not out[-1].ok

        parts = cam.pitch_parts(motion) if lines is None else None
        if parts is not None or fol.oscillating:
            angle = (parts.pressure_angle() if parts is not None else
                     cam.pressure_angle(theta, motion, lines))
            phi = np.degrees(np.abs(angle))
            k = int(np.argmax(phi))
            out.append(LimitValue("pressure_angle" + suffix, "pressure angle",
                                  not bool((phi > self.pressure_deg).any()), float(phi[k]),
                                  self.pressure_deg, "deg", "max", _deg(theta[k])))
            if stop():
                return out
        if lines is not None:  # the flat face's envelope: ρ = h + h_ββ
            working = lines.h + lines.h_beta2
            folds = ~(working > 0.0)
            k = int(np.argmin(working))
            out.append(LimitValue("undercut" + suffix, "the flat face's radius of curvature",
                                  not bool(folds.any()), float(working[k]), 0.0, "mm", "min",
                                  _deg(theta[k])))
        else:
            assert parts is not None
            rho = parts.radius()
            radius = fol.radius
            working = rho - radius if radius else rho
            folds = (rho > 0.0) & (rho < radius)
            if self.groove:
                bent = (rho < 0.0) & (-rho < radius)
                k = int(np.argmin(np.abs(rho)))
                out.append(LimitValue("groove" + suffix, "the pitch curve's radius of curvature "
                                      "against the groove's half width",
                                      not bool(folds.any() or bent.any()), float(abs(rho[k])),
                                      radius, "mm", "min", _deg(theta[k])))
            else:
                value, at = _least(theta, rho, rho > 0.0)
                out.append(LimitValue("undercut" + suffix, "the pitch curve's convex radius of "
                                      "curvature against the follower's radius",
                                      not bool(folds.any()), value, radius, "mm", "min", at))
        if stop():
            return out
        if self.margin > 0.0:
            low = (working > 0.0) & (working < self.margin)
            value, at = _least(theta, working, working > 0.0)
            out.append(LimitValue("curvature" + suffix, "the profile's convex radius of curvature",
                                  not bool(low.any() or folds.any()), value, self.margin, "mm",
                                  "min", at))
            if stop():
                return out
        contact = cam.face_contact(theta, motion, lines) if fol.flat else None
        if contact is not None and self.face_width is not None:
            low_mm, high_mm = float(contact.min()), float(contact.max())
            needed = high_mm - low_mm if fol.oscillating else 2.0 * max(abs(low_mm), abs(high_mm))
            out.append(LimitValue("face_width" + suffix, "the face width the contact needs",
                                  self.face_width >= needed, needed, self.face_width, "mm", "max"))
            if stop():
                return out
        if self.stress is not None:
            out.append(self.stress.at(grid, fine, self._sides(cam, parts, working, contact,
                                                              carries), suffix))
            if stop():
                return out
        if self.life is not None and parts is not None:
            out.append(self.life.at(grid, self._rolled(parts, fol.radius, carries), suffix))
        return out

    def _rolled(self, parts: PitchParts, radius: float,
                carries: int) -> list[LifeSide]:
        """The walls a roller of (working) *radius* (mm) rides for its bearing's life, as the
        build's contact has them: the profile, loaded or not, or a groove's inner wall where
        it pushes the follower along its motion and its outer wall where it pulls it back;
        the normal force 1/cos φ, the rolling speed the wall's (mm/rad)."""
        normal = 1.0 / np.cos(parts.pressure_angle())
        speed, rho = np.hypot(parts.d1x, parts.d1y), parts.radius()
        if not self.groove:
            return [LifeSide(carries, normal, offset_rolling(speed, rho, radius))]
        return [LifeSide(carries, normal, offset_rolling(speed, rho, radius), always=False),
                LifeSide(-carries, normal, offset_rolling(speed, rho, -radius), always=False)]

    def _sides(self, cam: DiscCam, parts: PitchParts | None, working: Array,
               contact: Array | None, carries: int) -> list[tuple[int, Array, Array]]:
        """The plate's sides under the follower for the contact stress, as the build's
        contact has them (:meth:`camfab.kinds.disc.PlateResult.contact`): the profile of
        radius *working* (mm) and a groove's outer wall, the normal force 1/cos φ, or for an
        oscillating flat face the arm over the contact's distance along it (*contact*, mm)."""
        fol = cam.follower
        if fol.flat:
            if fol.oscillating:
                assert contact is not None
                with np.errstate(divide="ignore"):
                    normal = fol.arm_length / np.abs(contact)
            else:
                normal = np.ones_like(working)
            pitch = None
        else:
            assert parts is not None
            normal = 1.0 / np.cos(parts.pressure_angle())
            pitch = parts.radius()
        sides = plate_sides(working, normal, fol.radius if self.groove else None, pitch)
        return [(carries * side, curvature, load) for side, curvature, load in sides]


def _deg(theta: float) -> float:
    return math.degrees(float(theta))


def _least(theta: Array, values: Array, where: Array) -> tuple[float | None, float | None]:
    """The smallest of *values* where *where* holds, and its cam angle (deg); None, None when it
    holds nowhere."""
    if not where.any():
        return None, None
    masked = np.where(where, values, np.inf)
    k = int(np.argmin(masked))
    return float(values[k]), _deg(theta[k])


def fit_limits(design: Design, follower: FollowerGeometry, base: float) -> list[LimitValue]:
    """The part's fit on a plate of base radius *base* (mm), as the design file's rules judge it:
    the export tolerance, the bore and keyway inside the base circle, the follower's line inside
    the prime circle, an oscillating arm that reaches it, stays short of 180° and keeps its
    pivot outside the cam."""
    cam = design.cam
    tolerance = design.manufacturing.tolerance
    out = [LimitValue("tolerance", "the export tolerance", base > tolerance, base, tolerance,
                      least=tolerance, of_size=True)]
    if cam.bore is not None:
        need = wall_need(cam.bore)
        out.append(LimitValue("bore", f"a {MIN_WALL_MM:g} mm wall round the bore", base >= need,
                              base, need, least=need, of_size=True))
        if cam.keyway is not None:
            need = wall_need(cam.bore, cam.keyway.depth)
            out.append(LimitValue("keyway", f"a {MIN_WALL_MM:g} mm wall beyond the keyway",
                                  base >= need, base, need, least=need, of_size=True))
    if follower.oscillating:
        broken = oscillating_fit(follower, base, design.program.max_lift)
        out.append(LimitValue("reach", "the arm's reach" if broken is None else broken[1],
                              broken is None))
    elif not follower.flat:
        need = abs(follower.offset) - follower.radius
        out.append(LimitValue("offset", "the follower's line inside the prime circle",
                              base > need, base + follower.radius, abs(follower.offset),
                              least=need))
    return out


def least_fit(design: Design, follower: FollowerGeometry) -> float:
    """The least base radius the part's fit allows (mm), of the limits that bound it below in
    closed form (:func:`fit_limits`; an arm's reach bounds it below as well:
    |pivot_distance − arm_length| < Rp, or 0 < Rb + face_offset for a flat face)."""
    leasts = [limit.least for limit in fit_limits(design, replace(follower, oscillating=False),
                                                  math.inf) if limit.least is not None]
    if follower.oscillating:
        leasts.append(-follower.face_offset if follower.flat else
                      abs(follower.pivot_distance - follower.arm_length) - follower.radius)
    return max(leasts) * (1.0 + 1e-12) + 1e-12


def lift_mm(design: Design, program: MotionProgram) -> float:
    """The follower's largest lift at its trace point (mm)."""
    fol = design.follower
    return program.max_lift * ((fol.arm_length or 0.0) if fol.oscillating else 1.0)


def plate_problem(design: Design, follower: FollowerGeometry, grid_pair: tuple[Grid, Grid],
                  clearance: float = 0.0, groove: bool = False,
                  partner: bool = False) -> SizeProblem:
    """The sizing of a plate cam's base radius: a disc cam's (its follower *follower*, the
    radius grown by *clearance* mm for a groove's inner wall), with both walls of a *groove*,
    or with cam b of a conjugate pair (*partner*), its limits measured on *grid_pair* (the
    build's grid, and with the finer one)."""
    face_width = design.follower.face_width
    stress = stress_limit(design, grid_pair)
    rules = CamLimits(math.degrees(design.pressure_angle_limit), design.min_profile_radius,
                      face_width, groove, stress, life_limit(design, grid_pair))
    working = replace(follower, radius=follower.radius + clearance)
    sigma = design.cam.sigma
    pair_grids = grids(opposite(design.program)) if partner else None

    def evaluate(base: float, fine: bool, until: bool = False) -> list[LimitValue]:
        fit = fit_limits(design, working, base)
        if not all(limit.ok for limit in fit):
            return fit
        cam = DiscCam(working, base, sigma)
        out = [*fit, *rules.at(cam, grid_pair[fine], until=until, fine=fine)]
        if partner and not (until and not passes(out)):
            assert pair_grids is not None
            out += _partner_limits(design, cam, rules, pair_grids[fine], until, fine)
        return out

    low = least_fit(design, working)
    return SizeProblem("base_radius", evaluate, low,
                       low + SEARCH_FACTOR * lift_mm(design, design.program))


def _partner_limits(design: Design, cam_a: DiscCam, rules: CamLimits, grid: Grid,
                    until: bool, fine: bool) -> list[LimitValue]:
    """Cam b of a conjugate pair whose cam a is *cam_a*: a base circle round the bore, and the
    limits of a plate."""
    from camfab.geometry.conjugate import partner_base_radius, partner_cam

    need = wall_need(design.cam.bore or 0.0)
    base_b = partner_base_radius(design, cam_a)
    fit = LimitValue("partner_b", "cam b's base circle round the bore", base_b >= need, base_b,
                     need)
    if not fit.ok:
        return [fit]
    cam_b, _ = partner_cam(design, cam_a)
    return [fit, *rules.at(cam_b, grid, "_b", until, fine, carries=-1)]
