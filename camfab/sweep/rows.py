"""One variant of a sweep as one row: its design checked and analysed (no files written), and
the key numbers a designer compares variants by.

A row is a tuple: the variant's index, its varied values, its status (``OK``, ``FAIL`` with the
checks that failed, ``INVALID`` with the design's one-line message), then the numbers of
:data:`NUMBERS` (None where the design has none: no speed, no dynamics, no face width).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.workers import Died

#: The key numbers of a row, by column name, in order (units in the names; the motion's are SI:
#: m/s, m/s², m/s³ for a translating follower, rad/s, rad/s², rad/s³ for an oscillating one,
#: as ``motion_units`` says; the cam at its speed last: its contact stress, the vibration left
#: in its dwells by an elastic follower train and the speed at which it first leaves the cam,
#: its roller's bearing life). A drum's pressure
#: angle is its worst (at the groove's root), its curvature the developed groove's, its undercut
#: the groove check's (a wall that folds), as for a groove cam.
NUMBERS = (
    "pressure_angle_max_deg",
    "pressure_angle_max_at_deg",
    "profile_min_radius_of_curvature_mm",
    "undercut",
    "max_velocity",
    "max_acceleration",
    "max_jerk",
    "motion_units",
    "face_width_required_mm",
    "jump_speed_rpm",
    "max_contact_force_N",
    "min_contact_force_N",
    "contact_stress_max_MPa",
    "residual_vibration_mm",
    "dynamic_jump_speed_rpm",
    "roller_life_h",
)
#: The columns ``--size`` adds: the least base radius (a drum's radius) meeting the limits.
SIZE_NUMBERS = ("least_size_mm",)
#: The leading columns of every row, before the varied keys.
LEAD = ("variant",)
#: The status columns, after the varied keys.
STATUS = ("status", "message")
#: How a FAIL row's message begins, before the ids of the checks that failed (comma-separated).
FAILED = "failed: "

Row = tuple[Any, ...]


def columns(paths: Sequence[str], size: bool) -> tuple[str, ...]:
    """The table's columns for the varied *paths* (and the least size when *size*)."""
    return (*LEAD, *paths, *STATUS, *NUMBERS, *(SIZE_NUMBERS if size else ()))


def evaluate(base: dict[str, Any], file: str, folder: Path,
             keys: Sequence[tuple[str | int, ...]],
             batch: Sequence[tuple[int, tuple[Any, ...]]], size: bool = False) -> list[Row]:
    """The rows of a *batch* of variants (index, values) of the design data *base* from *file*
    (its table files found from *folder*): each validated and analysed. A variant that fails in
    any way is a row, never an exception."""
    import warnings

    with warnings.catch_warnings():  # what a design does wrong is its row, not noise
        warnings.simplefilter("ignore", RuntimeWarning)
        rows = [row(base, file, folder, keys, index, values, size) for index, values in batch]
    _freeze_once()
    return rows


_FROZEN: list[bool] = []


def _freeze_once() -> None:
    """After a process's first batch, what it has imported is put out of the garbage
    collector's reach (:func:`gc.freeze`), as the local pool's workers have it from the process
    they are forked from: a Dask worker's collections then skip the libraries' objects."""
    if not _FROZEN:
        import gc

        gc.freeze()
        _FROZEN.append(True)


def row(base: dict[str, Any], file: str, folder: Path, keys: Sequence[tuple[str | int, ...]],
        index: int, values: tuple[Any, ...], size: bool = False) -> Row:
    """Variant *index* with *values* at *keys*: its row (see the module)."""
    from camfab.sweep.vary import with_values

    blank = (None,) * (len(NUMBERS) + (len(SIZE_NUMBERS) if size else 0))
    try:
        data = with_values(base, keys, values)
    except LookupError as exc:
        return (index, *values, "INVALID", f"{file}: {exc}", *blank)
    status, message, analysis = checked(data, file, folder)
    if analysis is None:
        return (index, *values, status, message, *blank)
    numbers = key_numbers(analysis)
    if size:
        numbers = (*numbers, least_size(analysis.design))
    return (index, *values, status, message, *numbers)


def checked(data: dict[str, Any], file: str,
            folder: Path) -> tuple[str, str, Analysis | None]:
    """The design data *data* from *file* (its table files found from *folder*) validated and
    analysed without files: its status (``OK``, ``FAIL``, ``INVALID``), its message (the
    checks that failed, or the design's one-line error) and its analysis (None when
    INVALID). A design that fails in any way is a status, never an exception."""
    from camfab.errors import CamfabError
    from camfab.pipeline import analyse, design_from_mapping

    try:
        design = design_from_mapping(data, file, folder)
        analysis = analyse(design, advice=False)
    except CamfabError as exc:
        return "INVALID", " ".join(str(exc).split()), None
    except Exception as exc:  # a design the analysis cannot take: its status, not an end
        return "INVALID", (f"{file}: cannot analyse: "
                           f"{type(exc).__name__}: {' '.join(str(exc).split())}"), None
    failed = [f.id for f in analysis.findings if not f.ok and f.severity == "error"]
    message = f"{FAILED}{', '.join(dict.fromkeys(failed))}" if failed else ""
    return ("FAIL" if failed else "OK"), message, analysis


def died_row(variant: tuple[int, tuple[Any, ...]], died: Died, size: bool = False) -> Row:
    """The row of a variant (index, values) whose worker process died analysing it: FAIL,
    saying so, its numbers blank."""
    index, values = variant
    blank = (None,) * (len(NUMBERS) + (len(SIZE_NUMBERS) if size else 0))
    return (index, *values, "FAIL", died.words(), *blank)


def key_numbers(analysis: Analysis) -> tuple[Any, ...]:
    """The numbers of :data:`NUMBERS` of *analysis*."""
    geometry = analysis.result.report_geometry(analysis)
    pressure = next((f for f in analysis.findings if f.id == "pressure_angle"), None)
    angle = geometry.get("pressure_angle_max_deg",
                         None if pressure is None else pressure.value)
    # where: beside the worst of the kind's pressure angles (a drum's is at its groove's root)
    at = next((geometry.get(k.removesuffix("_deg") + "_at_deg") for k, v in geometry.items()
               if k.endswith("pressure_angle_max_deg") and v is not None and v == angle), None)
    curvature = geometry.get("profile_min_radius_of_curvature_mm",
                             geometry.get("developed_min_radius_of_curvature_mm"))
    # a drum's or a groove cam's walls fold under its groove check
    undercut = next((f for f in analysis.findings if f.id == "undercut"),
                    next((f for f in analysis.findings if f.id == "groove"), None))
    maxima: list[float | None] = []
    for order in range(3):  # None without a speed, or where a law's is unbounded (a step)
        found = [s.max_si[order] for s in analysis.segments if s.max_si is not None]
        maxima.append(max(found) if found and None not in found else None)
    units = ("rad/s, rad/s², rad/s³" if analysis.design.follower.oscillating
             else "m/s, m/s², m/s³")
    dyn = analysis.dynamics
    return (
        _number(angle),
        _number(at),
        _number(curvature),
        None if undercut is None else not undercut.ok,
        *(_number(m) for m in maxima),
        units,
        _number(geometry.get("face_width_required_mm")),
        None if dyn is None else _number(dyn.jump_speed_rpm),
        None if dyn is None else _number(dyn.max_force_N),
        None if dyn is None else _number(dyn.min_force_N),
        *_at_speed_numbers(analysis),
    )


def _at_speed_numbers(analysis: Analysis) -> tuple[float | None, ...]:
    """The largest contact stress (MPa), the largest residual vibration in a dwell (mm
    peak to peak), the least speed at which the elastic follower first leaves the cam (rpm)
    and the roller's least L10 life (h), None where not computed."""
    speed = analysis.at_speed
    if speed is None:
        return None, None, None, None
    shaken = speed.vibration
    residual = None if shaken is None or shaken.residual_m is None else 1000.0 * shaken.residual_m
    return (None if speed.stress is None else _number(speed.stress.max_MPa), _number(residual),
            None if shaken is None else _number(shaken.jump_speed_rpm),
            None if speed.life is None else _number(speed.life.hours_min))


def least_size(design: Any) -> float | None:
    """The least base radius (a drum's radius; mm) that meets *design*'s limits, None where
    camfab does not size the cam or no size meets them."""
    from camfab.design.cam_types import CAM_TYPES
    from camfab.pipeline import size_design

    spec = CAM_TYPES[design.cam.type]
    if not spec.auto_keys:
        return None
    key = next(k for k in spec.auto_keys if k.startswith("cam."))
    try:
        return _number(size_design(design, frozenset({key})).size)
    except (ArithmeticError, ValueError):
        return None


def _number(value: Any) -> float | None:
    """*value* as a float to 12 significant digits, as the JSON report gives it (far below any
    tolerance: 20 mm, not 19.999999999999996); None, NaN and infinities as None (a table has no
    room for them)."""
    if value is None:
        return None
    number = float(value)
    if number != number or abs(number) == float("inf"):
        return None
    return float(f"{number:.12g}")
