"""``STEM-lift.csv`` of a scan's inspection: the follower's motion through the scanned flanks,
one row per step of the design's motion table.

Columns: ``cam_angle_deg``; ``design_lift_mm`` and ``lift_mm`` (an oscillating follower's or a
globoid's swing: ``design_lift_deg``, ``lift_deg``), the lift as made being the middle of the
play between two flanks; ``lift_error_mm`` (as made − design, at the trace point); one
``<flank>_error_mm`` per flank (its run less the design's: + the flank pushes the follower
toward more lift); ``backlash_mm`` where the cam has two flanks; ``pressure_angle_deg`` as made.
Empty cells: the scan does not reach the flank there.
"""

from __future__ import annotations

import math
import re

import numpy as np

from camfab.export.motion_csv import csv_bytes
from camfab.inspect.scan_record import ScanInspection


def column_name(flank: str) -> str:
    """A flank's name as a CSV column's: lower case, words joined by ``_``, ASCII only."""
    words = re.findall(r"[a-z0-9]+", flank.lower().encode("ascii", "ignore").decode())
    return "_".join(words) or "flank"


def scan_rows(ins: ScanInspection, table_step: float) -> np.ndarray:
    """The rows of the model's grid at every *table_step* (rad) of cam angle."""
    step = float(ins.theta[1] - ins.theta[0])
    every = max(1, round(table_step / step))
    return np.arange(0, ins.theta.size, every)


def scan_lift_table(ins: ScanInspection, table_step: float) -> tuple[list[str], np.ndarray]:
    """Column names and the (rows, columns) values (NaN: empty)."""
    k = scan_rows(ins, table_step)
    swing = ins.model.q_unit == "rad"
    unit = "deg" if swing else "mm"
    scale = math.degrees(1.0) if swing else 1.0
    columns = ["cam_angle_deg", f"design_lift_{unit}", f"lift_{unit}", "lift_error_mm"]
    values = [np.degrees(ins.theta[k]), ins.design_q[k] * scale, ins.lift_q[k] * scale,
              ins.lift_error_mm[k]]
    for f in ins.flanks:
        columns.append(f"{column_name(f.name)}_error_mm")
        values.append(f.error_mm[k])
    if ins.backlash_mm is not None:
        columns.append("backlash_mm")
        values.append(ins.backlash_mm[k])
    columns.append("pressure_angle_deg")
    values.append(np.degrees(ins.pressure_angle[k]))
    return columns, np.column_stack(values)


def render_scan_lift_csv(ins: ScanInspection, table_step: float) -> bytes:
    """The table as CSV bytes (``\\n`` line ends, 10 significant digits)."""
    return csv_bytes(*scan_lift_table(ins, table_step))
