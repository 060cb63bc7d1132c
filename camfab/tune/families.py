"""What a segment's motion law leaves free for tuning, family by family.

A family is a small class: :meth:`Family.of` reads its parameters from one rise or return (the
entry of the design's data and the segment as the program built it) or finds none, and
:meth:`~Family.written` gives the values to write back, each with its key path in the design's
data (``("motion", 0, "rise", "law")``), which is also the path the design file's editor takes
(``motion[0].rise.law``). A new law with free values is one more class in :data:`FAMILIES`.

- :class:`LawChoice` — a segment that follows one of the standard laws may follow another: a
  discrete choice among those that need no data of their own (the search keeps only those
  whose joints with the neighbours are as continuous as the design's were). A segment that
  follows ``modified-uniform-velocity`` has its blend tuned instead.
- :class:`PolynomialPoints` — a ``polynomial`` law's ``points``: each point's angle stays, its
  lift is free between the segment's start and end lifts (its share of the segment's lift in
  [0, 1]). The end conditions (``start``, ``end``) stay: they are the joints' continuity.
  A polynomial without points has nothing free (add points to free some).
- :class:`Blend` — the ``blend`` of ``modified-uniform-velocity``, in
  [:data:`LEAST_BLEND`, 0.5]. The SCCA laws' shape fractions are no design keys (the
  modified-sine and modified-trapezoid are fixed members of the family): they stay.
- :class:`SplineControls` — a ``spline`` law's free control values, given as a list
  (``controls: [0.1, 0.4, 0.6, 0.9]``), each in [0, 1] (normalised lift, as the law takes
  them); its order and end conditions stay. A count (``controls: 4``, the smooth rise's
  values) is not rewritten as a list: the message says what to write to free them.

A continuous family's parameters are given to the search normalised to [0, 1] each; the values
written are rounded (:data:`LIFT_DIGITS`, :data:`BLEND_DIGITS` significant digits), and the
search evaluates the rounded values, so what is written is what was measured.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from camfab.arrays import Array
from camfab.design import Design
from camfab.motion.program import ProgramSegment

#: A key path into the design's data: names and list indices.
Keys = tuple[str | int, ...]
#: A value written into the design: its key path and the value.
Written = tuple[Keys, Any]

#: Significant digits of a point's lift as written (in the file's units): far below any
#: tolerance of a made cam, and enough that the least peak acceleration found by the linear
#: programme survives its rounding to 1e-9.
LIFT_DIGITS = 10
#: Significant digits of a blend as written.
BLEND_DIGITS = 6
#: Significant digits of a spline's control value as written (normalised lift).
CONTROL_DIGITS = 10
#: The least blend the search tries (a share of the segment at each end): the acceleration
#: grows as 1/blend, and below a few hundredths the blend is all but a velocity step.
LEAST_BLEND = 0.02


def rounded(value: float, digits: int) -> float:
    """*value* to *digits* significant digits."""
    return float(f"{value:.{digits}g}")


class Family(ABC):
    """The free parameters of segment *index* (a rise or a return: *kind*)."""

    #: What it tunes, in words for the report.
    label: ClassVar[str] = ""
    #: True for a choice among options, False for numbers in [0, 1].
    discrete: ClassVar[bool] = False

    def __init__(self, index: int, kind: str) -> None:
        self.index = index
        self.kind = kind

    def keys(self, *rest: str | int) -> Keys:
        """The key path of *rest* inside this segment."""
        return ("motion", self.index, self.kind, *rest)

    @property
    def where(self) -> str:
        return f"motion[{self.index}] ({self.kind})"

    @classmethod
    @abstractmethod
    def of(cls, index: int, kind: str, entry: dict[str, Any], segment: ProgramSegment,
           design: Design) -> Family | None:
        """This family's parameters of the segment *entry* (its keys as the file gives them)
        placed as *segment* in *design*, or None when the family does not apply."""


class ChoiceFamily(Family):
    """A discrete choice: :attr:`options` (the current one among them)."""

    discrete = True

    def __init__(self, index: int, kind: str, options: Sequence[str], current: str) -> None:
        super().__init__(index, kind)
        self.options = tuple(options)
        self.current = current

    @abstractmethod
    def written(self, option: str) -> list[Written]:
        """The values that choose *option*."""

    @abstractmethod
    def updates(self, option: str) -> dict[str, Any]:
        """The segment's fields (the design model's, internal units) that choose *option*."""


class ContinuousFamily(Family):
    """:attr:`size` numbers, each searched in [0, 1]."""

    size: int = 0

    @abstractmethod
    def start(self) -> Array:
        """The design's own values, normalised."""

    @abstractmethod
    def written(self, x: Array) -> list[Written]:
        """The values (rounded, in the file's units) of the normalised parameters *x*."""

    @abstractmethod
    def updates(self, x: Array) -> dict[str, Any]:
        """The segment's fields (the design model's, internal units) of the values
        :meth:`written` writes for *x*."""

    @abstractmethod
    def names(self) -> list[str]:
        """A name for each parameter, for the report."""


class LawChoice(ChoiceFamily):
    """The segment's standard law, among those that need no data of their own."""

    label = "the law"

    @classmethod
    def of(cls, index: int, kind: str, entry: dict[str, Any], segment: ProgramSegment,
           design: Design) -> LawChoice | None:
        options = standard_laws()
        if segment.law_name not in options or segment.law_name == "modified-uniform-velocity":
            return None  # (a blend's segment is tuned by its blend)
        return cls(index, kind, options, segment.law_name)

    def written(self, option: str) -> list[Written]:
        return [(self.keys("law"), option)]

    def updates(self, option: str) -> dict[str, Any]:
        return {"law": option}


def standard_laws() -> tuple[str, ...]:
    """The laws a design may name that need nothing but their name (a blend has a default)."""
    from camfab.motion.laws import LAWS

    return tuple(info.name for info in LAWS
                 if not info.params or info.name == "modified-uniform-velocity")


class Blend(ContinuousFamily):
    """The blend of ``modified-uniform-velocity``: the share of the segment over which each
    parabolic blend runs, from :data:`LEAST_BLEND` (or the design's own, if less) to 0.5."""

    label = "the blend"
    size = 1

    def __init__(self, index: int, kind: str, blend: float) -> None:
        super().__init__(index, kind)
        self.blend = blend
        self.low = min(LEAST_BLEND, blend)

    @classmethod
    def of(cls, index: int, kind: str, entry: dict[str, Any], segment: ProgramSegment,
           design: Design) -> Blend | None:
        from camfab.motion.laws import ModifiedUniformVelocity

        if segment.law_name != "modified-uniform-velocity":
            return None
        law = segment.law
        assert isinstance(law, ModifiedUniformVelocity)
        return cls(index, kind, law.blend)

    def value(self, x: Array) -> float:
        return rounded(self.low + float(x[0]) * (0.5 - self.low), BLEND_DIGITS)

    def start(self) -> Array:
        return np.array([(self.blend - self.low) / (0.5 - self.low)])

    def written(self, x: Array) -> list[Written]:
        return [(self.keys("blend"), self.value(x))]

    def updates(self, x: Array) -> dict[str, Any]:
        return {"blend": self.value(x)}

    def names(self) -> list[str]:
        return [f"motion[{self.index}].{self.kind}.blend"]


class PolynomialPoints(ContinuousFamily):
    """The lifts of a ``polynomial`` law's points, each its share of the segment's lift in
    [0, 1] (from the segment's start lift to its end lift), written in the file's units."""

    label = "the points' lifts"

    def __init__(self, index: int, kind: str, angles: Array, shares: Array, s0: float,
                 delta: float, per_unit: float) -> None:
        super().__init__(index, kind)
        self.angles = angles  # rad, as the design model holds them
        self.shares = shares
        self.size = shares.size
        self.s0, self.delta = s0, delta
        self.per_unit = per_unit  # the program's units (mm or rad) per unit of the file's

    @classmethod
    def of(cls, index: int, kind: str, entry: dict[str, Any], segment: ProgramSegment,
           design: Design) -> PolynomialPoints | None:
        points = design.motion[index].points
        if segment.law_name != "polynomial" or not points or segment.delta == 0.0:
            return None
        from camfab.design import units as U

        angles = np.array([p[0] for p in points])
        lift = np.array([p[1] for p in points])
        shares = np.clip((lift - segment.s0) / segment.delta, 0.0, 1.0)
        kind_of_lift = U.ANGLE if design.follower.oscillating else U.LENGTH
        per_unit = U.convert(1.0, kind_of_lift, design.units)
        return cls(index, kind, angles, shares, segment.s0, segment.delta, per_unit)

    def lifts(self, x: Array) -> list[float]:
        """The points' lifts (the file's units, rounded) of the shares *x*."""
        return [rounded((self.s0 + float(f) * self.delta) / self.per_unit, LIFT_DIGITS) + 0.0
                for f in x]

    def start(self) -> Array:
        return self.shares.copy()

    def written(self, x: Array) -> list[Written]:
        return [(self.keys("points", k, 1), lift) for k, lift in enumerate(self.lifts(x))]

    def updates(self, x: Array) -> dict[str, Any]:
        return {"points": tuple((float(angle), lift * self.per_unit)
                                for angle, lift in zip(self.angles, self.lifts(x),
                                                       strict=True))}

    def names(self) -> list[str]:
        return [f"motion[{self.index}].{self.kind}.points[{k}][1]" for k in range(self.size)]


class SplineControls(ContinuousFamily):
    """The free control values of a ``spline`` law given as a list, each in [0, 1]."""

    label = "the spline's control values"

    def __init__(self, index: int, kind: str, values: Array) -> None:
        super().__init__(index, kind)
        self.values = values
        self.size = values.size

    @classmethod
    def of(cls, index: int, kind: str, entry: dict[str, Any], segment: ProgramSegment,
           design: Design) -> SplineControls | None:
        controls = design.motion[index].controls
        if segment.law_name != "spline" or not isinstance(controls, tuple) or not controls:
            return None
        return cls(index, kind, np.clip(np.array(controls, dtype=np.float64), 0.0, 1.0))

    def controls(self, x: Array) -> list[float]:
        return [rounded(float(v), CONTROL_DIGITS) + 0.0 for v in x]

    def start(self) -> Array:
        return self.values.copy()

    def written(self, x: Array) -> list[Written]:
        return [(self.keys("controls", k), v) for k, v in enumerate(self.controls(x))]

    def updates(self, x: Array) -> dict[str, Any]:
        return {"controls": tuple(self.controls(x))}

    def names(self) -> list[str]:
        return [f"motion[{self.index}].{self.kind}.controls[{k}]" for k in range(self.size)]


#: Every family, tried in order on each segment tuned: the first that applies is its.
FAMILIES: tuple[type[Family], ...] = (Blend, PolynomialPoints, SplineControls, LawChoice)
#: The families whose every derivative of the motion is affine in their parameters (the peak
#: acceleration or jerk over them is convex: :mod:`camfab.tune.convex`).
AFFINE: tuple[type[Family], ...] = (PolynomialPoints, SplineControls)


@dataclass(frozen=True)
class Untuned:
    """A segment asked for that has nothing free, and why."""

    index: int
    why: str


def families_of(data: dict[str, Any], design: Design,
                indices: Sequence[int]) -> tuple[list[Family], list[Untuned]]:
    """The family of each segment of *indices* (rises and returns) of *design*, whose data is
    *data*, and the segments that have none."""
    found: list[Family] = []
    none: list[Untuned] = []
    motion = data["motion"]
    for index in indices:
        segment = design.program.segments[index]
        kind = segment.kind
        entry = motion[index].get(kind) if isinstance(motion[index], dict) else None
        entry = entry if isinstance(entry, dict) else {}
        family = next((f for f in (cls.of(index, kind, entry, segment, design)
                                   for cls in FAMILIES) if f is not None), None)
        if family is None:
            none.append(Untuned(index, _why_not(segment, design)))
        else:
            found.append(family)
    return found, none


def _why_not(segment: ProgramSegment, design: Design) -> str:
    if segment.law_name == "polynomial":
        return ("a polynomial without points has nothing free: add points: [[ANGLE, LIFT], ...] "
                "inside the segment to free their lifts")
    if segment.law_name == "table":
        return "a table's points are data, not free parameters"
    if segment.law_name == "spline":
        free = getattr(segment.law, "free", ())
        values = ", ".join(f"{v:.4g}" for v in free)
        return (f"a spline's controls given as a count are the smooth rise's values: write "
                f"them as a list to free them (controls: [{values}])" if free else
                "a spline without free control values has nothing free (give controls: [...])")
    return f"the {segment.law_name} law has no free parameters camfab tunes"
