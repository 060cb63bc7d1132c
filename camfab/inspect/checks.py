"""The inspection's checks: the deviation against the tolerance, the pressure angle against its
limit."""

from __future__ import annotations

import math

import numpy as np

from camfab.analysis.findings import Finding
from camfab.angles import Range, ranges_deg
from camfab.inspect.record import Inspection


def inspection_findings(ins: Inspection) -> list[Finding]:
    """The deviation against the tolerance (an error: it fails the inspection) and the pressure
    angle against its limit (a warning: the part is as designed or not, whatever its φ)."""
    from camfab.angles import degrees

    findings = []
    worst = ins.max_deviation()
    tolerance = ins.setup.tolerance
    if worst is not None and tolerance is not None:
        value, at = worst
        ranges = tuple((e.start_deg, e.end_deg) for e in sorted(ins.excursions(),
                                                                key=lambda e: e.start_deg))
        ok = value <= tolerance
        rms = ins.rms_deviation()
        text = (f"the follower deviates {value:.3g} mm at most from the design motion (at "
                f"{at:.4g}°), RMS {rms:.3g} mm, tolerance {tolerance:.3g} mm")
        if not ok:
            text += f"; over the tolerance at {', '.join(_range_text(r) for r in ranges[:6])}°"
            if len(ranges) > 6:
                text += f" and {len(ranges) - 6} more range(s)"
        findings.append(Finding("deviation", ok, "error", text, value, tolerance, "mm", ranges))
    phi = np.abs(ins.pressure_angle)
    limit = ins.setup.pressure_angle_limit
    k = int(np.argmax(phi))
    over = phi > limit
    findings.append(Finding(
        "pressure_angle", not bool(over.any()), "warning",
        f"the pressure angle of the measured motion reaches {math.degrees(phi[k]):.3g}° at "
        f"{degrees(float(ins.theta[k])):.4g}° (limit {math.degrees(limit):.3g}°)",
        math.degrees(float(phi[k])), math.degrees(limit), "deg", ranges_deg(ins.theta, over)))
    return findings


def _range_text(r: Range) -> str:
    return f"{r[0]:.4g}" if abs(r[1] - r[0]) < 1e-9 else f"{r[0]:.4g}–{r[1]:.4g}"
