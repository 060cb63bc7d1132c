"""``NAME-report.json``: the inspection report for machines (SPEC §5).

Keys carry their units. Values a later stage of camfab computes but this build did not are present
and ``null``; values unbounded in theory (the jerk where the acceleration steps) are ``null`` too,
with a ``continuity`` check saying where.
"""

from __future__ import annotations

import json
import math
from typing import TYPE_CHECKING, Any

from camfab import __version__
from camfab.analysis.findings import count

if TYPE_CHECKING:
    from camfab.pipeline import Analysis


def report_dict(analysis: Analysis) -> dict[str, Any]:
    """The report as plain data."""
    design = analysis.design
    cam, fol = design.cam, design.follower
    units = analysis.units
    return {
        "camfab_version": __version__,
        "name": design.name,
        "description": design.description,
        "cam_type": cam.type,
        "units": design.units,
        "rotation": cam.rotation,
        "speed_rpm": cam.speed_rpm,
        "follower": {"type": fol.type, "motion": fol.motion},
        "geometry": _geometry(analysis),
        "motion": {
            units.lift_key.replace("lift", "max_lift"): units.lift_value(analysis.program.max_lift),
            "segment_count": len(analysis.program.segments),
        },
        "segments": [_segment(s, analysis) for s in analysis.segments],
        "checks": [f.to_json() for f in analysis.findings],
        "dynamics": {"jump_speed_rpm": None, "min_contact_force_N": None,
                     "required_preload_N": None},
        "verification": {"max_lift_error_mm": None},
        "status": {
            "exit_code": analysis.exit_code,
            "errors": count(analysis.findings, "error"),
            "warnings": count(analysis.findings, "warning"),
        },
    }


def _geometry(analysis: Analysis) -> dict[str, Any]:
    cam, fol = analysis.design.cam, analysis.design.follower
    if cam.type == "cylindrical":
        return {"radius_mm": cam.radius, "length_mm": cam.length,
                "groove_depth_mm": cam.groove_depth, "roller_radius_mm": fol.roller_radius,
                "pitch_radius_mm": None, "root_pressure_angle_max_deg": None}
    base = cam.base_radius
    return {
        "base_radius_mm": base,
        "prime_radius_mm": None if base is None else base + fol.trace_radius,
        "max_radius_mm": None,
        "pitch_min_radius_of_curvature_mm": None,
        "profile_min_radius_of_curvature_mm": None,
        "profile_min_concave_radius_mm": None,
        "face_width_required_mm": None,
    }


def _segment(stats: Any, analysis: Analysis) -> dict[str, Any]:
    units = analysis.units
    out: dict[str, Any] = {
        "kind": stats.kind,
        "law": stats.law,
        "start_deg": stats.start_deg,
        "end_deg": stats.end_deg,
        units.lift_key: stats.lift,
    }
    for order in (1, 2, 3):
        value = stats.max_si[order - 1] if stats.max_si is not None else None
        out[f"max_{units.key(order)}"] = value
    for order in (1, 2, 3):
        out[units.per_rad_key(order)] = stats.max_per_rad[order - 1]
    out["law_coefficients"] = dict(zip(("Cv", "Ca", "Cj"), stats.coefficients, strict=True))
    out["max_pressure_angle_deg"] = None
    return out


def _clean(value: Any) -> Any:
    """JSON has no infinities or NaN: unbounded or undefined values become null."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_clean(v) for v in value]
    return value


def render_report_json(analysis: Analysis) -> bytes:
    """The report as UTF-8 JSON bytes (stable key order, no timestamps)."""
    text = json.dumps(_clean(report_dict(analysis)), indent=2, ensure_ascii=False,
                      allow_nan=False)
    return (text + "\n").encode("utf-8")
