"""Findings: the result of one check of a buildable design, as data.

A design that builds but is bad (a velocity step, an undercut, a pressure angle over the limit) is
not an exception: each check yields a :class:`Finding` with an id, whether it passed, its severity,
the measured value against the limit, and where (angle ranges in degrees). The command line turns
failed ``error`` findings into exit status 1.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

Severity = Literal["error", "warning"]

#: A finding's message names at most this many places; its ``ranges_deg`` holds them all.
MOST_PLACES = 8


def listed(places: Sequence[str], most: int = MOST_PLACES) -> str:
    """*places* joined for a message, the list cut after *most* (a program of a thousand
    segments has a thousand joints, which no one reads in a sentence)."""
    if len(places) <= most:
        return ", ".join(places)
    return ", ".join(places[:most]) + f" and {len(places) - most} more (all in the report)"


@dataclass(frozen=True)
class Finding:
    """One check's outcome. *value* and *limit* are in *unit*; ranges are cam angles (deg)."""

    id: str
    ok: bool
    severity: Severity
    message: str
    value: float | None = None
    limit: float | None = None
    unit: str | None = None
    ranges_deg: tuple[tuple[float, float], ...] = field(default_factory=tuple)
    quantity: str | None = None
    #: False when the check does not apply to this design (the message says why): neither
    #: passed nor failed, shown as "–" and written with ``ok`` null.
    applicable: bool = True
    #: The cam angle (deg) where *value* is measured, where it is one place (the largest
    #: pressure angle, the smallest radius of curvature): a passing check's "where".
    at_deg: float | None = None

    @property
    def failed_error(self) -> bool:
        """True when this finding makes the build fail (exit status 1)."""
        return not self.ok and self.severity == "error"

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "id": self.id,
            "ok": self.ok if self.applicable else None,
            "severity": self.severity,
            "message": self.message,
            "value": self.value,
            "limit": self.limit,
            "unit": self.unit,
            "ranges_deg": [list(r) for r in self.ranges_deg],
        }
        if self.quantity is not None:
            out["quantity"] = self.quantity
        if self.at_deg is not None:
            out["value_at_deg"] = self.at_deg
        if not self.applicable:
            out["applicable"] = False
        return out

    @property
    def mark(self) -> str:
        """✔ passed, ✖ a failed error, ! a failed warning, – not applicable."""
        if not self.applicable:
            return "–"
        if self.ok:
            return "✔"
        return "✖" if self.severity == "error" else "!"


def exit_status(findings: Iterable[Finding]) -> int:
    """0 when every error-severity check passed, else 1."""
    return 1 if any(f.failed_error for f in findings) else 0


def count(findings: Sequence[Finding], severity: Severity) -> int:
    """How many checks of *severity* failed."""
    return sum(1 for f in findings if not f.ok and f.severity == severity)
