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

import numpy as np

from camfab import __version__
from camfab.analysis.findings import count
from camfab.export.design_record import design_record, follower_record, record_units

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.design import Design


def report_dict(analysis: Analysis) -> dict[str, Any]:
    """The report as plain data."""
    design = analysis.design
    cam = design.cam
    units = analysis.units
    return {
        "camfab_version": __version__,
        "name": design.name,
        "description": design.description,
        "cam_type": cam.type,
        "units": design.units,
        "rotation": cam.rotation,
        "speed_rpm": cam.speed_rpm,
        "design": design_record(design),
        "design_units": record_units(design),
        "follower": follower_record(design),
        "geometry": analysis.result.report_geometry(analysis),
        "sizing": sizing_dict(design),
        "motion": {
            units.lift_key.replace("lift", "max_lift"): units.lift_value(analysis.program.max_lift),
            "segment_count": len(analysis.program.segments),
            **analysis.result.report_motion(analysis),
        },
        "segments": [_segment(s, analysis) for s in analysis.segments],
        "lift_table": lift_table(analysis),
        "checks": [f.to_json() for f in analysis.findings],
        "dynamics": _dynamics(analysis),
        "verification": _verification(analysis),
        **({"machining": machining_list(analysis)} if analysis.machining else {}),
        "status": {
            "exit_code": analysis.exit_code,
            "errors": count(analysis.findings, "error"),
            "warnings": count(analysis.findings, "warning"),
        },
    }


def machining_list(analysis: Analysis) -> list[dict[str, Any]]:
    """The setup sheet of each machining program written (mm, mm/min, min): its file, the
    stock, the work zero and the machine's axes, each tool and each operation in order with
    its estimated time, the estimated cycle time (the operations' times summed: feed moves at
    their feeds, rapid moves and tool changes not counted) and the notes."""
    return [{"file": setup.file, "stock": setup.stock, "work_zero": setup.work_zero,
             "axes": setup.axes,
             "tools": [{"number": t.number, "what": t.what, "diameter_mm": t.diameter_mm,
                        "flutes": t.flutes, "cut_length_mm": t.cut_length_mm}
                       for t in setup.tools],
             "operations": [{"name": op.name, "tool": op.tool, "passes": op.passes,
                             "feed_mm_min": op.feed_mm_min, "minutes": op.minutes}
                            for op in setup.operations],
             "cycle_time_min": setup.minutes, "notes": list(setup.notes)}
            for setup in analysis.machining]


def sizing_dict(design: Design) -> dict[str, Any] | None:
    """What camfab sized where the design said ``auto`` (mm, deg), or None: the values chosen,
    the limit that governs them (its check id, the limit in words, its value and limit in
    ``unit``, the cam angle where it binds) and the stock step the radius was rounded up to."""
    sized = design.sized
    if sized is None:
        return None
    values = {"base_radius_mm": sized.base_radius, "offset_mm": sized.offset,
              "radius_mm": sized.radius}
    return {**{k: v for k, v in values.items() if v is not None},
            "governed_by": sized.governed_by, "governing_limit": sized.what,
            "value": sized.value, "limit": sized.limit, "unit": sized.unit,
            "at_deg": sized.at_deg, "round_to_mm": sized.rounded_to}


def lift_table(analysis: Analysis) -> dict[str, Any]:
    """The lift at every ``table_step`` of cam angle, for inspection with a dial gauge on the
    follower, and the band an inspector holds it to: the inspection tolerance met along the
    profile's normal moves the follower by tolerance / cos φ (an oscillating arm by that over
    its length, in degrees)."""
    from camfab.export.motion_csv import motion_table

    design, units = analysis.design, analysis.units
    columns, table = motion_table(analysis)
    theta, lift = table[:, 0], table[:, columns.index(units.displacement_column)]
    phi = (table[:, columns.index("pressure_angle_deg")] if "pressure_angle_deg" in columns
           else np.zeros(theta.size))
    cosine = np.maximum(np.cos(np.radians(np.nan_to_num(phi))), 0.01)
    band = design.inspection_tolerance / cosine
    unit = "deg" if units.oscillating else "mm"
    if units.oscillating:
        band = np.degrees(band / (design.follower.arm_length or 1.0))
    return {"step_deg": math.degrees(design.table_step), "unit": unit,
            "inspection_tolerance_mm": design.inspection_tolerance,
            "columns": ["cam_angle_deg", f"lift_{unit}", f"tolerance_{unit}"],
            "rows": np.column_stack((theta, lift, band)).round(6).tolist()}


def _dynamics(analysis: Analysis) -> dict[str, Any]:
    """The rigid model's dynamics, then the cam at its speed (:func:`at_speed_dict`)."""
    return {**_rigid(analysis), **at_speed_dict(analysis)}


def _rigid(analysis: Analysis) -> dict[str, Any]:
    dyn = analysis.dynamics
    if dyn is None:
        note = (analysis.result.dynamics_note(analysis)
                or "no follower mass (or neither spring nor speed) in the design")
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


def at_speed_dict(analysis: Analysis) -> dict[str, Any]:
    """The contact stress, the elastic follower train and the roller's life (MPa, Hz, mm at
    the trace point, N, rpm, hours), null where not computed, with a note saying why."""
    speed = analysis.at_speed
    stress = None if speed is None else speed.stress
    shaken = None if speed is None else speed.vibration
    life = None if speed is None else speed.life
    out: dict[str, Any] = {
        "contact_stress_max_MPa": None if stress is None else stress.max_MPa,
        "contact_stress_max_at_deg": None if stress is None else stress.max_at_deg,
    }
    if stress is not None:
        contact = stress.contact
        side = stress.max_side
        row = int(stress.row[stress.index])
        out.update({
            "contact_stress_on": None if side is None else side.name,
            "contact_stress_max_at_mm": (None if side is None or side.rows is None
                                         else float(side.rows[row])),
            "contact_stress_max_at_xy_mm": (None if side is None or side.place is None
                                            else [float(v) for v in side.place[stress.index]]),
            "contact_stress_max_at_mm_from": (None if side is None or side.rows is None
                                              else side.rows_from),
            "contact_stress_cam_radius_mm": stress.cam_radius_at(stress.index),
            "contact_stress_cam_shape": stress.shape_at(stress.index),
            "contact": contact.shape,
            "contact_length_mm": contact.length,
            "effective_modulus_MPa": stress.modulus,
        })
    else:
        out["contact_stress_note"] = None if speed is None else speed.stress_note
    out.update({
        "natural_frequency_Hz": None if shaken is None else shaken.natural_Hz,
        "dynamic_error_max_mm": None if shaken is None else 1000.0 * shaken.max_error_m,
        "residual_vibration_mm": (None if shaken is None or shaken.residual_m is None
                                  else 1000.0 * shaken.residual_m),
        "dynamic_min_contact_force_N": None if shaken is None else shaken.min_force_N,
        "dynamic_jump_speed_rpm": None if shaken is None else shaken.jump_speed_rpm,
    })
    if shaken is not None:
        out.update({
            "frequency_ratio": shaken.frequency_ratio,
            "damping_ratio": shaken.train.zeta,
            "dynamic_error_max_at_deg": shaken.max_error_at_deg,
            "residual_vibration_by_dwell": [
                {"segment": d.segment, "start_deg": d.start_deg, "end_deg": d.end_deg,
                 "peak_to_peak_mm": 1000.0 * d.peak_to_peak_m} for d in shaken.dwells],
            "dynamic_min_contact_force_at_deg": shaken.min_force_at_deg,
            "dynamic_max_contact_force_N": shaken.max_force_N,
            "dynamic_jump_searched_from_rpm": (shaken.searched_from_rpm if shaken.one_sided
                                               else None),
            "dynamic_jump_searched_to_rpm": (shaken.searched_to_rpm if shaken.one_sided
                                             else None),
            "dynamic_jump_at_every_speed": (shaken.jump_at_every_speed if shaken.one_sided
                                            else None),
            "static_deflection_max_mm": 1000.0 * shaken.max_static_m,
            "dynamic_vibration_max_mm": 1000.0 * shaken.max_ringing_m,
        })
        if speed is not None and speed.band is not None:
            out["polydyne"] = polydyne_dict(analysis)
        if not shaken.one_sided:
            out["flank_changes"] = [{"cam_angle_deg": deg, "onto": "pushing" if onto > 0
                                     else "pulling back"} for deg, onto in shaken.flank_changes]
    elif analysis.design.follower.stiffness is not None and speed is not None:
        out["vibration_note"] = speed.force_note
    else:
        out["vibration_note"] = ("the follower train is rigid: give follower.stiffness (N/mm) "
                                 "for its vibration")
    out["roller_life_h"] = None if life is None else life.hours_min
    if life is not None:
        out["roller_life_by_roller"] = [
            {"roller": name, "hours": hours, "equivalent_load_N": load,
             "revolutions_per_turn": turns}
            for name, hours, load, turns in zip(life.names, life.hours, life.load_N,
                                                life.revolutions, strict=True)]
    else:
        out["roller_life_note"] = None if speed is None else speed.life_note
    return out


def polydyne_dict(analysis: Analysis) -> dict[str, Any]:
    """A polydyne cam's motions and its vibration against speed (mm at the trace point, rpm):
    how far the cam's lift departs from the motion asked of the mass, the largest dwell
    vibration at each speed of the band of the polydyne cam and of the motion list cut directly
    as the cam (null where the train resonates), and the speeds about the design speed over
    which the polydyne cam rings less."""
    speed = analysis.at_speed
    assert speed is not None and speed.band is not None and speed.vibration is not None
    band, shaken = speed.band, speed.vibration
    theta = shaken.theta
    apart = (analysis.program.evaluate(theta)[0]
             - analysis.design.output_program.evaluate(theta)[0]) * shaken.trace_m
    at = band.at
    return {
        "speed_rpm": shaken.speed_rpm,
        "cam_minus_output_max_mm": 1000.0 * float(np.max(np.abs(apart))),
        "residual_vibration_mm": 1000.0 * float(band.polydyne_m[at]),
        "direct_residual_vibration_mm": 1000.0 * float(band.direct_m[at]),
        "better_from_rpm": band.low_rpm,
        "better_to_rpm": band.high_rpm,
        "band": {"speeds_rpm": band.speeds_rpm.tolist(),
                 "polydyne_residual_mm": (1000.0 * band.polydyne_m).tolist(),
                 "direct_residual_mm": (1000.0 * band.direct_m).tolist()},
    }


def _verification(analysis: Analysis) -> dict[str, Any]:
    check, lift = analysis.verification, analysis.result.sampled_lift()
    if check is None:
        if lift is None:
            return {"max_lift_error_mm": None}
        return {"max_lift_error_mm": lift.max_mm, "max_lift_error_at_deg": lift.at_deg,
                "checked_on": "sampled profile"}
    out = {
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
    if check.withheld:  # (only when an output asked for could not be made)
        out["not_produced"] = {name: why for name, why in check.withheld}
    if check.step is not None:  # (only when a STEP was asked for)
        step = check.step
        out["step"] = {
            "checked_on": f"{analysis.design.name}.step read back by OpenCASCADE",
            "ok": step.ok, "solids": step.solids, "expected_solids": step.expected_solids,
            "valid": step.valid, "volume_mm3": step.volume_mm3,
            "expected_volume_mm3": step.expected_volume_mm3,
            "volume_allowance_mm3": step.volume_allowance_mm3,
            "max_deviation_mm": step.deviation_mm, "circles": step.circles,
            "cylinders": step.cylinders, "b_splines": step.b_splines,
        }
    return out


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
    worst = analysis.result.numbers.segment_pressure[stats.index]
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
