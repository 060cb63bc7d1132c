"""Checks of a globoidal cam's groove (THEORY §H): the pressure angle along the roller's contact
line, the undercut of either flank (the largest roller the flanks take without folding), and
the groove's fit in the blank.

Lengths are millimetres and angles degrees in the findings.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camfab.analysis.cam_checks import fmt, where
from camfab.analysis.findings import Finding
from camfab.angles import Extreme, extreme, ranges_deg
from camfab.arrays import Array, Index
from camfab.design import Design
from camfab.geometry.globoid import undercut_radii
from camfab.geometry.globoid_cam import ANALYSIS_STEP, GloboidCam, groove_extent
from camfab.motion.program import MotionProgram

#: Cam-angle step (rad) of the differences the undercut's regularity is taken from.
UNDERCUT_STEP = 1e-4


@dataclass(frozen=True)
class GloboidDense:
    """The groove on the analysis grid: cam angles (rad, segment by segment, joints twice),
    their segment, the motion (4, N: the arm's swing per radian), the distances along the
    roller inside the groove (mm) and the pressure angle (rad) at each of them (rows) and
    cam angle (columns)."""

    blank: GloboidCam
    segment: Index
    theta: Array
    motion: Array
    ells: Array
    pressure_angle: Array
    #: The largest roller radius neither flank folds with, at each cam angle over the groove
    #: from the blank's surface to its floor (mm; inf where none folds).
    undercut_radius: Array


def globoid_dense(blank: GloboidCam, program: MotionProgram) -> GloboidDense:
    """The pressure angle along the contact line and the undercut limit over the cycle."""
    segment, theta, m = program.segment_grid(ANALYSIS_STEP)
    g = blank.follower
    ells = blank.contact()
    phi = g.pressure_angle(ells[:, None], g.rest + m[0][None, :], m[1][None, :])
    deep = np.linspace(blank.surface, blank.floor, 7)[:, None]
    h = UNDERCUT_STEP
    limit = undercut_radii(g, theta[None, :], deep, m[:, None, :],
                           program.evaluate(theta + h)[:, None, :],
                           program.evaluate(theta - h)[:, None, :], h).min(axis=0)
    return GloboidDense(blank, segment, theta, m, ells, phi, limit)


@dataclass(frozen=True)
class GloboidNumbers:
    """The key numbers of a globoidal cam (mm, deg): the largest pressure angle along the
    contact line (and the distance from the pivot where it occurs), per segment too; the
    largest roller the flanks take without undercutting (inf: any); and the groove's fit:
    the least distance of its floor and of its flanks from the cam axis, its reach along
    the axis either side of the middle, and the walls left at the blank's ends."""

    pressure: Extreme
    pressure_at_mm: float | None
    segment_pressure: list[Extreme]
    undercut_radius: float
    floor_radius: float
    flank_radius: float
    reach_z: float
    end_wall: float


def globoid_numbers(dense: GloboidDense, program: MotionProgram) -> GloboidNumbers:
    """Extremes of the pressure angle, the undercut limit and the groove's fit."""
    blank, theta = dense.blank, dense.theta
    phi = np.degrees(np.abs(dense.pressure_angle))
    along = phi.max(axis=0)
    pressure = extreme(theta, along, largest=True)
    row = int(np.argmax(phi[:, int(np.argmax(along))]))
    floor_r, flank_r, reach = groove_extent(blank, program)
    return GloboidNumbers(
        pressure=pressure,
        pressure_at_mm=float(dense.ells[row]),
        segment_pressure=[extreme(theta, along, dense.segment == i, largest=True)
                          for i in range(len(program.segments))],
        undercut_radius=float(np.min(dense.undercut_radius)),
        floor_radius=floor_r,
        flank_radius=flank_r,
        reach_z=reach,
        end_wall=blank.width / 2.0 - reach,
    )


def pressure_finding(design: Design, dense: GloboidDense, numbers: GloboidNumbers) -> Finding:
    """The largest |α| along the roller's contact line (tan α = |ψ′|ℓ/|C − ℓ cos ψ|) against
    ``limits.pressure_angle``."""
    limit = math.degrees(design.pressure_angle_limit)
    worst = numbers.pressure
    value = worst.value or 0.0
    over = ranges_deg(dense.theta, np.degrees(np.abs(dense.pressure_angle)).max(axis=0) > limit)
    at = (f"{fmt(value)}° at {fmt(worst.at_deg or 0.0)}°, {fmt(numbers.pressure_at_mm or 0.0)} "
          f"mm from the pivot along the roller")
    if not over:
        return Finding("pressure_angle", True, "error",
                       f"largest pressure angle along the roller's contact line {at}, within "
                       f"the limit {fmt(limit)}°", value, limit, "deg", at_deg=worst.at_deg)
    return Finding("pressure_angle", False, "error",
                   f"pressure angle along the roller's contact line reaches {at}, over the "
                   f"limit {fmt(limit)}° at {where(over)}: the roller binds in the groove; a "
                   "longer rise or return, or the roller's path farther from the cam axis (a "
                   "larger |pivot_distance − arm_length|), lowers it", value, limit, "deg",
                   over, at_deg=worst.at_deg)


def undercut_finding(dense: GloboidDense, numbers: GloboidNumbers) -> Finding:
    """The roller (its radius and half the clearance) must be smaller than the largest one the
    flanks take without folding."""
    wall = dense.blank.follower.radius
    limit = numbers.undercut_radius
    if not math.isfinite(limit):
        return Finding("undercut", True, "error", "neither flank folds for any roller radius",
                       wall, None, "mm")
    folds = ranges_deg(dense.theta, dense.undercut_radius <= wall)
    if not folds:
        return Finding("undercut", True, "error",
                       f"neither flank is undercut: the roller's {fmt(wall)} mm (its radius and "
                       f"half the clearance) is under the {fmt(limit)} mm at which a flank "
                       "would fold", wall, limit, "mm")
    return Finding("undercut", False, "error",
                   f"a flank is undercut: the roller's {fmt(wall)} mm (its radius and half the "
                   f"clearance) reaches the {fmt(limit)} mm at which the flank folds over "
                   f"itself at {where(folds)}, and the roller cannot follow it; a smaller "
                   "roller or a gentler motion avoids it", wall, limit, "mm", folds)


def fit_finding(design: Design, numbers: GloboidNumbers) -> Finding:
    """The groove inside the blank: its floor's least distance from the cam axis (and the
    bore's), and the walls left at the blank's ends (the design file's rules require 1 mm of
    each; this reports what is left)."""
    bore = (design.cam.bore or 0.0) / 2.0
    nearest = min(numbers.floor_radius, numbers.flank_radius)  # the floor or its corners
    inside = nearest - bore
    message = (f"the groove fits the blank: its floor stays {fmt(nearest)} mm from "
               f"the cam axis ({fmt(inside)} mm of wall {'over the bore' if bore else 'to it'}), "
               f"its flanks reach z = ±{fmt(numbers.reach_z)} mm, leaving "
               f"{fmt(numbers.end_wall)} mm at the blank's ends")
    least = min(inside, numbers.end_wall)
    return Finding("groove", True, "error", message, least, None, "mm")


def globoid_findings(design: Design, dense: GloboidDense,
                     numbers: GloboidNumbers) -> list[Finding]:
    """Every geometric check of a globoidal cam."""
    return [pressure_finding(design, dense, numbers), undercut_finding(dense, numbers),
            fit_finding(design, numbers)]
