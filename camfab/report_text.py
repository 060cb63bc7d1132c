"""Readable terminal summaries (``camfab check``, ``camfab laws``) with rich tables."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from rich.console import Console
from rich.markup import escape
from rich.table import Table

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.geometry.disc_geometry import DiscGeometry


def _console() -> Console:
    return Console(highlight=False, soft_wrap=False, width=120)


def _num(value: float | None, digits: int = 4) -> str:
    if value is None or not math.isfinite(value):
        return "∞"
    return f"{value:.{digits}g}"


def print_summary(analysis: Analysis) -> None:
    """The design, its motion program with peak kinematics, and every check."""
    from camfab.analysis.cam_checks import CamNumbers
    from camfab.analysis.drum_checks import DrumNumbers
    from camfab.analysis.findings import count

    design, units = analysis.design, analysis.units
    console = _console()
    cam, fol = design.cam, design.follower
    speed = f"{cam.speed_rpm:g} rpm" if cam.speed_rpm else "no speed given"
    motion = "moving toward −X" if cam.linear else cam.rotation
    console.print(f"[bold]{design.name}[/bold] — {cam.type} cam, {motion}, {speed}; "
                  f"{fol.motion} {fol.type} follower")
    if design.description:
        console.print(design.description, markup=False, emoji=False)
    with_speed = cam.omega is not None
    table = Table(title="motion program", title_justify="left")
    for name in ("#", "segment", "law", "θ (deg)", units.lift_key.replace("_", " ")):
        table.add_column(name)
    for order, label in ((1, "v"), (2, "a"), (3, "j")):
        table.add_column(f"max {label} ({units.unit(order, with_speed)})", justify="right")
    numbers = analysis.numbers
    if numbers is not None:
        table.add_column("max φ (deg)", justify="right")
    for stats in analysis.segments:
        peaks = stats.max_si if stats.max_si is not None else stats.max_per_rad
        extra = [] if numbers is None else [_num(numbers.segment_pressure[stats.index].value)]
        table.add_row(str(stats.index), stats.kind, stats.law,
                      f"{stats.start_deg:g}–{stats.end_deg:g}", f"{stats.lift:.6g}",
                      *(_num(v) for v in peaks), *extra)
    console.print(table)
    geom = analysis.geometry
    dense = analysis.drum
    if dense is not None and isinstance(numbers, DrumNumbers):
        d = dense.drum
        console.print(
            f"drum: radius {_num(d.radius)} mm, groove floor at {_num(d.root)} mm, "
            f"{_num(2 * d.roller)} mm wide, roller centre at z = {_num(d.start)} mm at zero lift; "
            f"pressure angle up to {_num(numbers.root_pressure.value)}° at the floor; developed "
            f"groove's smallest radius of curvature {_num(numbers.min_developed_radius.value)} mm")
    if geom is not None and isinstance(numbers, CamNumbers):
        convex = numbers.pitch_min_convex.value
        console.print(
            f"cam: base radius {_num(design.cam.base_radius)} mm, prime radius "
            f"{_num(geom.cam.prime_radius)} mm, largest radius {_num(numbers.max_radius_mm)} mm; "
            f"pitch curve's smallest convex radius {_num(convex)} mm; {_profile_words(geom)}; "
            f"the follower run over it strays {geom.lift.max_mm:.2g} mm from the design")
    walls = analysis.groove
    if walls is not None:
        changes = walls.contact.changes_deg
        moves = ("contact passes to the other wall (the roller reverses its spin) at "
                 + ", ".join(f"{a:.4g}°" for a in changes) if changes else
                 "the follower never accelerates: no wall carries it")
        console.print(
            f"groove: {_num(walls.width)} mm wide (roller {_num(walls.roller_radius)} mm, "
            f"clearance {_num(walls.clearance)} mm), {_num(walls.depth)} mm deep in a plate "
            f"{_num(walls.thickness)} mm thick of radius {_num(walls.outer_radius)} mm; {moves}")
    partner = analysis.partner
    if partner is not None and partner.contact is not None:
        sides = partner.sides
        held = partner.hold
        passes = ", ".join(f"{math.degrees(float(a)):.4g}° (onto {sides[int(to)]})"
                           for a, to in zip(partner.contact.changes, partner.contact.onto,
                                            strict=True)) or "nowhere"
        console.print(f"held on both sides: gap up to {held.max_gap:.2g} mm, interference up to "
                      f"{held.max_interference:.2g} mm; the load passes sides at {passes}")
    linear = analysis.linear
    if linear is not None:
        from camfab.analysis.linear_checks import LinearNumbers

        lin = linear.cam
        convex = numbers.pitch_min_convex.value if isinstance(numbers, LinearNumbers) else None
        pace = ("" if cam.speed_rpm is None else
                f", traversing at {_num(lin.stroke * cam.speed_rpm / 60.0)} mm/s")
        console.print(
            f"plate: stroke {_num(lin.stroke)} mm{pace}, base height {_num(lin.base_height)} mm, "
            f"{_num(linear.plate_length)} mm long; pitch curve's smallest convex radius "
            f"{_num(convex)} mm; "
            f"outline of {len(linear.outline.vertices)} lines and arcs; the follower run over "
            f"it strays {linear.lift.max_mm:.2g} mm from the design")
    shape = analysis.shape
    if shape is not None:
        flank = ("straight flanks" if shape.flank_radius is None else
                 f"flank radius {_num(shape.flank_radius)} mm")
        console.print(
            f"shape: {flank}, nose radius {_num(shape.nose_radius)} mm, nose centre "
            f"{_num(shape.nose_centre_distance)} mm from the cam centre; contact passes from "
            f"flank to nose at {_num(math.degrees(shape.flank_end_angle))}°")
    for finding in analysis.findings:
        colour = ("dim" if not finding.applicable else "green" if finding.ok else
                  "red" if finding.severity == "error" else "yellow")
        mark = f"[{colour}]{finding.mark}[/{colour}]"
        console.print(f"{mark} {finding.id}: {escape(finding.message)}", emoji=False)
    errors, warnings = count(analysis.findings, "error"), count(analysis.findings, "warning")
    verdict = "[red]FAIL[/red]" if analysis.exit_code else "[green]OK[/green]"
    console.print(f"{verdict}: {errors} error(s), {warnings} warning(s)")


def _profile_words(geom: DiscGeometry) -> str:
    count = len(geom.profile.vertices)
    if geom.exact:
        return f"exact profile of {count} arcs and lines"
    return f"profile of {count} points within {geom.tolerance:.2g} mm"


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
        table.add_row(info.name, aliases, cv, ca, cj, info.continuity)
    _console().print(table)
