"""Lengths, angles, the speed and the cam centre given on the command line or in a follower
file, each checked and refused with where it was given."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from camfab.design.rules import MIN_TABLE_STEP_DEG
from camfab.errors import InspectionError

if TYPE_CHECKING:
    from camfab.design import Design
    from camfab.inspect.options import InspectOptions

#: The lift table's row step when neither the command line nor a design gives one: 1°, like the
#: design's motion table.
DEFAULT_STEP = math.radians(1.0)

#: ``--step`` (deg): the range of a design's ``table_step``, from 0.01° (36,000 rows, the
#: follower run at each) to 30°. The angles the follower is run at grow as 1/step.
STEP_RANGE_DEG = (MIN_TABLE_STEP_DEG, 30.0)

#: ``--smooth`` (deg): from 0.1°, the step the follower is run at (a window of less is that of
#: two steps), to 30°; the fit over the window costs its width in steps at every angle.
SMOOTH_RANGE_DEG = (0.1, 30.0)


def length(what: str, raw: object, units: str, file: str = "", positive: bool = False) -> float:
    """A length (mm) from a number in *units* or a string with a unit; a refusal names *what*
    (an option, or a key of *file*)."""
    from camfab.design.units import LENGTH, convert
    from camfab.errors import DesignError

    where = f"{file}: {what}" if file else what
    try:
        value = convert(raw, LENGTH, units)
    except DesignError as exc:
        raise InspectionError(where, str(exc)) from None
    if positive and value <= 0.0:
        raise InspectionError(where, f"must be > 0 (got {raw})")
    return value


def optional_length(what: str, raw: str | None, units: str, positive: bool = False
                    ) -> float | None:
    """:func:`length` of *raw*, or None when it is not given."""
    return None if raw is None else length(what, raw, units, positive=positive)


def angle(what: str, raw: str, range_deg: tuple[float, float]) -> float:
    """An angle (rad) from a number of degrees or a string with a unit, within *range_deg*
    (deg, both ends included)."""
    from camfab.design.units import ANGLE, convert
    from camfab.errors import DesignError

    try:
        value = convert(raw, ANGLE)
    except DesignError as exc:
        raise InspectionError(what, str(exc)) from None
    low, high = range_deg
    if not math.radians(low) * (1 - 1e-12) <= value <= math.radians(high) * (1 + 1e-12):
        raise InspectionError(what, f"must be from {low:g}° to {high:g}° (got {raw})")
    return value


def row_step(options: InspectOptions, design: Design | None) -> float:
    """The lift table's row step (rad): ``--step``, else the design's ``table_step`` (which the
    design rules hold to the same range), else 1°."""
    if options.step is not None:
        return angle("--step", options.step, STEP_RANGE_DEG)
    return DEFAULT_STEP if design is None else design.table_step


def cam_speed(options: InspectOptions, extra: dict[str, Any], design: Design | None
              ) -> float | None:
    """The cam's speed (rpm): ``--speed``, else the follower file's ``speed_rpm``, else the
    design's; None when none gives one."""
    from camfab.design.units import SPEED, convert
    from camfab.errors import DesignError

    raw = options.speed if options.speed is not None else extra.get("speed_rpm")
    if raw is None:
        return design.cam.speed_rpm if design is not None else None
    what = "--speed" if options.speed is not None else f"{extra['_file']}: speed_rpm"
    try:
        value = convert(raw, SPEED)
    except DesignError as exc:
        raise InspectionError(what, str(exc)) from None
    if value <= 0.0:
        raise InspectionError(what, f"must be > 0 (got {raw})")
    return value


def cam_centre(raw: str | None, mm_per_unit: float) -> tuple[float, float]:
    """The cam centre (mm) from ``--centre X,Y`` in the outline file's units; the origin when
    not given."""
    if raw is None:
        return (0.0, 0.0)
    parts = raw.replace(";", ",").split(",")
    try:
        x, y = (float(p) for p in parts)
    except ValueError:
        raise InspectionError("--centre", f"must be X,Y in the outline's coordinates (got "
                              f"{raw!r})") from None
    from camfab.export.outline import MAX_COORDINATE_MM

    if not (math.isfinite(x) and math.isfinite(y)):
        raise InspectionError("--centre", f"must be finite (got {raw!r})")
    if not max(abs(x), abs(y)) * mm_per_unit <= MAX_COORDINATE_MM:
        raise InspectionError("--centre", f"must lie within {MAX_COORDINATE_MM:,.0f} mm of the "
                              f"origin (got {raw!r})")
    return (x * mm_per_unit, y * mm_per_unit)
