"""``STEM-lift.csv``: the measured motion of an inspected cam, one row per step of cam angle.

Rows run from 0 to 360° − step. Columns: ``cam_angle_deg``; ``lift_mm`` (``lift_deg`` for an
oscillating follower); with a speed ``velocity_m_s`` and ``acceleration_m_s2``
(``angular_velocity_rad_s``, ``angular_acceleration_rad_s2``); the signed
``pressure_angle_deg``; the signed ``pitch_radius_of_curvature_mm`` (convex positive, empty where
straight); and with a design ``design_lift_mm`` and ``deviation_mm`` (measured − design;
oscillating: ``design_lift_deg``, ``deviation_deg`` and ``deviation_mm`` at the trace point).
Velocities and accelerations are the derivatives of the measured lift (see
:mod:`camfab.inspect.measure` for how and their limits).
"""

from __future__ import annotations

import numpy as np

from camfab.analysis.kinematics import MotionUnits
from camfab.export.motion_csv import csv_bytes
from camfab.inspect.record import Inspection


def lift_table(ins: Inspection) -> tuple[list[str], np.ndarray]:
    """Column names and the (rows, columns) array of values (NaN: empty)."""
    units = MotionUnits(ins.oscillating)
    k = ins.rows
    angle = "deg" if ins.oscillating else "mm"
    lift = ins.motion[0, k]
    columns = ["cam_angle_deg", f"lift_{angle}"]
    values = [np.degrees(ins.theta[k]), np.degrees(lift) if ins.oscillating else lift]
    omega = ins.setup.omega
    if omega is not None:
        for order in (1, 2):
            columns.append(units.key(order))
            per_rad = ins.motion[order, k] * omega**order
            values.append(per_rad if ins.oscillating else per_rad / 1000.0)
    columns += ["pressure_angle_deg", "pitch_radius_of_curvature_mm"]
    values += [np.degrees(ins.pressure_angle[k]), ins.pitch_radius[k]]
    if ins.design_lift is not None and ins.deviation is not None:
        design, deviation = ins.design_lift[k], ins.deviation[k]
        if ins.oscillating:
            columns += ["design_lift_deg", "deviation_deg"]
            values += [np.degrees(design), np.degrees(deviation)]
        else:
            columns.append("design_lift_mm")
            values.append(design)
        columns.append("deviation_mm")
        assert ins.deviation_mm is not None
        values.append(ins.deviation_mm[k])
    return columns, np.column_stack(values)


def render_lift_csv(ins: Inspection) -> bytes:
    """The lift table as CSV bytes (``\\n`` line ends, 10 significant digits)."""
    return csv_bytes(*lift_table(ins))
