"""Every limit's margin, read from a candidate's checks: each ``error`` check with a measured
value and a limit (the pressure angle against its limit, the least radius of curvature against
the roller's or the limit's, the contact stress, the jump speeds against the design speed, the
roller's life, ...) gives how far the value stays inside its limit — positive while it holds,
negative by how much it is broken — in the check's unit and as a share of the limit.

Whether a limit is an upper or a lower bound is read from the check's own verdict: a check
that holds with its value below its limit is an upper bound. The sum of the broken limits'
shares is a candidate's violation, which the search's penalty grows with.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from camfab.analysis.findings import Finding

#: Words for the checks' ids (the others are named by their id).
LABELS = {
    "pressure_angle": "pressure angle",
    "undercut": "radius of curvature (undercut)",
    "curvature": "radius of curvature",
    "contact_stress": "contact stress",
    "jump": "jump speed (rigid follower)",
    "dynamic_jump": "jump speed (elastic train)",
    "train_vibration": "train vibration",
    "roller_life": "roller life",
    "face_width": "face width",
}


@dataclass(frozen=True)
class Margin:
    """One limit: the check's *id*, its words, whether it holds, the value, the limit and the
    unit, and the margin (in the unit; positive inside the limit; None without both
    numbers)."""

    id: str
    label: str
    ok: bool
    value: float | None
    limit: float | None
    unit: str
    margin: float | None

    @property
    def share(self) -> float | None:
        """The margin as a share of the limit."""
        if self.margin is None or not self.limit:
            return None
        return self.margin / abs(self.limit)


def margins(findings: Sequence[Finding]) -> list[Margin]:
    """The margin of every applicable ``error`` check of *findings* that measures a value
    against a limit, or that fails (the continuity checks, which have none to spend, aside
    while they hold)."""
    out = []
    for f in findings:
        if f.severity != "error" or not f.applicable:
            continue
        if f.id == "continuity" and f.ok:
            continue
        value, limit = f.value, f.limit
        margin = None
        if value is not None and limit is not None:
            upper = (value <= limit) == f.ok
            margin = (limit - value) if upper else (value - limit)
            margin = abs(margin) if f.ok else -abs(margin)
        out.append(Margin(f.id, LABELS.get(f.id, f.id.replace("_", " ")), f.ok, value, limit,
                          f.unit or "", margin))
    return out


def violation(found: Sequence[Margin]) -> float:
    """How much *found* break their limits: each broken limit 1, plus its excess as a share
    of the limit (capped at 10)."""
    total = 0.0
    for m in found:
        if m.ok:
            continue
        share = m.share
        total += 1.0 + (min(abs(share), 10.0) if share is not None else 0.0)
    return total
