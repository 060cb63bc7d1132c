"""``NAME-report.json``: the inspection report for machines (SPEC §5).

Keys carry their units; lengths are millimetres whatever the design's units. Values a later stage
of camfab computes but this build did not are present and ``null``; values unbounded in theory
(the jerk where the acceleration steps) are ``null`` too, with a ``continuity`` check saying where.
Angle ranges are ``[start_deg, end_deg]`` in the direction of rotation; one running through 0°
has start > end.
"""

from __future__ import annotations

import json
import math
from typing import TYPE_CHECKING, Any

from camfab import __version__
from camfab.analysis.cam_checks import CamNumbers, offset_side
from camfab.analysis.drum_checks import DrumNumbers
from camfab.analysis.findings import count

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis


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
            **_key_points(analysis),
        },
        "segments": [_segment(s, analysis) for s in analysis.segments],
        "checks": [f.to_json() for f in analysis.findings],
        "dynamics": _dynamics(analysis),
        "verification": _verification(analysis),
        "status": {
            "exit_code": analysis.exit_code,
            "errors": count(analysis.findings, "error"),
            "warnings": count(analysis.findings, "warning"),
        },
    }


def _geometry(analysis: Analysis) -> dict[str, Any]:
    cam, fol = analysis.design.cam, analysis.design.follower
    if cam.type == "cylindrical":
        return _drum_geometry(analysis)
    if analysis.linear is not None:
        from camfab.analysis.linear_checks import linear_report_geometry

        return linear_report_geometry(analysis)
    base = cam.base_radius
    geom, numbers = analysis.geometry, analysis.numbers
    if geom is None or not isinstance(numbers, CamNumbers) or base is None:
        return {"base_radius_mm": base}
    contact = numbers.face_contact_mm
    required = None if contact is None else contact[1] - contact[0]
    out: dict[str, Any] = {
        "base_radius_mm": base,
        "prime_radius_mm": geom.cam.prime_radius,
        "max_radius_mm": numbers.max_radius_mm,
        "pitch_min_radius_of_curvature_mm": numbers.pitch_min_convex.value,
        "pitch_min_radius_of_curvature_at_deg": numbers.pitch_min_convex.at_deg,
        "pitch_min_concave_radius_mm": numbers.pitch_min_concave.value,
        "profile_min_radius_of_curvature_mm": numbers.profile_min_convex.value,
        "profile_min_radius_of_curvature_at_deg": numbers.profile_min_convex.at_deg,
        "profile_min_concave_radius_mm": numbers.profile_min_concave.value,
        "profile_min_concave_radius_at_deg": numbers.profile_min_concave.at_deg,
        "face_width_required_mm": required,
        "face_contact_range_mm": None if contact is None else list(contact),
        "pressure_angle_max_deg": numbers.pressure_angle.value,
        "pressure_angle_max_at_deg": numbers.pressure_angle.at_deg,
        "pressure_angle_limit_deg": math.degrees(analysis.design.pressure_angle_limit),
        "offset_side_lowering_rise_pressure_angle": offset_side(analysis.design),
        "undercut": geom.undercut,
        "undercut_ranges_deg": [list(r) for r in numbers.undercut_ranges],
        "profile_points": len(geom.profile.vertices),
        "sampling_tolerance_mm": geom.tolerance,
    }
    if fol.oscillating:
        out["rest_arm_angle_deg"] = math.degrees(geom.cam.rest)
    shape = analysis.shape
    if shape is not None:
        out.update({
            "flank_radius_mm": shape.flank_radius,
            "flank_centre_distance_mm": shape.flank_centre_distance,
            "nose_radius_mm": shape.nose_radius,
            "nose_centre_distance_mm": shape.nose_centre_distance,
            "lift_angle_deg": math.degrees(shape.lift_angle),
            "top_dwell_deg": math.degrees(shape.top_dwell),
            "flank_end_angle_deg": math.degrees(shape.flank_end_angle),
        })
    for extra in (analysis.groove, analysis.partner):
        if extra is not None:
            out.update(extra.report_geometry())
    return out


def _key_points(analysis: Analysis) -> dict[str, Any]:
    """A shaped cam's follower motion at the start of lift, the end of the flank, the start of
    the nose and the apex: per radian, and in SI at the design speed."""
    if analysis.shape is None:
        return {}
    units, omega = analysis.units, analysis.design.cam.omega
    rows = []
    for point in analysis.shape.points:
        row: dict[str, Any] = {"point": point.name, "cam_angle_deg": math.degrees(point.angle),
                               units.displacement_column: units.lift_value(point.motion[0])}
        for order in (1, 2):
            key = units.per_rad_key(order).removeprefix("max_")
            row[key] = float(point.motion[order])
            if omega is not None:
                row[units.key(order)] = units.to_si(order, float(point.motion[order]), omega)
        rows.append(row)
    return {"key_points": rows}


def _dynamics(analysis: Analysis) -> dict[str, Any]:
    dyn = analysis.dynamics
    if dyn is None:
        note = "no follower mass (or neither spring nor speed) in the design"
        if analysis.groove is not None:
            note = ("a groove cam drives its follower both ways without a spring: the forces "
                    "on its walls are in geometry (max_inner_wall_force_N, ...)")
        elif analysis.partner is not None:
            note = (f"a {analysis.design.cam.type} cam drives its follower both ways without a "
                    "spring: the forces on either side are in geometry (load_changes, "
                    "max_..._force_N)")
        return {"jump_speed_rpm": None, "min_contact_force_N": None, "required_preload_N": None,
                "required_spring_force_N": None, "note": note}
    return {
        "jump_speed_rpm": dyn.jump_speed_rpm,
        "jump_speed_rad_s": dyn.jump_speed_rad_s,
        "jump_first_at_deg": dyn.jump_at_deg,
        "min_contact_force_N": dyn.min_force_N,
        "min_contact_force_at_deg": dyn.min_force_at_deg,
        "max_contact_force_N": dyn.max_force_N,
        "required_preload_N": dyn.required_preload_N,
        "preload_N": dyn.preload_N,
        "max_camshaft_torque_N_m": dyn.max_torque_N_m,
        "required_spring_force_N": dyn.required_spring_force_N,
        "required_spring_force_at_deg": dyn.required_spring_force_at_deg,
    }


def _drum_geometry(analysis: Analysis) -> dict[str, Any]:
    cam, fol = analysis.design.cam, analysis.design.follower
    dense, numbers = analysis.drum, analysis.numbers
    out: dict[str, Any] = {"radius_mm": cam.radius, "length_mm": cam.length,
                           "groove_depth_mm": cam.groove_depth,
                           "roller_radius_mm": fol.roller_radius}
    if dense is None or not isinstance(numbers, DrumNumbers):
        return out
    d = dense.drum
    out.update({
        "root_radius_mm": d.root,
        "pitch_radius_mm": d.pitch,
        "groove_width_mm": 2 * d.roller,
        "groove_start_mm": d.start,
        "bore_radius_mm": d.bore or None,
        "root_pressure_angle_max_deg": numbers.root_pressure.value,
        "root_pressure_angle_max_at_deg": numbers.root_pressure.at_deg,
        "pitch_pressure_angle_max_deg": numbers.pitch_pressure.value,
        "pitch_pressure_angle_max_at_deg": numbers.pitch_pressure.at_deg,
        "outer_pressure_angle_max_deg": numbers.outer_pressure.value,
        "outer_pressure_angle_max_at_deg": numbers.outer_pressure.at_deg,
        "pressure_angle_limit_deg": math.degrees(analysis.design.pressure_angle_limit),
        "developed_min_radius_of_curvature_mm": numbers.min_developed_radius.value,
        "developed_min_radius_of_curvature_at_deg": numbers.min_developed_radius.at_deg,
        "developed_min_radius_of_curvature_at_radius_mm": numbers.min_developed_radius_at_mm,
    })
    return out


def _verification(analysis: Analysis) -> dict[str, Any]:
    check, geom = analysis.verification, analysis.geometry
    if check is None:
        if geom is None:
            return {"max_lift_error_mm": None}
        return {"max_lift_error_mm": geom.lift.max_mm, "max_lift_error_at_deg": geom.lift.at_deg,
                "checked_on": "sampled profile"}
    return {
        "max_lift_error_mm": check.lift.max_mm,
        "max_lift_error_at_deg": check.lift.at_deg,
        "checked_on": check.source,
        "angle_step_deg": math.degrees(float(check.lift.theta[1] - check.lift.theta[0])),
        "cut_outline_entities": check.entities,
        "cut_outline_max_deviation_mm": check.deviation_mm,
        "stl": None if check.stl is None else {
            "checked_on": f"{analysis.design.name}.stl read back",
            "faces": check.stl.faces,
            "watertight": check.stl.watertight,
            "consistent_winding": check.stl.consistent_winding,
            "degenerate_faces": check.stl.degenerate_faces,
            "short_edges": check.stl.short_edges,
            "sliver_faces": check.stl.sliver_faces,
            "volume_mm3": check.stl.volume_mm3,
            "expected_volume_mm3": check.stl.expected_volume_mm3,
            "volume_allowance_mm3": check.stl.volume_allowance_mm3,
        },
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
    numbers = analysis.numbers
    worst = None if numbers is None else numbers.segment_pressure[stats.index]
    out["max_pressure_angle_deg"] = None if worst is None else worst.value
    out["max_pressure_angle_at_deg"] = None if worst is None else worst.at_deg
    return out


def _clean(value: Any) -> Any:
    """JSON has no infinities or NaN: unbounded or undefined values become null; floats are
    rounded to 12 significant digits."""
    if isinstance(value, float):
        # 12 significant digits: far below any tolerance, and 30° does not print as 29.999…
        return float(f"{value:.12g}") if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: _clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_clean(v) for v in value]
    return value


def report_data(analysis: Analysis) -> dict[str, Any]:
    """The report as JSON-ready data: :func:`report_dict` with its floats cleaned."""
    cleaned: dict[str, Any] = _clean(report_dict(analysis))
    return cleaned


def render_report_json(analysis: Analysis) -> bytes:
    """The report as UTF-8 JSON bytes (stable key order, no timestamps)."""
    text = json.dumps(report_data(analysis), indent=2, ensure_ascii=False,
                      allow_nan=False)
    return (text + "\n").encode("utf-8")
