"""``NAME-report.html``: the inspection report for people (SPEC §5), one self-contained page.

A Jinja2 template inside the package lays out the verdict, every check with where it fails, the
drawing of the cam (a disc with its follower, or a drum's developed groove, moved by the page's
slider, its title saying the cam angle), the key numbers, the motion diagrams, pressure angle and
curvature, the dynamics, the setup sheet of each machining program written (``machining_page``)
and the verification. The figures are inline SVG (``figures``), so the page works offline.
"""

from __future__ import annotations

from functools import cache
from typing import TYPE_CHECKING, Any

from camfab import __version__
from camfab.analysis.findings import count

if TYPE_CHECKING:
    import jinja2
    import numpy as np

    from camfab.analysis.record import Analysis


def num(value: float | None, digits: int = 5) -> str:
    if value is None:
        return "—"
    if 1e4 <= abs(value) < 1e9:  # large values in full, not as 4.9907e+05
        return f"{value:.1f}"
    return f"{value:.{digits}g}"


def where(ranges: tuple[tuple[float, float], ...]) -> str:
    """Cam-angle ranges (deg); a point as one angle."""
    return ", ".join(f"{a:.4g}" if f"{a:.4g}" == f"{b:.4g}" else f"{a:.4g}–{b:.4g}"
                     for a, b in ranges)


def _findings(analysis: Analysis) -> list[dict[str, Any]]:
    rows = []
    for f in sorted(analysis.findings, key=lambda f: (f.ok, f.severity != "error")):
        row = "na" if not f.applicable else (
            "" if f.ok else ("fail" if f.severity == "error" else "warn"))
        label = f.id if f.quantity is None else f"{f.id} ({f.quantity})"
        rows.append({"id": label, "severity": f.severity, "row": row, "mark": f.mark,
                     "value": "" if f.value is None else f"{num(f.value)} {f.unit or ''}",
                     "limit": "" if f.limit is None else f"{num(f.limit)} {f.unit or ''}",
                     "where": where(f.ranges_deg) if f.ranges_deg or f.at_deg is None
                     else where(((f.at_deg, f.at_deg),)), "message": f.message})
    return rows


def _numbers(report: dict[str, Any], elsewhere: set[str]) -> list[tuple[str, str]]:
    """The geometry and dynamics keys of the JSON report, as labelled rows, but for those the
    page shows in sections of their own (*elsewhere*: the cam at its speed)."""
    rows = []
    for section in ("geometry", "dynamics"):
        for key, value in report[section].items():
            if value is None or isinstance(value, (list, dict)) or key == "note" \
                    or key in elsewhere:
                continue
            rows.append((column_label(key), show(value)))
    return rows


def _segments(report: dict[str, Any]) -> tuple[list[str], list[list[str]]]:
    keys = [k for k in report["segments"][0] if k not in ("law_coefficients",)]
    steps = [a for c in report["checks"] if c.get("quantity") == "acceleration" and not c["ok"]
             for a, _ in c["ranges_deg"]]
    rows = [[_unbounded(k, seg, steps) if seg[k] is None else show(seg[k]) for k in keys]
            for seg in report["segments"]]
    return [column_label(k) for k in keys], rows


def _unbounded(key: str, segment: dict[str, Any], steps: list[float]) -> str:
    """A value the JSON writes as null: a jerk is unbounded where the acceleration steps at the
    segment's ends (the continuity check's angles, deg); another is not computed."""
    if "jerk" not in key:
        return "—"
    ends = (segment["start_deg"], segment["end_deg"] % 360.0)
    at = [a for a in steps if any(abs(a - e) < 1e-6 for e in ends)]
    where = ", ".join(f"{a:.4g}°" for a in at)
    return f"∞ (acceleration step at {where})" if at else "∞ (acceleration steps)"


def _key_points(report: dict[str, Any]) -> tuple[list[str], list[list[str]]]:
    """A shaped cam's key points of the rise (none for other cams)."""
    points = report["motion"].get("key_points") or []
    if not points:
        return [], []
    keys = list(points[0])
    rows = [[num(p[k]) if isinstance(p[k], float) else str(p[k]) for k in keys]
            for p in points]
    return [k.replace("_", " ") for k in keys], rows


def _verification(report: dict[str, Any]) -> list[tuple[str, str]]:
    rows = []
    for key, value in report["verification"].items():
        if key == "not_produced":
            rows += [(f"not produced: {name}", why) for name, why in value.items()]
        elif isinstance(value, dict):
            rows += [(f"{key.upper()} {column_label(k)}", show(v)) for k, v in value.items()]
        elif value is not None:
            rows.append((column_label(key), show(value)))
    return rows


#: The package's template of the report page.
REPORT_TEMPLATE = "report.html.j2"


@cache
def page_template(name: str) -> jinja2.Template:
    """The page template *name* of the package, compiled once per process (compiling costs a
    build more than filling it in)."""
    import jinja2

    env = jinja2.Environment(loader=jinja2.PackageLoader("camfab", "templates"),
                             autoescape=True, trim_blocks=True, lstrip_blocks=True)
    return env.get_template(name)


def render_report_html(analysis: Analysis) -> bytes:
    """The report page as UTF-8 bytes."""
    from camfab.analysis.sizing_words import sized_words
    from camfab.export import figures
    from camfab.export.machining_page import machining_section
    from camfab.export.report_json import at_speed_dict, report_data

    report = report_data(analysis)
    errors, warnings = count(analysis.findings, "error"), count(analysis.findings, "warning")
    design = analysis.design
    head, rows = _segments(report)
    key_head, key_rows = _key_points(report)
    follower = f"{design.follower.motion} {design.follower.type} follower"
    result = analysis.result
    kind = result.kind_name(design)
    page = page_template(REPORT_TEMPLATE).render(
        version=__version__, name=design.name,
        description=design.description or f"{kind}, {follower}",
        exit_code=analysis.exit_code,
        verdict="PASS" if analysis.exit_code == 0 else "FAIL",
        summary=f"{kind}, {result.motion_words(design)}, {follower}; {errors} error(s), "
                f"{warnings} warning(s)",
        findings=_findings(analysis),
        sized=sized_words(design),
        drawing=figures.cam_drawing(analysis),
        drawing_title=result.drawing_title,
        numbers=_numbers(report, set(at_speed_dict(analysis))), segment_head=head,
        segment_rows=rows,
        key_head=key_head, key_rows=key_rows,
        changes=result.contact_changes(report),
        diagrams=figures.diagrams(analysis),
        dynamics=figures.has_dynamics(analysis),
        stress=_stress_section(analysis, report["dynamics"]),
        vibration=_vibration_section(analysis, report["dynamics"]),
        verification=_verification(report),
        animation=animation_data(analysis), units=design.units,
        inputs=_inputs(report["design"], report["design_units"]),
        lift_table=_lift_rows(report["lift_table"]),
        machining=machining_section(analysis, report["geometry"]) if analysis.machining else [])
    return page.encode("utf-8")


def _stress_section(analysis: Analysis, dynamics: dict[str, Any]) -> dict[str, Any]:
    """The page's contact-stress section: its key numbers and figure, each roller's life, or
    why there are none."""
    from camfab.export.speed_figures import stress_figure

    rows: list[tuple[str, str]] = []
    if dynamics["contact_stress_max_MPa"] is not None:
        xy = dynamics.get("contact_stress_max_at_xy_mm")
        along = dynamics.get("contact_stress_max_at_mm")
        rows += [("largest contact stress (MPa)", num(dynamics["contact_stress_max_MPa"])),
                 ("at the cam angle (°)", num(dynamics["contact_stress_max_at_deg"])),
                 ("on", dynamics["contact_stress_on"])]
        if xy is not None:
            rows.append(("at the point of the cam (mm)", f"({num(xy[0])}, {num(xy[1])})"))
        if along is not None:
            rows.append((f"along the contact line, {dynamics['contact_stress_max_at_mm_from']} "
                         "(mm)", num(along)))
        shape, radius = dynamics["contact_stress_cam_shape"], dynamics[
            "contact_stress_cam_radius_mm"]
        rows += [("the flank across the contact line (mm)" if along is not None else
                  "the cam there, its radius of curvature (mm)",
                  shape if radius is None else f"{shape}, {num(abs(radius))}"),
                 ("contact", dynamics["contact"]),
                 ("contact length (mm)", num(dynamics["contact_length_mm"])),
                 ("effective modulus E* (MPa)", num(dynamics["effective_modulus_MPa"]))]
        limit = analysis.design.limits.contact_stress
        rows.append(("allowed (MPa)", "not checked (no limits.contact_stress)" if limit is None
                     else num(limit)))
    lives = [(f"{life['roller']}: L10 life (h)", num(life["hours"]))
             for life in dynamics.get("roller_life_by_roller") or []]
    lives += [(f"{life['roller']}: equivalent load (N), revolutions a turn",
               f"{num(life['equivalent_load_N'])}, {num(life['revolutions_per_turn'])}")
              for life in dynamics.get("roller_life_by_roller") or []]
    notes = [note for note in (dynamics.get("contact_stress_note"),
                               dynamics.get("roller_life_note")) if note]
    return {"rows": rows, "lives": lives, "notes": notes, "figure": stress_figure(analysis)}


def _vibration_section(analysis: Analysis, dynamics: dict[str, Any]) -> dict[str, Any]:
    """The page's follower-train section: its key numbers, each dwell's residual vibration,
    where a positive drive changes sides, and its figures; or why there are none."""
    from camfab.export.speed_figures import spectrum_figure, vibration_figure

    if dynamics["natural_frequency_Hz"] is None:
        return {"rows": [], "dwells": [], "changes": [],
                "notes": [dynamics.get("vibration_note") or ""], "figure": None,
                "spectrum": None}
    jump = dynamics["dynamic_jump_speed_rpm"]
    searched = dynamics["dynamic_jump_searched_to_rpm"]
    rows = [("natural frequency (Hz)", num(dynamics["natural_frequency_Hz"])),
            ("over the cam's turning frequency", num(dynamics["frequency_ratio"])),
            ("damping ratio ζ of the train's own damper (follower.damping_ratio)",
             num(dynamics["damping_ratio"])),
            ("with the spring's damping (spring.damping adds to it), in all",
             num(_total_zeta(analysis))),
            ("largest dynamic error x − s (mm)", f"{num(dynamics['dynamic_error_max_mm'])} at "
             f"{num(dynamics['dynamic_error_max_at_deg'])}°"),
            ("of it, the train's largest compression under the load (mm)",
             num(dynamics["static_deflection_max_mm"])),
            ("and its vibration about that, at most (mm)",
             num(dynamics["dynamic_vibration_max_mm"])),
            ("largest residual vibration in a dwell, peak to peak (mm)",
             num(dynamics["residual_vibration_mm"])),
            ("least contact force (N)", f"{num(dynamics['dynamic_min_contact_force_N'])} at "
             f"{num(dynamics['dynamic_min_contact_force_at_deg'])}°"),
            ("largest contact force (N)", num(dynamics["dynamic_max_contact_force_N"]))]
    if "flank_changes" in dynamics:  # a positive drive: the force's sign is the side
        rows[-2:] = [("largest force pushing the follower along its motion (N)",
                      num(dynamics["dynamic_max_contact_force_N"])),
                     ("largest force pulling it back (N)",
                      f"{num(-dynamics['dynamic_min_contact_force_N'])} at "
                      f"{num(dynamics['dynamic_min_contact_force_at_deg'])}°")]
    if searched is not None:
        rows.append(("speed at which the follower first leaves the cam (rpm)",
                     num(jump) if jump is not None else f"none up to {num(searched)}"))
    dwells = [(num(d["start_deg"]), num(d["end_deg"]), num(d["peak_to_peak_mm"]))
              for d in dynamics["residual_vibration_by_dwell"]]
    changes = [(num(c["cam_angle_deg"]), c["onto"]) for c in dynamics.get("flank_changes", [])]
    return {"rows": rows, "dwells": dwells, "changes": changes, "notes": [],
            "figure": vibration_figure(analysis), "spectrum": spectrum_figure(analysis),
            "polydyne": _polydyne_section(analysis, dynamics.get("polydyne"))}


def _polydyne_section(analysis: Analysis, polydyne: dict[str, Any] | None,
                      ) -> dict[str, Any] | None:
    """A polydyne cam's part of the follower-train section: its key numbers and its two
    figures (the motions side by side, the vibration against speed); None for another cam."""
    from camfab.export.speed_figures import band_figure, polydyne_figure

    if polydyne is None:
        return None
    rows = [("cut for (rpm)", num(polydyne["speed_rpm"])),
            ("largest difference of the cam's lift from the motion asked, |s − x| (mm)",
             num(polydyne["cam_minus_output_max_mm"])),
            ("residual vibration at that speed (mm)", num(polydyne["residual_vibration_mm"])),
            ("the motion list cut directly as the cam, there (mm)",
             num(polydyne["direct_residual_vibration_mm"])),
            ("speeds about it where the polydyne cam rings less (rpm)",
             f"{num(polydyne['better_from_rpm'])} to {num(polydyne['better_to_rpm'])}")]
    return {"rows": rows, "figure": polydyne_figure(analysis), "band": band_figure(analysis)}


def _total_zeta(analysis: Analysis) -> float | None:
    """The follower train's damping ratio with the spring's damping added (None without it)."""
    shaken = None if analysis.at_speed is None else analysis.at_speed.vibration
    return None if shaken is None else shaken.train.total_zeta


def animation_data(analysis: Analysis) -> dict[str, Any]:
    """The animation's readout: at each frame's cam angle (the motion table's rows, at least
    1° apart: :func:`camfab.export.figures.frame_angles`), the cam angle, the lift, its
    derivatives (at the design's speed, or per radian), the pressure angle, the radii of
    curvature and the contact force where there are dynamics; labels with units, lengths in
    the design's units. A column of the table empty at every row (a globoid's pitch radius)
    is left out."""
    import numpy as np

    from camfab.export.figures import frame_angles
    from camfab.export.motion_csv import motion_table

    design, units = analysis.design, analysis.units
    columns, table = motion_table(analysis)
    theta = frame_angles(design.table_step)
    every = max(1, round(len(table) / len(theta)))
    table = table[::every][: len(theta)]
    labels, values = [], []
    length = design.mm_per_unit
    for k, name in enumerate(columns):
        column = table[:, k]
        if not np.isfinite(column).any():
            continue
        label = column_label(name)
        if name.endswith("_mm") and design.units == "in":
            column, label = column / length, label.replace("(mm)", "(in)")
        labels.append(label)
        values.append(column)
    if design.cam.omega is None:
        motion = analysis.program.evaluate(theta)
        for order in (1, 2, 3):
            derivative = motion[order]
            scale = 1.0 if units.oscillating else 1.0 / length
            unit = units.unit(order, False).replace("mm", design.units)
            labels.append(f"{('s′', 's″', 's‴')[order - 1]} ({unit})")
            values.append(np.degrees(derivative) if units.oscillating else derivative * scale)
    dyn = analysis.dynamics
    if dyn is not None and dyn.force_N is not None:
        labels.append("contact force (N)")
        values.append(np.interp(theta, dyn.theta, dyn.force_N, period=2 * np.pi))
    rows = np.column_stack(values)
    # rounding's residue (3e-14 where a value is zero) shown as 0: far below its column's
    # typical size (the median of its values that are finite and not 0)
    for k in range(rows.shape[1]):
        column = np.abs(rows[:, k])
        typical = np.sort(column[np.isfinite(column) & (column > 0.0)])
        if typical.size:
            rows[column < 1e-9 * typical[typical.size // 2], k] = 0.0
    return {"labels": labels, "rows": six_digits(rows)}


def six_digits(values: np.ndarray) -> list[list[float | None]]:
    """The rows of *values* (2-D) as lists of numbers to 6 significant digits (what
    ``float(f"{v:.6g}")`` gives), a value that is not finite as None. The digits are written by
    one ``%`` format of every value and read back by numpy: some ten times quicker than a
    format per value, with the same numbers (both round correctly)."""
    import numpy as np

    flat = values.ravel()
    good = np.isfinite(flat)
    text = ("%.6g," * flat.size) % tuple(np.where(good, flat, 0.0).tolist())
    numbers = np.array(text[:-1].split(","), dtype=float) if flat.size else flat
    rows = numbers.reshape(values.shape).tolist()
    if not good.all():
        for i, j in zip(*np.nonzero(~good.reshape(values.shape)), strict=True):
            rows[i][j] = None
    return rows


#: Units in the keys of camfab's tables, as written on the page; the longer suffix first where
#: one ends another (``_rad_per_rad`` before ``_per_rad``: an arm's swing per radian of cam
#: angle reads "rad/rad", not "rad (/rad)").
_UNITS = (("_mm_s", "mm/s"), ("_m_s3", "m/s³"), ("_m_s2", "m/s²"), ("_m_s", "m/s"),
          ("_rad_s3", "rad/s³"), ("_rad_s2", "rad/s²"), ("_rad_s", "rad/s"),
          ("_mm_per_rad3", "mm/rad³"), ("_mm_per_rad2", "mm/rad²"), ("_mm_per_rad", "mm/rad"),
          ("_rad_per_rad3", "rad/rad³"), ("_rad_per_rad2", "rad/rad²"),
          ("_rad_per_rad", "rad/rad"), ("_per_rad3", "/rad³"), ("_per_rad2", "/rad²"),
          ("_per_rad", "/rad"), ("_mm3", "mm³"), ("_mm2", "mm²"),
          ("_mm", "mm"), ("_deg", "°"), ("_rpm", "rpm"), ("_N_m", "N·m"),
          ("_N_per_mm", "N/mm"), ("_N", "N"), ("_kg", "kg"), ("_MPa", "MPa"), ("_Hz", "Hz"),
          ("_h", "h"))


def column_label(key: str) -> str:
    """A table key as a label: ``max_acceleration_m_s2`` → ``max acceleration (m/s²)``."""
    for suffix, unit in _UNITS:
        if key.endswith(suffix):
            return f"{key[: -len(suffix)].replace('_', ' ')} ({unit})"
    return key.replace("_", " ")


def _inputs(record: dict[str, Any], units: dict[str, str],
            prefix: str = "") -> list[tuple[str, str]]:
    """The design's every input as (key, value) rows, nested keys dotted, each value with its
    unit (*units*, by dotted key: the JSON's ``design_units``)."""
    rows: list[tuple[str, str]] = []
    for key, value in record.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict):
            rows += _inputs(value, units, f"{name}.")
        elif isinstance(value, list) and value and isinstance(value[0], dict):
            for i, item in enumerate(value):
                rows += _inputs({k: v for k, v in item.items() if v is not None}, units,
                                f"{name}[{i}].")
        elif value is not None:
            unit = units.get(name)
            shown = show(value)
            rows.append((name, shown if unit is None else
                         f"{shown}°" if unit == "deg" else f"{shown} {unit}"))
    return rows


def show(value: Any) -> str:
    """A value on the page: numbers as :func:`num`, yes/no for booleans, lists joined."""
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        return num(value)
    if isinstance(value, list):
        return ", ".join(show(v) for v in value)
    return str(value)


def _lift_rows(table: dict[str, Any]) -> dict[str, Any]:
    """The lift table in six side-by-side blocks of rows (a page holds it)."""
    rows = [[num(v) for v in row] for row in table["rows"]]
    blocks = 6
    depth = -(-len(rows) // blocks)
    return {"unit": table["unit"], "step": num(table["step_deg"]), "depth": depth,
            "tolerance": num(table["inspection_tolerance_mm"]),
            "blocks": [rows[i * depth:(i + 1) * depth] for i in range(blocks)]}
