"""A sizing in words, lengths in the design's units: what a build chose where the design said
``auto`` (the report's page and the terminal), and one limit at a size (``camfab size``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from camfab.analysis.sizing import LimitValue
    from camfab.design import Design


def length(design: Design, mm: float | None) -> str:
    """A length (mm) in the design's units, to 1e-4 mm."""
    if mm is None:
        return "–"
    if design.units == "in":
        return f"{mm / design.mm_per_unit:.6f} in ({mm:.4f} mm)"
    return f"{mm:.4f} mm"


def step(design: Design, mm: float) -> str:
    """A stock step (mm) in the design's units, as short as it is."""
    return f"{mm / design.mm_per_unit:g} {design.units}"


def _value(design: Design, value: float | None, unit: str) -> str:
    """A limit's value: an angle (deg), a length (mm, shown in the design's units) or another
    quantity in its *unit* (a stress in MPa)."""
    if value is None:
        return "–"
    if unit == "deg":
        return f"{value:.4g}°"
    return length(design, value) if unit == "mm" else f"{value:.4g} {unit}"


def limit_words(design: Design, limit: LimitValue) -> str:
    """One limit at a size: what, its value (and where), its limit; a limit on the size itself
    (a wall round the bore), the least size it allows."""
    bound = "at most" if limit.sense == "max" else "at least"
    where = f" at {limit.at_deg:.4g}°" if limit.at_deg is not None else ""
    against = ("" if limit.limit is None else
               f" ({bound} {_value(design, limit.limit, limit.unit)})")
    if limit.value is None and limit.limit is None:
        return limit.what
    if limit.of_size and limit.limit is not None:
        more = "more than" if limit.id == "tolerance" else "at least"
        return f"{limit.what}: a size of {more} {_value(design, limit.limit, limit.unit)}"
    return f"{limit.what}: {_value(design, limit.value, limit.unit)}{where}{against}"


def sized_words(design: Design) -> str | None:
    """What a build chose where the design said ``auto``, or None."""
    sized = design.sized
    if sized is None:
        return None
    chosen = [f"{name} {length(design, value)}" for name, value in
              (("base radius", sized.base_radius), ("drum radius", sized.radius),
               ("offset", sized.offset)) if value is not None]
    where = f" at {sized.at_deg:.4g}°" if sized.at_deg is not None else ""
    rounded = (f", rounded up to a multiple of {step(design, sized.rounded_to)}"
               if sized.rounded_to else "")
    return (f"sized (auto): {', '.join(chosen)}{rounded}; governed by {sized.what}: "
            f"{_value(design, sized.value, sized.unit)}{where} (limit "
            f"{_value(design, sized.limit, sized.unit)})")
