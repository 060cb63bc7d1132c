"""``STEM-inspection.json``: the inspection of a made or scanned cam, for machines.

Keys carry their units, as in the build report; lengths are millimetres whatever the file's
units, angles degrees. ``deviation`` is ``null`` without a design. Where on the part: the contact
point of the follower at an angle, in the outline file's coordinates (converted to mm).
"""

from __future__ import annotations

import json
import math
from typing import TYPE_CHECKING, Any

import numpy as np

from camfab import __version__
from camfab.analysis.findings import count
from camfab.analysis.kinematics import MotionUnits
from camfab.inspect.record import Inspection

if TYPE_CHECKING:
    from camfab.inspect.options import Prepared

#: How the derivatives are obtained, for the reports.
METHOD = ("velocity and acceleration are the derivatives of the measured lift: a cubic fitted by "
          "least squares over ±{smooth:.3g}° of cam angle about each angle (Savitzky–Golay), so "
          "steps in acceleration are spread over ±{smooth:.3g}° and narrower peaks lowered; the "
          "pressure angle and the pitch curve's radius of curvature follow exactly from the lift "
          "and these derivatives")


def rounded(value: float | None, digits: int = 10) -> float | None:
    """A finite float rounded to *digits* significant digits, or None."""
    if value is None or not math.isfinite(value):
        return None
    return float(f"{value:.{digits}g}") + 0.0


def _deg(angle: float) -> float:
    return round(math.degrees(angle), 6) + 0.0


def _file_xy(ins: Inspection, prepared: Prepared, theta_deg: float) -> list[float | None]:
    """The contact point at *theta_deg* in the outline file's coordinates (mm)."""
    x, y = ins.on_outline(theta_deg)
    cx, cy = prepared.centre_mm
    return [rounded(x + cx, 8), rounded(y + cy, 8)]


def inspection_dict(ins: Inspection, prepared: Prepared) -> dict[str, Any]:
    """The inspection as plain data."""
    fol = ins.setup.follower
    units = MotionUnits(ins.oscillating)
    outline = prepared.outline
    return {
        "camfab_version": __version__,
        "profile": {
            "file": str(prepared.options.profile),
            "format": "dxf" if prepared.options.profile.suffix.lower() == ".dxf" else "csv",
            "read": outline.source,
            "units": outline.units,
            "centre_mm": [rounded(c) for c in prepared.centre_mm],
            "kerf_mm": rounded(prepared.kerf_mm),
            "kerf_from": prepared.kerf_source,
            "area_mm2": rounded(ins.profile.area),
            "min_radius_mm": rounded(ins.measured_base_radius),
            "max_radius_mm": rounded(float(ins.profile.radii().max())),
        },
        "follower": {
            "type": fol.contact,
            "motion": "oscillating" if fol.oscillating else "translating",
            "radius_mm": rounded(fol.radius),
            "offset_mm": None if fol.oscillating else rounded(fol.offset),
            "pivot_distance_mm": rounded(fol.pivot_distance) if fol.oscillating else None,
            "arm_length_mm": rounded(fol.arm_length) if fol.oscillating else None,
            "pivot_side": ("right" if fol.pivot_sign > 0 else "left") if fol.oscillating
            else None,
        },
        "rotation": "ccw" if ins.setup.sigma > 0 else "cw",
        "speed_rpm": prepared.speed_rpm,
        "method": {
            "table_step_deg": _deg(ins.setup.step),
            "grid_step_deg": rounded(math.degrees(float(ins.theta[1] - ins.theta[0]))),
            "smooth_deg": rounded(math.degrees(ins.setup.smooth)),
            "derivatives": METHOD.format(smooth=math.degrees(ins.setup.smooth)),
            "lift_from": ins.lift_from,
        },
        "design": _design(ins, prepared),
        "motion": _motion(ins, units),
        "deviation": _deviation(ins, prepared),
        "checks": [f.to_json() for f in ins.findings],
        "status": {"exit_code": ins.exit_code, "errors": count(ins.findings, "error"),
                   "warnings": count(ins.findings, "warning")},
    }


def _design(ins: Inspection, prepared: Prepared) -> dict[str, Any] | None:
    ref = ins.reference
    if ref is None or prepared.design is None:
        return None
    return {"file": str(prepared.options.design), "name": ref.name,
            "reference": ref.source, "base_radius_mm": rounded(ref.base_radius),
            "tolerance_mm": rounded(ins.setup.tolerance)}


def _extreme(values: np.ndarray, theta: np.ndarray, largest: bool = True) -> tuple[float, float]:
    k = int(np.argmax(values) if largest else np.argmin(values))
    return float(values[k]), _deg(float(theta[k]))


def _motion(ins: Inspection, units: MotionUnits) -> dict[str, Any]:
    theta, m = ins.theta, ins.motion
    scale = math.degrees(1.0) if ins.oscillating else 1.0
    lift_max, lift_at = _extreme(m[0], theta)
    out: dict[str, Any] = {
        units.lift_key.replace("lift", "max_lift"): rounded(lift_max * scale),
        "max_lift_at_deg": lift_at,
        "rest_position_" + ("deg" if ins.oscillating else "mm"): rounded(ins.rest * scale),
    }
    for order, name in ((1, "velocity"), (2, "acceleration")):
        value, at = _extreme(np.abs(m[order]), theta)
        omega = ins.setup.omega
        out["max_" + units.key(order)] = (None if omega is None
                                          else rounded(units.to_si(order, value, omega)))
        out[units.per_rad_key(order)] = rounded(value)
        out[f"max_{name}_at_deg"] = at
    phi, phi_at = _extreme(np.abs(ins.pressure_angle), theta)
    out["pressure_angle_max_deg"] = rounded(math.degrees(phi))
    out["pressure_angle_max_at_deg"] = phi_at
    radius = ins.pitch_radius
    convex = np.where(radius > 0, radius, np.inf)
    concave = np.where(radius < 0, -radius, np.inf)
    for name, values in (("pitch_min_radius_of_curvature", convex),
                         ("pitch_min_concave_radius", concave)):
        value, at = _extreme(values, theta, largest=False)
        out[f"{name}_mm"] = rounded(value if np.isfinite(value) else None)
        out[f"{name}_at_deg"] = at if np.isfinite(value) else None
    return out


def _deviation(ins: Inspection, prepared: Prepared) -> dict[str, Any] | None:
    worst = ins.max_deviation()
    if worst is None or ins.deviation_mm is None:
        return None
    value, at = worst
    k = int(np.argmax(np.abs(ins.deviation_mm)))
    tolerance = ins.setup.tolerance
    out: dict[str, Any] = {
        "max_mm": rounded(value),
        "max_at_deg": rounded(at),
        "max_signed_mm": rounded(float(ins.deviation_mm[k])),
        "max_at_xy_mm": _file_xy(ins, prepared, at),
        "rms_mm": rounded(ins.rms_deviation()),
        "mean_mm": rounded(float(np.mean(ins.deviation_mm))),
        "tolerance_mm": rounded(tolerance),
        "within_tolerance": None if tolerance is None else value <= tolerance,
        "align_deg": None if ins.align is None else rounded(math.degrees(ins.align)),
        "excursions": [{"start_deg": e.start_deg, "end_deg": e.end_deg,
                        "peak_mm": rounded(e.peak_mm), "peak_at_deg": rounded(e.peak_at_deg),
                        "peak_at_xy_mm": _file_xy(ins, prepared, e.peak_at_deg)}
                       for e in ins.excursions()],
    }
    if ins.oscillating and ins.deviation is not None:
        out["max_deg"] = rounded(math.degrees(float(np.max(np.abs(ins.deviation)))))
    return out


def render_inspection_json(ins: Inspection, prepared: Prepared) -> bytes:
    """The JSON report as UTF-8 bytes (indented, keys in a fixed order)."""
    return (json.dumps(inspection_dict(ins, prepared), indent=2, ensure_ascii=False)
            + "\n").encode("utf-8")
