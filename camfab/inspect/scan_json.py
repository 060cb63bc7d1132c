"""``STEM-inspection.json`` of a scan's inspection, for machines.

Keys carry their units; lengths are millimetres whatever the scan's units, angles degrees.
``scan``: what was read (``points``: a mesh's vertices), how many points were judged (a mesh's
triangles sampled) and how many set aside; ``alignment``: the rigid
motion from the scanner's frame to the cam's (p_cam = R·p_scan + t) and its residual;
``surface``: each flank's deviation statistics (+ material left on); ``motion``: the follower's
lift error through the scanned flanks per flank (+ pushed toward more lift), the play between two
flanks, the pressure angle as made; ``checks`` and ``status`` as an outline's inspection.
"""

from __future__ import annotations

import json
import math
from typing import TYPE_CHECKING, Any

import numpy as np

from camfab import __version__
from camfab.analysis.findings import count
from camfab.inspect.report_json import rounded as _r
from camfab.inspect.scan_record import ScanInspection

if TYPE_CHECKING:
    from camfab.design import Design
    from camfab.inspect.options import InspectOptions


def scan_dict(ins: ScanInspection, options: InspectOptions, design: Design) -> dict[str, Any]:
    """The scan's inspection as plain data."""
    al, dev, setup = ins.alignment, ins.deviations, ins.setup
    on_flanks = int(np.count_nonzero(dev.flank >= 0))
    return {
        "camfab_version": __version__,
        "scan": {"file": str(options.profile), "read": ins.scan.source, "units": ins.scan.units,
                 "points": len(ins.scan.points), "judged": len(dev.flank),
                 "on_flanks": on_flanks,
                 "set_aside": {"off_every_flank": dev.off_surface,
                               "beyond_gate": dev.beyond_gate},
                 "fit_mm": _r(setup.fit), "gate_mm": _r(setup.gate)},
        "alignment": {"mode": al.mode, "start": al.start,
                      "rotation": [[_r(float(v)) for v in row] for row in al.rotation],
                      "translation_mm": [_r(float(v)) for v in al.translation],
                      "phase_deg": _r(al.phase_deg), "tilt_deg": _r(al.tilt_deg),
                      "residual_rms_mm": _r(al.residual_mm), "points_used": al.used,
                      "iterations": al.iterations},
        "design": {"file": str(options.design), "name": design.name,
                   "cam_type": design.cam.type, "tolerance_mm": _r(setup.tolerance)},
        "surface": [s.to_json() for s in ins.stats],
        "motion": _motion(ins),
        "checks": [f.to_json() for f in ins.findings],
        "status": {"exit_code": ins.exit_code, "errors": count(ins.findings, "error"),
                   "warnings": count(ins.findings, "warning")},
    }


def _motion(ins: ScanInspection) -> dict[str, Any]:
    step = math.degrees(float(ins.theta[1] - ins.theta[0]))
    worst = ins.worst()
    flanks = []
    for f in ins.flanks:
        found = f.worst()
        error = f.error_mm[f.measured]
        flanks.append({
            "flank": f.name,
            "max_error_mm": None if found is None else _r(float(f.error_mm[found[1]])),
            "max_error_at_deg": None if found is None else _r(
                math.degrees(float(ins.theta[found[1]]))),
            "rms_error_mm": _r(float(np.sqrt(np.mean(error * error)))) if error.size else None,
            "measured_share": _r(float(np.mean(f.measured)), 6)})
    out: dict[str, Any] = {
        "grid_step_deg": _r(step),
        "coordinate": "lift (mm)" if ins.model.q_unit == "mm" else "swing (rad)",
        "mm_per_unit": _r(ins.model.q_scale),
        "max_error_mm": None if worst is None else _r(worst[0]),
        "max_error_flank": None if worst is None else worst[1],
        "max_error_at_deg": None if worst is None else _r(worst[2]),
        "flanks": flanks,
        "backlash": None,
    }
    if ins.backlash_mm is not None and np.isfinite(ins.backlash_mm).any():
        out["backlash"] = {"min_mm": _r(float(np.nanmin(ins.backlash_mm))),
                           "max_mm": _r(float(np.nanmax(ins.backlash_mm))),
                           "design_mm": _r(ins.model.clearance * ins.model.q_scale)}
    phi = np.abs(ins.pressure_angle)
    if np.isfinite(phi).any():
        k = int(np.nanargmax(phi))
        out["pressure_angle_max_deg"] = _r(math.degrees(float(phi[k])))
        out["pressure_angle_max_at_deg"] = _r(math.degrees(float(ins.theta[k])))
        out["design_pressure_angle_max_deg"] = _r(math.degrees(float(np.max(np.abs(
            ins.design_pressure_angle)))))
    return out


def render_scan_json(ins: ScanInspection, options: InspectOptions, design: Design) -> bytes:
    """The JSON report as UTF-8 bytes (indented, keys in a fixed order)."""
    return (json.dumps(scan_dict(ins, options, design), indent=2, ensure_ascii=False)
            + "\n").encode("utf-8")
