"""Readable terminal summaries (``camfab check``, ``camfab laws``) with rich tables."""

from __future__ import annotations

from typing import TYPE_CHECKING

from rich.console import Console
from rich.markup import escape
from rich.table import Table

from camfab.analysis.record import terse
from camfab.terminal import fit

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis


def _console() -> Console:
    return Console(highlight=False, soft_wrap=False, width=120)


_num = terse


def print_summary(analysis: Analysis) -> None:
    """The design, its motion program with peak kinematics, and every check."""
    from camfab.analysis.findings import count
    from camfab.analysis.sizing_words import sized_words
    from camfab.export.report_html import column_label

    design, units = analysis.design, analysis.units
    console = _console()
    cam, fol = design.cam, design.follower
    speed = f"{cam.speed_rpm:g} rpm" if cam.speed_rpm else "no speed given"
    motion = analysis.result.motion_words(design)
    console.print(f"[bold]{design.name}[/bold] — {cam.type} cam, {motion}, {speed}; "
                  f"{fol.motion} {fol.type} follower")
    if design.description:
        console.print(design.description, markup=False, emoji=False)
    with_speed = cam.omega is not None
    table = Table(title="motion program", title_justify="left")
    for name in ("#", "segment", "law", "θ (°)", column_label(units.lift_key)):
        table.add_column(fit(name), overflow="fold")  # (no "…" to stand in for)
    for order, label in ((1, "v"), (2, "a"), (3, "j")):
        table.add_column(fit(f"max {label} ({units.unit(order, with_speed)})"), justify="right")
    numbers = analysis.result.numbers
    table.add_column(fit("max φ (°)"), justify="right")
    for stats in analysis.segments:
        peaks = stats.max_si if stats.max_si is not None else stats.max_per_rad
        extra = [_num(numbers.segment_pressure[stats.index].value)]
        cells = (str(stats.index), stats.kind, stats.law,
                 f"{stats.start_deg:g}–{stats.end_deg:g}", f"{stats.lift:.6g}",
                 *(_num(v) for v in peaks), *extra)
        table.add_row(*(fit(cell) for cell in cells))
    console.print(table)
    for line in analysis.result.summary(analysis):
        console.print(line)
    speed_line = _at_speed_words(analysis)
    if speed_line:
        console.print(speed_line, markup=False, emoji=False)
    sized = sized_words(design)
    if sized is not None:
        console.print(sized, markup=False, emoji=False)
    for finding in analysis.findings:
        colour = ("dim" if not finding.applicable else "green" if finding.ok else
                  "red" if finding.severity == "error" else "yellow")
        mark = f"[{colour}]{finding.mark}[/{colour}]"
        console.print(f"{mark} {finding.id}: {escape(finding.message)}", emoji=False)
    errors, warnings = count(analysis.findings, "error"), count(analysis.findings, "warning")
    verdict = "[red]FAIL[/red]" if analysis.exit_code else "[green]OK[/green]"
    console.print(f"{verdict}: {errors} error(s), {warnings} warning(s)")


def _at_speed_words(analysis: Analysis) -> str | None:
    """The cam at its speed in a line: the largest contact stress, the follower train's
    natural frequency and the vibration it leaves in the dwells, the roller's life; None where
    none is computed."""
    speed = analysis.at_speed
    if speed is None:
        return None
    parts = []
    if speed.stress is not None:
        parts.append(f"contact stress up to {_num(speed.stress.max_MPa)} MPa at "
                     f"{_num(speed.stress.max_at_deg)}°")
    shaken = speed.vibration
    if shaken is not None:
        words = (f"follower train at {_num(shaken.natural_Hz)} Hz "
                 f"({_num(shaken.frequency_ratio)}× the cam's), dynamic error up to "
                 f"{_num(1000.0 * shaken.max_error_m)} mm (its vibration about the train's "
                 f"compression up to {_num(1000.0 * shaken.max_ringing_m)} mm)")
        if shaken.residual_m is not None:
            words += f", {_num(1000.0 * shaken.residual_m)} mm left ringing in a dwell"
        parts.append(words)
    if speed.band is not None:
        band = speed.band
        parts.append(f"a polydyne cam: the motion cut directly would leave "
                     f"{_num(1000.0 * float(band.direct_m[band.at]))} mm ringing; this one rings "
                     f"less from {_num(band.low_rpm)} to {_num(band.high_rpm)} rpm")
    if speed.life is not None:
        life = speed.life
        parts.append(f"{life.names[life.least]}'s bearing L10 {_num(life.hours_min)} h")
    return f"at speed: {'; '.join(parts)}" if parts else None


def laws_table() -> None:
    """Every motion law with aliases, Cv, Ca, Cj and its continuity next to dwells."""
    from camfab.motion.laws import LAWS, standard_law

    table = Table(title="motion laws (peak coefficients of the normalised rise f(u))",
                  title_justify="left")
    for name in ("law", "aliases", "Cv", "Ca", "Cj", "continuity"):
        table.add_column(name, justify="right" if name in ("Cv", "Ca", "Cj") else "left")
    for info in LAWS:
        try:
            law = standard_law(info.name)
        except KeyError:  # polynomial and table: they depend on the design's data
            cv = ca = cj = "by data"
        else:
            cv, ca, cj = (_num(c) for c in law.coefficients)
            if info.name == "uniform-velocity":
                ca, cj = "∞ at ends", "—"
        aliases = ", ".join(info.aliases)
        if info.params:
            aliases = (aliases + "; " if aliases else "") + "takes " + ", ".join(info.params)
        table.add_row(*(fit(cell) for cell in (info.name, aliases, cv, ca, cj,
                                                info.continuity)))
    _console().print(table)
