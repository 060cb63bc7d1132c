"""Checks of a drum cam's groove: pressure angle (judged at the floor, where it is steepest) and
the developed curvature the roller must follow (the ``groove`` check).

Lengths are millimetres and angles degrees in the findings.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camfab.analysis.cam_checks import fmt, where
from camfab.analysis.findings import Finding, listed
from camfab.angles import Extreme, extreme, ranges_deg
from camfab.design import Design
from camfab.geometry.drum import DrumDense


@dataclass(frozen=True)
class DrumNumbers:
    """The key numbers of a drum cam (mm, deg): the pressure angle at the floor, the mean
    (pitch) and the outer radius, the floor's per segment, and the smallest developed radius of
    curvature of the pitch curve anywhere in the groove (and at which radius)."""

    root_pressure: Extreme
    pitch_pressure: Extreme
    outer_pressure: Extreme
    segment_pressure: list[Extreme]
    min_developed_radius: Extreme
    min_developed_radius_at_mm: float | None


def drum_numbers(dense: DrumDense, segment_count: int) -> DrumNumbers:
    """Extremes of pressure angle and developed curvature."""
    theta = dense.theta
    phi = np.degrees(np.abs(dense.pressure_angle))
    pitch = np.degrees(np.abs(dense.drum.pressure_angle(dense.motion[1], dense.drum.pitch)))
    size = np.abs(dense.developed_radius)
    row, col = np.unravel_index(int(np.argmin(size)), size.shape)
    smallest = (Extreme(None, None) if not np.isfinite(size[row, col]) else
                Extreme(float(size[row, col]), math.degrees(float(theta[col]))))
    return DrumNumbers(
        root_pressure=extreme(theta, phi[0], largest=True),
        pitch_pressure=extreme(theta, pitch, largest=True),
        outer_pressure=extreme(theta, phi[-1], largest=True),
        segment_pressure=[extreme(theta, phi[0], dense.segment == i, largest=True)
                          for i in range(segment_count)],
        min_developed_radius=smallest,
        min_developed_radius_at_mm=None if smallest.value is None else float(dense.radii[row]),
    )


def drum_pressure_finding(design: Design, dense: DrumDense, numbers: DrumNumbers) -> Finding:
    """|φ| at the groove's floor (tan φ = s′/r, steepest at the smallest radius) against
    ``limits.pressure_angle``."""
    limit = math.degrees(design.pressure_angle_limit)
    root = numbers.root_pressure
    value = root.value or 0.0
    over = ranges_deg(dense.theta, np.degrees(np.abs(dense.pressure_angle[0])) > limit)
    also = (f"(at the pitch radius {fmt(numbers.pitch_pressure.value or 0.0)}°, at the surface "
            f"{fmt(numbers.outer_pressure.value or 0.0)}°)")
    if not over:
        return Finding("pressure_angle", True, "error",
                       f"largest pressure angle at the groove's floor {fmt(value)}° at "
                       f"{fmt(root.at_deg or 0.0)}° {also}, within the limit {fmt(limit)}°",
                       value, limit, "deg", at_deg=root.at_deg)
    return Finding(
        "pressure_angle", False, "error",
        f"pressure angle at the groove's floor reaches {fmt(value)}° at "
        f"{fmt(root.at_deg or 0.0)}° {also}, over the limit {fmt(limit)}° at {where(over)}: "
        f"the roller binds in the groove; a larger drum radius or a longer rise or return "
        f"lowers it", value, limit, "deg", over, at_deg=root.at_deg)


def groove_finding(design: Design, dense: DrumDense, numbers: DrumNumbers) -> Finding:
    """Both walls must bend less sharply than the roller: |ρ(r)| of the developed pitch curve
    above the roller radius (plus half the clearance) at every radius of the groove."""
    roller = dense.drum.roller
    tight = np.any(np.abs(dense.developed_radius) <= roller, axis=0)
    ranges = ranges_deg(dense.theta, tight)
    smallest = numbers.min_developed_radius
    if smallest.value is None:
        return Finding("groove", True, "error", "the groove runs straight round the drum",
                       None, roller, "mm")
    at = (f"{fmt(smallest.value)} mm at {fmt(smallest.at_deg or 0.0)}° (radius "
          f"{fmt(numbers.min_developed_radius_at_mm or 0.0)} mm)")
    if not ranges:
        return Finding("groove", True, "error",
                       f"the developed groove's smallest radius of curvature {at} is larger than "
                       f"the roller's {fmt(roller)} mm", smallest.value, roller, "mm")
    return Finding(
        "groove", False, "error",
        f"the developed groove bends tighter than the roller: its radius of curvature falls to "
        f"{at}, under the roller's {fmt(roller)} mm, at {where(ranges)}; the wall on the "
        f"inside of the bend folds over and the roller cannot follow it: a larger drum radius, "
        f"a longer segment or a smaller roller avoids it", smallest.value, roller, "mm", ranges)


def corner_finding(design: Design, dense: DrumDense) -> Finding | None:
    """At a velocity step the groove has a corner on the inside of the bend, where the walls
    swept before and after the step meet further from the roller's axis than its radius: the
    exact groove (every position of the roller) leaves it room there
    (:func:`~camfab.geometry.drum_mesh.corner_play`), and the middle of that room, which the
    read-back takes for the follower's place, lies half of it off the design. Within the
    tolerance the groove holds the motion; beyond it no groove does. None for a motion whose
    velocity has no step."""
    from camfab.geometry.drum_mesh import corner_play

    tolerance = design.manufacturing.tolerance
    plays = corner_play(dense.drum, design.program)
    if not plays:
        return None
    off = [(math.degrees(angle), play / 2.0) for angle, play in plays]
    worst_at, worst = max(off, key=lambda item: item[1])
    over = tuple((a, a) for a, half in off if half > tolerance)
    said = (f"at the velocity steps ({listed([f'{fmt(a)}°' for a, _ in off])}) the groove has "
            f"a corner on the inside of the bend that the roller cannot fill: the exact groove "
            f"lets it move up to {fmt(2.0 * worst)} mm there, and the middle of its room lies "
            f"{fmt(worst)} mm off the design at {fmt(worst_at)}°")
    if not over:
        return Finding("corner", True, "error", f"{said}, within the tolerance "
                       f"{fmt(tolerance)} mm", worst, tolerance, "mm")
    return Finding("corner", False, "error",
                   f"{said}, over the tolerance {fmt(tolerance)} mm: no groove holds this motion "
                   f"within the tolerance there; a motion law without a velocity step "
                   f"(modified-uniform-velocity, cycloidal, ...) makes it buildable, a larger "
                   f"drum or a smaller roller makes the corner shallower", worst, tolerance,
                   "mm", over)


def drum_findings(design: Design, dense: DrumDense, numbers: DrumNumbers) -> list[Finding]:
    """Every geometric check of a drum cam."""
    corner = corner_finding(design, dense)
    return [drum_pressure_finding(design, dense, numbers),
            groove_finding(design, dense, numbers), *([corner] if corner else [])]
