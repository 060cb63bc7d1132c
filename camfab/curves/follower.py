"""The follower as geometry: its contact shape and how its trace point moves (SPEC §2).

A translating follower moves along +Y on the line ``x = offset``; an oscillating one turns about
the pivot ``(pivot_sign·pivot_distance, 0)`` with its trace point at ``arm_length`` from it, above
the X axis, at the arm angle Ψ measured at the pivot from the line pivot → cam centre. Knife,
roller and mushroom followers touch the cam with a circle of ``radius`` (0 for a knife) about the
trace point; a flat face touches it with a line: perpendicular to the motion for a translating
follower, at ``face_offset`` from the pivot (toward the cam) for an oscillating one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal, Protocol

Contact = Literal["knife", "roller", "flat", "mushroom"]


class FollowerSpec(Protocol):
    """What the design file says of a follower (``camfab.design``'s follower model, mm)."""

    type: Contact
    oscillating: bool
    trace_radius: float
    offset: float
    pivot_distance: float | None
    arm_length: float | None
    pivot_side: str
    face_offset: float


class HasFollower(Protocol):
    """A design: anything with a :class:`FollowerSpec` as its ``follower``."""

    @property
    def follower(self) -> FollowerSpec: ...


@dataclass(frozen=True)
class FollowerGeometry:
    """A follower's shape and mounting (lengths in mm).

    Attributes
    ----------
    contact
        ``knife``, ``roller``, ``mushroom`` (a circle of ``radius`` about the trace point) or
        ``flat``.
    oscillating
        True for a follower on an arm turning about the pivot.
    radius
        Roller or mushroom face radius; 0 for knife and flat followers.
    offset
        Translating: the signed x of the line of motion.
    pivot_distance, arm_length, pivot_sign
        Oscillating: the pivot is at ``(pivot_sign·pivot_distance, 0)``, the trace point
        ``arm_length`` from it.
    face_offset
        Oscillating flat face: the face line's distance from the pivot, toward the cam.
    """

    contact: Contact
    oscillating: bool = False
    radius: float = 0.0
    offset: float = 0.0
    pivot_distance: float = 0.0
    arm_length: float = 0.0
    pivot_sign: int = 1
    face_offset: float = 0.0

    @property
    def flat(self) -> bool:
        return self.contact == "flat"

    @classmethod
    def from_design(cls, design: HasFollower) -> FollowerGeometry:
        """The follower of *design* (a :class:`camfab.design.Design`)."""
        fol = design.follower
        return cls(
            contact=fol.type,
            oscillating=fol.oscillating,
            radius=fol.trace_radius,
            offset=fol.offset,
            pivot_distance=fol.pivot_distance or 0.0,
            arm_length=fol.arm_length or 0.0,
            pivot_sign=1 if fol.pivot_side == "right" else -1,
            face_offset=fol.face_offset,
        )

    def rest_position(self, base_radius: float) -> float:
        """Where the follower is at zero lift on a cam of *base_radius* (mm).

        The trace point's height (mm) for a translating follower, or its arm angle Ψ₀ (rad) for
        an oscillating one: ``cos Ψ₀ = (a² + L² − Rp²)/(2aL)``, or ``sin Ψ₀ = (Rb + f)/a`` for a
        flat face (THEORY §B).
        """
        prime = base_radius + self.radius
        if not self.oscillating:
            if self.flat:
                return base_radius
            return math.sqrt(prime**2 - self.offset**2)
        a, arm = self.pivot_distance, self.arm_length
        if self.flat:
            return math.asin((base_radius + self.face_offset) / a)
        return math.acos((a * a + arm * arm - prime * prime) / (2.0 * a * arm))
