"""Follower kinematics in SI at the design speed, per segment, and continuity findings.

Translating followers: v = ω·s′, a = ω²·s″, j = ω³·s‴ with s in mm, reported in m/s, m/s², m/s³.
Oscillating followers: ψ in rad, reported as angular velocity rad/s, rad/s², rad/s³ and lifts in
degrees.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from camfab.analysis.findings import Finding, Severity, listed
from camfab.angles import degrees
from camfab.motion.continuity import ORDER_NAMES, Step, joint_steps, unbounded_orders
from camfab.motion.program import MotionProgram


@dataclass(frozen=True)
class MotionUnits:
    """How a follower's motion is reported: names and scale factors per derivative order."""

    oscillating: bool

    @property
    def lift_key(self) -> str:
        return "lift_deg" if self.oscillating else "lift_mm"

    @property
    def displacement_column(self) -> str:
        return "displacement_deg" if self.oscillating else "displacement_mm"

    def lift_value(self, internal: float) -> float:
        """Lift in the report unit (deg or mm) from internal (rad or mm)."""
        return math.degrees(internal) if self.oscillating else internal

    def key(self, order: int) -> str:
        """Report key of the order-th time derivative (``velocity_m_s`` ...)."""
        if self.oscillating:
            return ("angular_velocity_rad_s", "angular_acceleration_rad_s2",
                    "angular_jerk_rad_s3")[order - 1]
        return ("velocity_m_s", "acceleration_m_s2", "jerk_m_s3")[order - 1]

    def unit(self, order: int, with_speed: bool) -> str:
        base = "rad" if self.oscillating else ("m" if with_speed else "mm")
        power = {1: "", 2: "²", 3: "³"}[order]
        return f"{base}/s{power}" if with_speed else f"{base}/rad{power}"

    def per_rad_key(self, order: int) -> str:
        base = "rad" if self.oscillating else "mm"
        suffix = "" if order == 1 else str(order)
        name = ("velocity", "acceleration", "jerk")[order - 1]
        return f"max_{name}_{base}_per_rad{suffix}"

    def to_si(self, order: int, per_rad: float, omega: float) -> float:
        """A derivative per radianⁿ of cam angle at speed *omega* (rad/s) in report units."""
        value = per_rad * omega**order
        return value if self.oscillating else value / 1000.0


@dataclass(frozen=True)
class SegmentStats:
    """A segment's place, law and peak kinematics (None where unbounded)."""

    index: int
    kind: str
    law: str
    start_deg: float
    end_deg: float
    lift: float  # report unit: mm or deg
    coefficients: tuple[float, float, float]
    max_per_rad: tuple[float | None, float | None, float | None]
    max_si: tuple[float | None, float | None, float | None] | None


def segment_stats(program: MotionProgram, steps: list[Step], units: MotionUnits,
                  omega: float | None) -> list[SegmentStats]:
    """Per-segment peaks of s′, s″, s‴ and, with a speed, of v, a, j."""
    unbounded = unbounded_orders(program, steps)
    out = []
    for seg, bad in zip(program.segments, unbounded, strict=True):
        per_rad = tuple(None if (o in bad or not math.isfinite(seg.peak(o))) else seg.peak(o)
                        for o in (1, 2, 3))
        si = None
        if omega is not None:
            si = tuple(None if v is None else units.to_si(o, v, omega)
                       for o, v in zip((1, 2, 3), per_rad, strict=True))
        out.append(SegmentStats(
            index=seg.index, kind=seg.kind, law=seg.law_name,
            start_deg=degrees(seg.start), end_deg=degrees(seg.end),
            lift=units.lift_value(abs(seg.delta)),
            coefficients=seg.law.coefficients if seg.delta else (0.0, 0.0, 0.0),
            max_per_rad=per_rad,  # type: ignore[arg-type]
            max_si=si,  # type: ignore[arg-type]
        ))
    return out


_CONSEQUENCE = {
    1: "infinite acceleration: the follower is struck at every turn",
    2: "infinite jerk: vibration and noise at speed",
    3: ("finite, as the fundamental law of cam design asks (the velocity and the acceleration "
        "continuous); at speed a jerk step sets an elastic follower ringing"),
}

#: How much a jerk step sets the follower ringing, where camfab says it: the elastic follower
#: train, which needs a stiffness (and, to be computed, the forces: a mass, a speed and what
#: holds the follower on the cam).
RIGID_RINGING = "give follower.stiffness to see how much"
ELASTIC_RINGING = "the elastic follower train's residual vibration in the dwells says how much"


def ringing_words(stiffness: bool, missing: str | None) -> str:
    """Where to see how much a jerk step sets the follower ringing: a rigid train (no
    *stiffness*) needs one; an elastic one's vibration is computed, or (*missing*: why the
    forces are not) says what it needs."""
    if not stiffness:
        return RIGID_RINGING
    if missing is not None:
        return f"the elastic follower train's vibration would say how much, but {missing}"
    return ELASTIC_RINGING

_SEVERITY: dict[int, Severity] = {1: "error", 2: "warning", 3: "warning"}
#: The orders whose steps fail their check: a step of the velocity strikes the follower, one of
#: the acceleration means infinite jerk; a step of the jerk (cycloidal, 3-4-5 and most laws next
#: to a dwell) breaks nothing, and a warning every cam gives teaches its reader to skip warnings.
_FAILS = (1, 2)


def continuity_findings(program: MotionProgram, units: MotionUnits, omega: float | None,
                        ringing: str = RIGID_RINGING) -> tuple[list[Finding], list[Step]]:
    """One ``continuity`` finding per derivative order, and the steps found; a jerk step's
    says where to see the ringing it sets off (*ringing*: :func:`ringing_words`)."""
    steps = joint_steps(program)
    findings = []
    for order in (1, 2, 3):
        name = ORDER_NAMES[order]
        mine = [s for s in steps if s.order == order]
        unit = units.unit(order, omega is not None)
        # a step of the velocity or the acceleration must be none (0); a jerk step has no limit
        limit = 0.0 if order in _FAILS else None
        if not mine:
            lower = [s for s in steps if s.order < order]
            message = (f"{name} is continuous at every joint" if not lower else
                       f"{name} has no steps besides the joints where "
                       f"{ORDER_NAMES[min(s.order for s in lower)]} steps")
            findings.append(Finding("continuity", True, _SEVERITY[order], message, 0.0, limit,
                                    unit, quantity=name))
            continue

        def scaled(value: float, order: int = order) -> float:
            return units.to_si(order, value, omega) if omega is not None else value

        worst = max(mine, key=lambda s: s.size)
        angles = listed([f"{degrees(s.angle):.6g}°" for s in mine])
        message = (f"{name} steps at {angles} (largest {scaled(worst.size):.4g} {unit} at "
                   f"{degrees(worst.angle):.6g}°): {_CONSEQUENCE[order]}"
                   f"{': ' + ringing if order == 3 else ''}")
        findings.append(Finding(
            "continuity", order not in _FAILS, _SEVERITY[order], message,
            value=scaled(worst.size), limit=limit, unit=unit,
            ranges_deg=tuple((degrees(s.angle), degrees(s.angle)) for s in mine),
            quantity=name,
        ))
    return findings, steps
