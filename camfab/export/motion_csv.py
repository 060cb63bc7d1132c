"""``NAME-motion.csv``: the follower motion at every ``table_step`` of cam angle (SPEC §5).

Rows run from 0 to 360° − step. Where a value steps exactly at a row, the row gives the value just
after the step. The pressure angle is signed (counter-clockwise from the follower's direction of
motion to the cam's normal); radii of curvature are signed, convex positive, and empty where the
curve is straight. A drum cam gives the pressure angle at the groove's floor and the radius of
curvature of its pitch curve developed at the mean radius. A linear cam adds ``cam_travel_mm``
(the plate's travel, a stroke being 360° of cam angle) after the cam angle; a conjugate pair
adds cam b's pressure angle and radii (``..._b_...``); a globoidal cam, whose flanks are
surfaces, leaves the pitch radius empty and gives ``undercut_roller_radius_mm``, the largest
roller its flanks take without folding. Where computed, the contact stress
(``contact_stress_MPa``) and an elastic follower train's displacement and contact force
(``dynamic_displacement_mm`` or ``_deg``, ``dynamic_contact_force_N``) come last.
"""

from __future__ import annotations

import io
import math
from typing import TYPE_CHECKING

import numpy as np

from camfab.motion.program import cycle_angles

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis


def motion_table(analysis: Analysis) -> tuple[list[str], np.ndarray]:
    """Column names and the (rows, columns) array of values (NaN where not computed)."""
    design, units = analysis.design, analysis.units
    theta = cycle_angles(design.table_step)
    s = analysis.program.evaluate(theta)
    omega = design.cam.omega
    columns = ["cam_angle_deg", units.displacement_column]
    values = [np.degrees(theta), np.degrees(s[0]) if units.oscillating else s[0]]
    leading = analysis.result.table_leading(theta)
    columns[1:1] = [name for name, _ in leading]
    values[1:1] = [column for _, column in leading]
    if omega is not None:
        for order in (1, 2, 3):
            columns.append(units.key(order))
            values.append(units.to_si(order, s[order], omega))
    for name, column in analysis.result.table_columns(theta, s):
        columns.append(name)
        values.append(column)
    for name, column in at_speed_columns(analysis, theta):
        columns.append(name)
        values.append(column)
    return columns, np.column_stack(values)


def at_speed_columns(analysis: Analysis, theta: np.ndarray) -> list[tuple[str, np.ndarray]]:
    """The cam at its speed at the cam angles *theta* (rad), where computed: the contact
    stress (MPa), and with an elastic follower train its displacement (mm, or deg of an
    arm's swing) and its contact force along its motion (N)."""
    from camfab.speed.model import sample_at

    speed = analysis.at_speed
    if speed is None:
        return []
    out = []
    if speed.stress is not None:
        out.append(("contact_stress_MPa", sample_at(speed.theta, speed.stress.stress, theta)))
    shaken = speed.vibration
    if shaken is not None:
        units = analysis.units
        error = sample_at(shaken.theta, shaken.error_m, theta) / shaken.trace_m
        lift = analysis.program.evaluate(theta)[0] + error
        out.append((f"dynamic_{units.displacement_column}",
                    np.degrees(lift) if units.oscillating else lift))
        out.append(("dynamic_contact_force_N", sample_at(shaken.theta, shaken.force_N, theta)))
    return out


def render_motion_csv(analysis: Analysis) -> bytes:
    """The motion table as CSV bytes (``\\n`` line ends, 10 significant digits)."""
    return csv_bytes(*motion_table(analysis))


def csv_bytes(columns: list[str], table: np.ndarray) -> bytes:
    """A table as CSV bytes: a header row, ``\n`` line ends, 10 significant digits, empty cells
    for values that are not finite."""
    out = io.StringIO()
    out.write(",".join(columns) + "\n")
    for row in table:
        out.write(",".join("" if not math.isfinite(v) else f"{v + 0.0:.10g}" for v in row) + "\n")
    return out.getvalue().encode("ascii")
