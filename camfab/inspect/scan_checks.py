"""A scan inspection's checks: the motion as made against the tolerance (the verdict), and
beside it the surface's deviation, the play between two flanks, the scan's reach and the
pressure angle as made."""

from __future__ import annotations

import math

import numpy as np

from camfab.analysis.findings import Finding, listed
from camfab.angles import Range, ranges_deg
from camfab.inspect.scan_record import ScanInspection


def scan_findings(ins: ScanInspection) -> list[Finding]:
    """The motion error (an error: it fails the inspection), then the warnings: the surface
    over the tolerance, a play that jams the follower, flanks the scan does not reach, the
    pressure angle over its limit."""
    findings = [_motion(ins), _surface(ins)]
    if ins.backlash_mm is not None:
        findings.append(_play(ins))
    findings.append(_reach(ins))
    findings.append(_pressure(ins))
    return findings


def _places(ranges: list[Range]) -> str:
    return listed([f"{a:.4g}°" if abs(b - a) < 1e-9 else f"{a:.4g}–{b:.4g}°" for a, b in ranges])


def _motion(ins: ScanInspection) -> Finding:
    tolerance = ins.setup.tolerance
    worst = ins.worst()
    assert worst is not None
    value, flank, at = worst
    over = np.zeros(ins.theta.size, dtype=bool)
    for f in ins.flanks:
        over |= np.abs(np.nan_to_num(f.error_mm)) > tolerance
    ranges = ranges_deg(ins.theta, over)
    text = (f"the follower's lift as made departs from the design by {value:.3g} mm at most "
            f"(on the {flank}, at {at:.4g}°); tolerance {tolerance:.3g} mm")
    if ranges:
        text += f"; over it at {_places(ranges)}"
    return Finding("motion", value <= tolerance, "error", text, value, tolerance, "mm",
                   tuple(ranges), at_deg=at)


def _surface(ins: ScanInspection) -> Finding:
    tolerance = ins.setup.tolerance
    measured = [s for s in ins.stats if s.points]
    worst = max(measured, key=lambda s: max(abs(s.p01), abs(s.p99)))
    value = max(abs(worst.p01), abs(worst.p99))
    rms = ", ".join(f"{s.name} {s.rms:.3g} mm" for s in measured)
    return Finding("surface", value <= tolerance, "warning",
                   f"the flanks' surface departs from the exact one by {value:.3g} mm (99 % of "
                   f"the points on the {worst.name} within it), RMS {rms}; tolerance "
                   f"{tolerance:.3g} mm (the verdict is on the motion)", value, tolerance, "mm")


def _play(ins: ScanInspection) -> Finding:
    assert ins.backlash_mm is not None
    play = ins.backlash_mm
    design = ins.model.clearance * ins.model.q_scale
    if not np.isfinite(play).any():
        return Finding("backlash", True, "warning", "the play between the flanks is not "
                       "measured: the scan does not reach both flanks at any cam angle",
                       applicable=False)
    k = int(np.nanargmin(play))
    tight = ranges_deg(ins.theta, np.nan_to_num(play, nan=0.0) < -ins.setup.tolerance)
    text = (f"the follower's play between the flanks is {np.nanmin(play):.3g} to "
            f"{np.nanmax(play):.3g} mm (design {design:.3g} mm)")
    if tight:
        text += (f"; the flanks pinch the follower by more than the tolerance at "
                 f"{_places(tight)}")
    return Finding("backlash", not tight, "warning", text, float(play[k]),
                   -ins.setup.tolerance, "mm",
                   tuple(tight), at_deg=math.degrees(float(ins.theta[k])))


def _reach(ins: ScanInspection) -> Finding:
    missing = []
    for f in ins.flanks:
        gaps = ranges_deg(ins.theta, ~f.measured)
        if gaps:
            missing.append(f"the {f.name} at {_places(gaps)}")
    if not missing:
        return Finding("coverage", True, "warning", "the scan reaches every flank at every cam "
                       "angle")
    return Finding("coverage", False, "warning", "the scan does not reach "
                   + "; ".join(missing) + ": the motion there is not judged")


def _pressure(ins: ScanInspection) -> Finding:
    phi = np.abs(ins.pressure_angle)
    limit = ins.setup.pressure_angle_limit
    k = int(np.nanargmax(phi))
    over = np.nan_to_num(phi) > limit
    return Finding("pressure_angle", not bool(over.any()), "warning",
                   f"the pressure angle of the motion as made reaches "
                   f"{math.degrees(phi[k]):.3g}° at {math.degrees(float(ins.theta[k])):.4g}° "
                   f"(limit {math.degrees(limit):.3g}°)", math.degrees(float(phi[k])),
                   math.degrees(limit), "deg", tuple(ranges_deg(ins.theta, over)),
                   at_deg=math.degrees(float(ins.theta[k])))
