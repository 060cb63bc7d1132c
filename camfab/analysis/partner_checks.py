"""Checks of the cams that hold their follower without a spring: the conjugate pair's second cam
(each cam is checked on its own, THEORY §F) and the hold of both contacts (``hold``: no gap, no
interference over the whole cycle), for conjugate and constant-breadth cams.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from camfab.analysis.cam_checks import cam_findings, cam_numbers, fmt, where
from camfab.analysis.findings import Finding
from camfab.angles import extreme, ranges_deg
from camfab.geometry.conjugate import Hold, breadth, hold, partner_cam
from camfab.geometry.disc_geometry import VERIFY_STEP, plate_geometry
from camfab.motion.mirror import opposite
from camfab.motion.program import cycle_angles

if TYPE_CHECKING:
    from camfab.analysis.cam_checks import CamNumbers
    from camfab.analysis.record import Analysis
    from camfab.geometry.disc_geometry import DiscGeometry
    from camfab.geometry.groove import WallContact
    from camfab.motion.program import MotionProgram

@dataclass(frozen=True)
class Holder:
    """What holds the follower on its other side, as the checks and the report name it."""

    #: What the hold check says holds it ("the two rollers", "the yoke", ...).
    what: str
    #: The report's geometry key of the spacing: mm, or degrees for an angle.
    spacing_key: str
    #: The contact carrying the follower when s″ pushes it away from the cam centre (+1) and
    #: when it pulls it back (−1).
    outward: str
    inward: str
    #: What the hold of the files read back runs over.
    outlines: str
    #: True when the spacing is an angle (rad): the bell-crank's arms.
    angular: bool = False


#: A conjugate pair's translating follower, its two rollers on one slide.
ROLLERS = Holder("the two rollers", "roller_spacing_mm", "cam a", "cam b",
                 "the CUT outlines read back from the DXF files")
#: An oscillating conjugate pair's bell-crank: its arms an angle apart.
BELL_CRANK = Holder("the bell-crank's two rollers", "arm_angle_deg", "cam a", "cam b",
                    "the CUT outlines read back from the DXF files", angular=True)
#: A constant-breadth cam's yoke between two parallel faces, or two rollers.
YOKE_FACES = Holder("the yoke", "breadth_mm", "upper face", "lower face",
                    "the CUT outlines read back from the DXF")
YOKE_ROLLERS = Holder("the yoke", "breadth_mm", "upper roller", "lower roller",
                      "the CUT outlines read back from the DXF")


@dataclass(frozen=True)
class Partner:
    """What holds a positive-drive plate cam's follower on the other side.

    Attributes
    ----------
    holder
        What holds the follower on the other side: a conjugate pair's second cam and roller
        (:data:`ROLLERS`, :data:`BELL_CRANK`), or the same cam half a turn on under a
        constant-breadth cam's yoke (:data:`YOKE_FACES`, :data:`YOKE_ROLLERS`).
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
    """

    holder: Holder
    spacing: float
    hold: Hold
    geometry: DiscGeometry | None = None
    program: MotionProgram | None = None
    numbers: CamNumbers | None = None
    mirror: bool = False
    contact: WallContact | None = None

    @property
    def sides(self) -> dict[int, str]:
        """The contact carrying the follower by the sign of s″: +1 pushes it away from the cam
        centre, −1 pulls it back."""
        return {1: self.holder.outward, -1: self.holder.inward}

    def report_geometry(self) -> dict[str, Any]:
        """The JSON report's geometry keys of the second contact (mm, deg)."""
        holder = self.holder
        out: dict[str, Any] = {
            holder.spacing_key: math.degrees(self.spacing) if holder.angular else self.spacing}
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


#: Ids of the geometric checks run on each cam of a conjugate pair.
PER_CAM_CHECKS = ("pressure_angle", "undercut", "curvature", "face_width", "cutter", "kerf")


def _load_contact(analysis: Analysis) -> WallContact:
    """Which side carries the follower: as a groove's walls, by the sign of its
    acceleration."""
    from camfab.geometry.groove import wall_contact

    fol = analysis.design.follower
    metres = (fol.arm_length or 0.0) / 1000.0 if fol.oscillating else 1e-3
    return wall_contact(analysis.program, fol.mass, analysis.design.cam.omega, metres)


def breadth_partner(analysis: Analysis) -> tuple[Partner, list[Finding]]:
    """What holds the follower on its other side in *analysis* of a constant-breadth cam (its
    own outline half a turn on, under the yoke's other face or roller), and the findings with
    the ``hold`` check."""
    geom = analysis.geometry
    assert geom is not None
    theta = cycle_angles(VERIFY_STEP)
    spacing = breadth(geom.cam, analysis.program.max_lift)
    held = hold(theta, spacing, (geom.profile, geom.cam), (geom.profile, geom.cam), math.pi)
    holder = YOKE_FACES if geom.cam.follower.flat else YOKE_ROLLERS
    partner = Partner(holder, spacing, held, contact=_load_contact(analysis))
    return partner, [*analysis.findings, hold_finding(holder, partner.hold, spacing,
                                                      tolerance_of(analysis))]


def conjugate_partner(analysis: Analysis) -> tuple[Partner, list[Finding]]:
    """What holds the follower on its other side in *analysis* of a conjugate cam (cam b and
    its roller), and the findings with each cam's checks and the ``hold`` check."""
    design, geom = analysis.design, analysis.geometry
    assert geom is not None
    theta = cycle_angles(VERIFY_STEP)
    contact = _load_contact(analysis)
    cam_b, spacing = partner_cam(design, geom.cam)
    program_b = opposite(analysis.program)
    geom_b = plate_geometry(cam_b, program_b, design.manufacturing.tolerance)
    numbers_b = cam_numbers(geom_b, len(program_b.segments))
    held = hold(theta, spacing, (geom.profile, geom.cam), (geom_b.profile, cam_b))
    partner = Partner(BELL_CRANK if design.follower.oscillating else ROLLERS, spacing, held,
                      geom_b, program_b, numbers_b, mirror=design.follower.oscillating,
                      contact=contact)
    findings_a: list[Finding] = []
    others: list[Finding] = []
    for f in analysis.findings:
        (findings_a if f.id in PER_CAM_CHECKS else others).append(f)
    findings_a = [replace(f, message="cam a: " + f.message) for f in findings_a]
    findings_b = [replace(f, id=f.id + "_b", message="cam b: " + f.message)
                  for f in cam_findings(design, geom_b, numbers_b, program_b)]
    found = [*findings_a, *findings_b,
             hold_finding(partner.holder, held, spacing, tolerance_of(analysis)), *others]
    return partner, found


def tolerance_of(analysis: Analysis) -> float:
    """The hold's allowance (mm): each contact's cam may stray the export tolerance, so the two
    together twice that."""
    return 2.0 * analysis.design.manufacturing.tolerance


def hold_finding(holder: Holder, held: Hold, spacing: float, tolerance: float,
                 checked_on: str = "the cam outlines as sampled") -> Finding:
    """Do the two contacts hold the follower, without gap or interference, within *tolerance*
    (mm)? *spacing* is the rollers' or faces' distance (mm), or the bell-crank's arms' angle
    (rad)."""
    what = holder.what
    apart = (f"{fmt(math.degrees(spacing))}° apart" if holder.angular
             else f"{fmt(spacing)} mm apart")
    ok = held.worst <= tolerance
    detail = (f"{what} ({apart}) run over {checked_on}: largest gap "
              f"{fmt(held.max_gap)} mm, largest interference {fmt(held.max_interference)} mm "
              f"(allowed {fmt(tolerance)} mm: each cam within the export tolerance)")
    if ok:
        return Finding("hold", True, "error",
                       f"the follower is held on both sides over the whole cycle: {detail}",
                       held.worst, tolerance, "mm")
    off = ranges_deg(held.theta, np.abs(held.gap) > tolerance)
    cause = ("an undercut or a cutter that cannot follow the profile changes one contact, "
             "not the other")
    return Finding("hold", False, "error",
                   f"the follower is not held at {where(off)} (worst at "
                   f"{fmt(held.worst_at_deg)}°): {detail}; {cause}", held.worst, tolerance, "mm",
                   off)


def read_back_hold(analysis: Analysis, held: Hold) -> Finding:
    """The ``hold`` check of the cam outlines read back from the DXF files."""
    partner = analysis.partner
    assert partner is not None
    return hold_finding(partner.holder, held, partner.spacing, tolerance_of(analysis),
                        partner.holder.outlines)
