"""What a tuning found, in words: the lines ``camfab tune`` prints and the rows the report
shows — the objective before and after, the values changed, every limit's margin before and
after, and why nothing was written when no candidate meets every limit."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from camfab.tune.margins import Margin

if TYPE_CHECKING:
    from camfab.tune.plan import Plan
    from camfab.tune.search import Search
    from camfab.tune.trials import Trial


def number(value: float | None, unit: str = "") -> str:
    """*value* to 4 significant digits (a large one whole, in thousands: 17,650) with its
    *unit* (``–`` for none)."""
    if value is None or not math.isfinite(value):
        return "–"
    text = f"{value:,.0f}" if 1e4 <= abs(value) < 1e12 else f"{value:.4g}"
    return f"{text} {unit}".strip()


def objective_line(tuning: Plan, search: Search) -> str:
    """``the largest residual vibration over …: 0.15 mm → 0.012 mm (−92 %)``."""
    objective = tuning.objective
    before = search.before.objective if search.before is not None else math.nan
    words = f"{objective.words()}: {number(before, objective.unit)}"
    best = search.best
    if best is None:
        return words
    after = best.objective
    change = ""
    if math.isfinite(before) and before and math.isfinite(after):
        change = f" ({(after - before) / abs(before) * 100:+.3g} %)".replace("-", "−")
    return f"{words} → {number(after, objective.unit)}{change}"


def margin_rows(before: Sequence[Margin],
                after: Sequence[Margin] | None) -> list[tuple[str, str, str]]:
    """Every limit of *before* and *after* (by check, in the order met): its words, and its
    value against its limit with the margin, before and after."""
    rows: dict[str, list[Margin | None]] = {}
    for k, found in enumerate((before, after or ())):
        for m in found:
            rows.setdefault(f"{m.id}:{m.label}:{m.unit}", [None, None])[k] = m
    out = []
    for pair in rows.values():
        first = next(m for m in pair if m is not None)
        out.append((first.label, _margin_words(pair[0]), _margin_words(pair[1])))
    return out


def _margin_words(m: Margin | None) -> str:
    """``12.75 deg against 30 deg (inside by 17.25 deg)``."""
    if m is None:
        return "–"
    if m.value is None or m.limit is None or m.margin is None:
        return "holds" if m.ok else "broken"
    side = "inside by" if m.margin >= 0 else "OVER by"
    return (f"{number(m.value, m.unit)} against {number(m.limit, m.unit)} "
            f"({side} {number(abs(m.margin), m.unit)})")


def why_none(search: Search) -> str:
    """Why no candidate meets every limit: the closest's failed checks (or the design's)."""
    closest = search.closest or search.before
    if closest is None:
        return "no candidate was measured"
    failed = [m.label for m in closest.margins if not m.ok]
    if closest.out is not None:
        return f"the design: {closest.out}"
    what = ", ".join(dict.fromkeys(failed)) or closest.message
    whose = "the design" if closest is search.before else "the closest candidate"
    return f"{whose} breaks {what}"


def summary_lines(tuning: Plan, search: Search, stopped: bool, written: Sequence[Path],
                  standard: tuple[str, Trial] | None = None) -> list[str]:
    """The lines ``camfab tune`` prints (see the module); *standard*, the best standard law
    in the tuned segments' place (:meth:`~camfab.tune.trials.Evaluator.standard`), is
    compared with the tuned laws."""
    from camfab.tune.plan import changed

    name = tuning.options.design.stem
    best = search.best
    state = "OK" if best is not None else "FAIL"
    head = f"{name}: {state} — {objective_line(tuning, search)}"
    if stopped:
        head += " (stopped: the best found so far)"
    lines = [head]
    if best is None:
        lines.append(f"  no candidate meets every limit: {why_none(search)}")
    else:
        values = changed(tuning, best.written)
        lines += [f"  {path}: {shown(old)} → {shown(new)}" for path, old, new in values]
        if not values:
            lines.append("  the design's own laws are the best found: nothing changed")
        if search.global_optimum:
            lines.append(f"  the tuned laws are at their global optimum: {search.convex_note}")
        if standard is not None:
            lines.append(standard_line(tuning, best, *standard))
    for u in tuning.untuned:
        lines.append(f"  motion[{u.index}] not tuned: {u.why}")
    before = search.before.margins if search.before is not None else []
    rows = margin_rows(before, best.margins if best is not None else None)
    if rows:
        lines.append("  limits, before → after:")
        width = max(len(r[0]) for r in rows)
        lines += [f"    {label:<{width}}  {was} → {now}" for label, was, now in rows]
    ev = search.evaluator
    lines.append(f"  {ev.measured} candidates measured, {ev.analysed} analysed in full")
    lines += [f"  wrote {path}" for path in written]
    return lines


def standard_line(tuning: Plan, best: Trial, law: str, standard: Trial) -> str:
    """``the best standard law in their place, polynomial-56789: 0.15 mm, 1.08 times the
    tuned laws'``."""
    unit = tuning.objective.unit
    words = f"  the best standard law in their place, {law}: {number(standard.objective, unit)}"
    if best.objective > 0.0 and math.isfinite(standard.objective):
        words += f", {standard.objective / best.objective:.4g} times the tuned laws'"
    return words


def shown(value: object) -> str:
    """A value of the design as written: a whole number without its point, the default for
    none."""
    if value is None:
        return "(default)"
    if isinstance(value, float) and value.is_integer():
        return str(int(value))
    return str(value)


def trial_verdict(trial: Trial, best: Trial | None) -> str:
    """A candidate's verdict in words, for the report's table of the laws tried."""
    if trial.out is not None:
        return f"out: {trial.out}"
    if not trial.checked:
        return "not analysed: no better than the best found"
    if trial.feasible:
        return "the best" if trial is best else "meets every limit"
    failed = [m.label for m in trial.margins if not m.ok]
    return f"breaks {', '.join(dict.fromkeys(failed)) or trial.message}"
