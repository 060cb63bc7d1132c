"""``camfab size``'s answer on the terminal, lengths in the design's units."""

from __future__ import annotations

from typing import TYPE_CHECKING

from camfab.analysis.sizing_words import length, limit_words, step

if TYPE_CHECKING:
    from camfab.analysis.sizing import Sizing
    from camfab.design import Design

def sizing_lines(design: Design, sizing: Sizing) -> list[str]:
    """``camfab size``'s answer: the least size, what governs it and where, the offset or pivot
    distance chosen, every limit at that size; or why no size meets the limits."""
    from camfab.analysis.sizing import SIZE_NAMES, unmet_words

    name = SIZE_NAMES[sizing.key]
    found = sizing.found
    if found.size is None:
        return [f"{design.name}: {unmet_words(sizing, name)}"]
    lines = [f"{design.name}: least {name} {length(design, found.size)}"]
    if sizing.rounded_to:
        lines[0] += f" (rounded up to a multiple of {step(design, sizing.rounded_to)})"
    if sizing.offset is not None:
        how = ("centres the face on the contact (the base radius does not depend on it)"
               if design.follower.type == "flat" else "lets the base radius be least")
        lines.append(f"  with the offset {length(design, sizing.offset)}, which {how}")
    if sizing.pivot_distance is not None:
        lines.append(f"  with the pivot distance {length(design, sizing.pivot_distance)} (arm "
                     f"{length(design, design.follower.arm_length)}), which lets the base "
                     "radius be least")
    governing = found.governing
    if governing is not None:
        lines.append(f"  governed by {limit_words(design, governing)}")
        if governing.unit == "mm" and governing.limit == 0.0 and governing.at_deg is not None:
            lines.append("  the profile comes to a point there: give "
                         "limits.min_radius_of_curvature for a rounded one")
    lines.append("  at that size:")
    lines += [f"    {'✔' if limit.ok else '✖'} {limit.id}: {limit_words(design, limit)}"
              for limit in found.limits]
    return lines
