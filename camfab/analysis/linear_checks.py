"""Checks of a linear cam's geometry: pressure angle, undercut, curvature margin, a milling
cutter's reach, a laser beam's; its key numbers and the report's geometry section.

Ranges are degrees of the cycle angle θ = 360°·x/stroke (a stroke is one cycle), as for every
other cam; the messages also give them as travel in millimetres. Lengths are millimetres and
angles degrees whatever the design's units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from camfab.analysis.cam_checks import CurveNumbers, curve_extremes, fmt, where
from camfab.analysis.findings import Finding, listed
from camfab.angles import Extreme, Range, merge, ranges_deg
from camfab.geometry.linear import LinearGeometry

if TYPE_CHECKING:
    from camfab.design import Design


@dataclass(frozen=True)
class LinearNumbers(CurveNumbers):
    """The key numbers of a linear cam (mm, deg of the cycle): a plate cam's, and the plate's
    height."""

    max_height_mm: float


def linear_numbers(geom: LinearGeometry, segment_count: int) -> LinearNumbers:
    """Extremes of curvature and pressure angle, the plate's height and the undercut ranges."""
    dense = geom.dense
    theta = dense.theta
    working = geom.working
    within = (working.theta >= 0.0) & (working.theta < 2.0 * math.pi)
    folds = ranges_deg(theta, geom.folds)
    cut = ranges_deg(working.theta[within], geom.cut[within])
    return LinearNumbers(
        max_height_mm=float(np.max(geom.outline_points()[:, 1])),
        undercut_ranges=merge([*folds, *cut]),
        fold_ranges=merge(list(folds)),
        cut_ranges=merge(list(cut)),
        **curve_extremes(theta, dense.pitch.radius, dense.working.radius, geom.folds,
                         dense.pressure_angle, dense.segment, segment_count),
    )


def travel_mm(stroke: float, angle_deg: float) -> float:
    """The travel (mm) at a cycle angle (deg): a stroke is 360°."""
    return angle_deg / 360.0 * stroke


def where_travel(stroke: float, ranges: tuple[Range, ...]) -> str:
    """*ranges* (deg of the cycle) as degrees with their travel in mm."""
    if not ranges:
        return where(ranges)
    parts = []
    for a, b in ranges:
        mm_a, mm_b = travel_mm(stroke, a), travel_mm(stroke, b)
        if fmt(a) == fmt(b):
            parts.append(f"{fmt(a)}° (travel {fmt(mm_a)} mm)")
        else:
            parts.append(f"{fmt(a)}°–{fmt(b)}° (travel {fmt(mm_a)}–{fmt(mm_b)} mm)")
    return listed(parts)


def _at(stroke: float, at_deg: float | None) -> str:
    deg = at_deg or 0.0
    return f"{fmt(deg)}° (travel {fmt(travel_mm(stroke, deg))} mm)"


def pressure_angle_finding(design: Design, geom: LinearGeometry,
                           numbers: LinearNumbers) -> Finding:
    """|φ| against ``limits.pressure_angle``; φ = atan(ds/dx)."""
    limit = math.degrees(design.pressure_angle_limit)
    worst = numbers.pressure_angle
    value = worst.value or 0.0
    stroke = geom.cam.stroke
    dense = geom.dense
    over = ranges_deg(dense.theta, np.degrees(np.abs(dense.pressure_angle)) > limit)
    if not over:
        return Finding("pressure_angle", True, "error",
                       f"largest pressure angle {fmt(value)}° at {_at(stroke, worst.at_deg)}, "
                       f"within the limit {fmt(limit)}°", value, limit, "deg",
                       at_deg=worst.at_deg)
    slope = math.tan(design.pressure_angle_limit)
    return Finding(
        "pressure_angle", False, "error",
        f"pressure angle reaches {fmt(value)}° at {_at(stroke, worst.at_deg)}, over the limit "
        f"{fmt(limit)}° at {where_travel(stroke, over)}: tan φ = ds/dx, so a longer travel for "
        f"the rise or return lowers it (the slope must stay under {fmt(slope)})",
        value, limit, "deg", over, at_deg=worst.at_deg)


def undercut_finding(design: Design, geom: LinearGeometry, numbers: LinearNumbers) -> Finding:
    """Does the roller's envelope fold over (or cross itself)? With the lift error it causes."""
    radius = geom.cam.radius
    stroke = geom.cam.stroke
    smallest = numbers.pitch_min_convex
    value = smallest.value
    ranges = numbers.undercut_ranges
    if not geom.undercut:
        if value is None:
            message = "the pitch curve has no convex bend: nothing for the follower to undercut"
        elif radius == 0.0:
            message = (f"a knife edge follows any bend (the pitch curve's smallest convex radius "
                       f"is {fmt(value)} mm at {_at(stroke, smallest.at_deg)})")
        else:
            message = (f"the pitch curve's smallest convex radius {fmt(value)} mm at "
                       f"{_at(stroke, smallest.at_deg)} is larger than the roller radius "
                       f"{fmt(radius)} mm")
        return Finding("undercut", True, "error", message, value, radius, "mm")
    motion = (f"the plate that is really cut moves the follower up to {fmt(geom.lift.max_mm)} "
              f"mm off the design at {_at(stroke, geom.lift.at_deg)}")
    departs = ("" if not numbers.cut_ranges else
               f"; the plate as cut, its loops trimmed away, departs from the design at "
               f"{where_travel(stroke, numbers.cut_ranges)}")
    if geom.folds.any() and value is not None:
        cause = (f"the roller radius {fmt(radius)} mm exceeds the pitch curve's convex radius "
                 f"of curvature (down to {fmt(value)} mm) at "
                 f"{where_travel(stroke, numbers.fold_ranges)}: the envelope folds over "
                 f"there{departs}")
        need = (f"a roller radius below {fmt(value)} mm or a longer travel for the rise or "
                f"return avoids it")
    else:
        cause = (f"the roller's envelope crosses itself: the roller cannot follow a sharp crest "
                 f"of the pitch curve (a velocity step makes one) and rolls over the plate's "
                 f"corner there instead{departs}")
        need = "a motion law without a velocity step avoids it"
    return Finding("undercut", False, "error", f"{cause}; {motion}; {need}", value, radius, "mm",
                   ranges)


def curvature_finding(design: Design, geom: LinearGeometry,
                      numbers: LinearNumbers) -> Finding | None:
    """The convex working curve against ``limits.min_radius_of_curvature`` (when set)."""
    margin = design.min_profile_radius
    if margin <= 0.0:
        return None
    smallest = numbers.profile_min_convex
    value = smallest.value
    dense = geom.dense
    rw = dense.working.radius
    low = ranges_deg(dense.theta, (rw > 0) & (rw < margin))
    ok = not low and not geom.undercut
    stroke = geom.cam.stroke
    shape = ("the profile has no convex part" if value is None else
             f"smallest convex radius of the profile {fmt(value)} mm at "
             f"{_at(stroke, smallest.at_deg)}")
    verdict = (f"at least {fmt(margin)} mm" if ok else
               f"below the required {fmt(margin)} mm at {where_travel(stroke, low)}")
    return Finding("curvature", ok, "error", f"{shape}, {verdict}", value, margin, "mm", low)


def cutter_finding(design: Design, geom: LinearGeometry,
                   numbers: LinearNumbers) -> Finding | None:
    """Can a milling cutter of ``cutter_radius``, running along the plate's edge, follow its
    hollows? A smooth hollow's radius is the working curve's concave radius; where the velocity
    steps up (the foot of a uniform-velocity rise) the hollow is the roller's own radius, or a
    sharp corner for a knife."""
    radius = design.manufacturing.cutter_radius
    if radius <= 0.0:
        return None
    dense, cam = geom.dense, geom.cam
    rw = dense.working.radius
    tight = (rw < 0) & ~geom.folds & (-rw < radius)
    spots = list(ranges_deg(dense.theta, tight))
    smallest = [float(np.min(-rw[tight]))] if tight.any() else []
    if cam.radius < radius:
        for joint in design.program.joints():
            if joint.right[1] > joint.left[1] + 1e-12 * max(1.0, abs(joint.left[1])):
                deg = math.degrees(joint.angle)
                spots.append((deg, deg))
                smallest.append(cam.radius)
    where_ = merge(spots)
    stroke = cam.stroke
    if not where_:
        worst = numbers.profile_min_concave
        shape = (f"smallest concave radius {fmt(worst.value)} mm at {_at(stroke, worst.at_deg)}"
                 if worst.value is not None else "the plate's edge has no hollow")
        return Finding("cutter", True, "error", f"a cutter of radius {fmt(radius)} mm follows "
                       f"the whole plate ({shape})", worst.value, radius, "mm")
    value = min(smallest)
    cause = (f"a hollow's radius falls to {fmt(value)} mm" if value > 0 else
             "it has a sharp hollow (a velocity step of the motion makes one)")
    advice = (f"a cutter radius below {fmt(value)} mm cuts it" if value > 0 else
              "a motion law without a velocity step, or finishing the hollow by hand, cuts it")
    return Finding("cutter", False, "error",
                   f"a cutter of radius {fmt(radius)} mm cannot follow the plate's edge at "
                   f"{where_travel(stroke, where_)}: {cause}; {advice}", value, radius, "mm",
                   where_)


def kerf_finding(design: Design, geom: LinearGeometry,
                 numbers: LinearNumbers) -> Finding | None:
    """Can a laser's beam, ``kerf`` wide (running outside the plate, its radius half the kerf),
    cut the plate's edge? A sharp hollow (a knife's velocity step makes one) or a concave radius
    under the beam's is rounded to the beam's radius; the follower run over the plate as cut
    says how far it moves off the design there (see
    :func:`camfab.analysis.cam_checks.tool_cut`)."""
    from camfab.analysis.cam_checks import tool_cut, tool_finding

    kerf = design.manufacturing.kerf
    if kerf <= 0.0:
        return None
    stroke = geom.cam.stroke
    return tool_finding("kerf", f"a beam of kerf {fmt(kerf)} mm (radius {fmt(kerf / 2.0)} mm)",
                        kerf / 2.0, tool_cut(design, geom, kerf / 2.0), numbers, scale=2.0,
                        what="kerf", made="cut", spots=lambda r: where_travel(stroke, r),
                        at=lambda deg: _at(stroke, deg))


def linear_findings(design: Design, geom: LinearGeometry,
                    numbers: LinearNumbers) -> list[Finding]:
    """Every geometric check of a linear cam."""
    found = [pressure_angle_finding(design, geom, numbers),
             undercut_finding(design, geom, numbers),
             curvature_finding(design, geom, numbers),
             cutter_finding(design, geom, numbers),
             kerf_finding(design, geom, numbers)]
    return [f for f in found if f is not None]


def linear_report_geometry(design: Design, geom: LinearGeometry,
                           numbers: LinearNumbers) -> dict[str, Any]:
    """The report's ``geometry`` section of a linear cam (mm, deg of the cycle, and the travel
    in mm where something happens)."""
    cam = geom.cam
    stroke = cam.stroke
    rpm = design.cam.speed_rpm

    def at_mm(extreme_: Extreme) -> float | None:
        return None if extreme_.at_deg is None else travel_mm(stroke, extreme_.at_deg)

    return {
        "stroke_mm": stroke,
        "base_height_mm": cam.base_height,
        "roller_radius_mm": cam.radius if cam.radius > 0 else None,
        "profile_base_height_mm": cam.base_height - cam.radius,
        "max_height_mm": numbers.max_height_mm,
        "plate_length_mm": geom.plate_length,
        "plate_area_mm2": geom.outline.area,
        "thickness_mm": design.cam.thickness,
        "traverse_speed_mm_s": None if rpm is None else stroke * rpm / 60.0,
        "pitch_min_radius_of_curvature_mm": numbers.pitch_min_convex.value,
        "pitch_min_radius_of_curvature_at_deg": numbers.pitch_min_convex.at_deg,
        "pitch_min_radius_of_curvature_at_mm": at_mm(numbers.pitch_min_convex),
        "pitch_min_concave_radius_mm": numbers.pitch_min_concave.value,
        "profile_min_radius_of_curvature_mm": numbers.profile_min_convex.value,
        "profile_min_radius_of_curvature_at_deg": numbers.profile_min_convex.at_deg,
        "profile_min_radius_of_curvature_at_mm": at_mm(numbers.profile_min_convex),
        "profile_min_concave_radius_mm": numbers.profile_min_concave.value,
        "profile_min_concave_radius_at_deg": numbers.profile_min_concave.at_deg,
        "profile_min_concave_radius_at_mm": at_mm(numbers.profile_min_concave),
        "pressure_angle_max_deg": numbers.pressure_angle.value,
        "pressure_angle_max_at_deg": numbers.pressure_angle.at_deg,
        "pressure_angle_max_at_mm": at_mm(numbers.pressure_angle),
        "pressure_angle_limit_deg": math.degrees(design.pressure_angle_limit),
        "undercut": geom.undercut,
        "undercut_ranges_deg": [list(r) for r in numbers.undercut_ranges],
        "undercut_fold_ranges_deg": [list(r) for r in numbers.fold_ranges],
        "undercut_cut_ranges_deg": [list(r) for r in numbers.cut_ranges],
        "undercut_ranges_mm": [[travel_mm(stroke, a), travel_mm(stroke, b)]
                               for a, b in numbers.undercut_ranges],
        "profile_points": len(geom.outline.vertices),
        "sampling_tolerance_mm": geom.tolerance,
    }
