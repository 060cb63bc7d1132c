"""Checks of the cams that hold their follower without a spring: the conjugate pair's second cam
(each cam is checked on its own, THEORY §F) and the hold of both contacts (``hold``: no gap, no
interference over the whole cycle), for conjugate and constant-breadth cams.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from camfab.analysis.cam_checks import cam_findings, cam_numbers, fmt, where
from camfab.analysis.findings import Finding
from camfab.analysis.ranges import ranges_deg
from camfab.geometry.conjugate import Hold, Partner, breadth, hold, partner_cam
from camfab.geometry.disc_geometry import VERIFY_STEP, plate_geometry
from camfab.motion.mirror import opposite
from camfab.motion.program import cycle_angles

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.geometry.groove import WallContact

#: Ids of the geometric checks run on each cam of a conjugate pair.
PER_CAM_CHECKS = ("pressure_angle", "undercut", "curvature", "face_width", "cutter")


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
    design, geom = analysis.design, analysis.geometry
    assert geom is not None
    theta = cycle_angles(VERIFY_STEP)
    spacing = breadth(geom.cam, analysis.program.max_lift)
    held = hold(theta, spacing, (geom.profile, geom.cam), (geom.profile, geom.cam), math.pi)
    partner = Partner("constant-breadth", spacing, held, contact=_load_contact(analysis),
                      flat=geom.cam.follower.flat)
    return partner, [*analysis.findings, hold_finding(design.cam.type, partner.hold,
                                                      spacing, tolerance_of(analysis))]


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
    partner = Partner("conjugate", spacing, held, geom_b, program_b, numbers_b,
                      mirror=design.follower.oscillating, contact=contact)
    findings_a: list[Finding] = []
    others: list[Finding] = []
    for f in analysis.findings:
        (findings_a if f.id in PER_CAM_CHECKS else others).append(f)
    findings_a = [replace(f, message="cam a: " + f.message) for f in findings_a]
    findings_b = [replace(f, id=f.id + "_b", message="cam b: " + f.message)
                  for f in cam_findings(design, geom_b, numbers_b, program_b)]
    found = [*findings_a, *findings_b,
             hold_finding(partner.hold_kind, held, spacing, tolerance_of(analysis)), *others]
    return partner, found


def tolerance_of(analysis: Analysis) -> float:
    """The hold's allowance (mm): each contact's cam may stray the export tolerance, so the two
    together twice that."""
    return 2.0 * analysis.design.manufacturing.tolerance


def hold_finding(kind: str, held: Hold, spacing: float, tolerance: float,
                 checked_on: str = "the cam outlines as sampled") -> Finding:
    """Do the two contacts hold the follower, without gap or interference, within *tolerance*
    (mm)? *spacing* is the rollers' or faces' distance (mm)."""
    what = ("the two rollers" if kind == "conjugate" else "the yoke")
    apart = (f"{fmt(math.degrees(spacing))}° apart" if kind == "bell-crank"
             else f"{fmt(spacing)} mm apart")
    if kind == "bell-crank":
        what = "the bell-crank's two rollers"
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
    return hold_finding(partner.hold_kind, held, partner.spacing, tolerance_of(analysis),
                        "the CUT outlines read back from the DXF" +
                        (" files" if partner.kind == "conjugate" else ""))
