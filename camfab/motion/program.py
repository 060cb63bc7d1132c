"""Motion programs: a cycle of rise, dwell and return segments as s(θ) and its derivatives.

θ is the cam angle in radians from the start of the program (0 ≤ θ < 2π, wrapped), and the
derivatives are per radian of cam angle. s is in millimetres for translating followers and
radians of swing for oscillating ones. Where a derivative steps at a segment boundary, evaluation
returns the value just after it (the limit from increasing θ).
"""

from __future__ import annotations

import functools
import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
from numpy.typing import ArrayLike

from camfab.arrays import Index, spaced
from camfab.motion.law import Array, Law
from camfab.motion.laws import DWELL, standard_law
from camfab.motion.polynomial import Condition, SingularConditionsError, solve_polynomial

TWO_PI = 2.0 * math.pi

#: The laws built from a segment's own data (its conditions, points or controls), by name.
DATA_LAWS = ("polynomial", "table", "spline")
#: The boundary conditions' keys by derivative order (the design file's ``start`` and ``end``).
CONDITION_KEYS = {1: "velocity", 2: "acceleration", 3: "jerk", 4: "snap"}

#: Table points must start and end on the segment's boundaries; this slack (in radians of cam
#: angle and in mm or rad of lift) absorbs the rounding of values typed with a few decimals.
POINT_SLACK = 1e-6


def cycle_angles(step: float) -> Array:
    """Cam angles (rad) from 0 to one turn less one step, the turn split into equal steps as near
    to *step* as divides it."""
    count = round(TWO_PI / step)
    return (TWO_PI / count) * np.arange(count, dtype=np.float64)


class ProgramError(ValueError):
    """A motion program that cannot be built: *index* is the segment, *field* its key."""

    def __init__(self, index: int | None, field: str, problem: str) -> None:
        self.index = index
        self.field = field
        self.problem = problem
        where = "motion" if index is None else f"motion[{index}]"
        super().__init__(f"{where}{'.' + field if field else ''}: {problem}")


class SegmentSpec(Protocol):
    """What the program needs of a design segment (see :class:`camfab.design.model.Segment`)."""

    @property
    def kind(self) -> str: ...
    @property
    def angle(self) -> float: ...
    @property
    def lift(self) -> float | None: ...
    @property
    def law(self) -> str | None: ...
    @property
    def blend(self) -> float | None: ...
    @property
    def start(self) -> Any: ...
    @property
    def end(self) -> Any: ...
    @property
    def points(self) -> Sequence[tuple[float, float]] | None: ...
    @property
    def order(self) -> int | None: ...
    @property
    def controls(self) -> int | Sequence[float] | None: ...


@dataclass(frozen=True)
class ProgramSegment:
    """One segment placed in the cycle: θ from *start* over *span* (rad), s from *s0* by *delta*."""

    index: int
    kind: str
    law_name: str
    law: Law
    start: float
    span: float
    s0: float
    delta: float

    @property
    def end(self) -> float:
        return self.start + self.span

    @property
    def s1(self) -> float:
        return self.s0 + self.delta

    def evaluate_local(self, t: ArrayLike) -> Array:
        """s, s′, s″, s‴ at *t* radians into the segment (0 ≤ t ≤ span)."""
        u = np.asarray(t, dtype=np.float64) / self.span
        f = self.law.evaluate(u)
        scale = self.delta / self.span ** np.arange(4)
        out = f * scale[:, None]
        out[0] += self.s0
        return out

    def end_values(self, order: int = 3) -> Array:
        """(2, order + 1): s and its derivatives up to *order* (at most the law's
        :attr:`~camfab.motion.law.Law.top_order`) at the start (right limit) and the end (left
        limit)."""
        f = self.law.derivatives(np.array([0.0, 1.0]), order)
        out = f * (self.delta / self.span ** np.arange(order + 1))[:, None]
        out[0] += self.s0
        return out.T

    def peak(self, order: int) -> float:
        """max |s⁽ᵒʳᵈᵉʳ⁾| inside the segment per radianᵒʳᵈᵉʳ (inf: unbounded inside)."""
        if self.delta == 0.0:
            return 0.0
        return abs(self.delta) * self.law.peak(order) / self.span**order


@dataclass(frozen=True)
class Joint:
    """Where segment *after* starts: derivatives just before (*left*) and after (*right*)."""

    angle: float
    before: int
    after: int
    left: Array
    right: Array


@dataclass(frozen=True)
class SegmentTable:
    """The segments of a program as arrays, for evaluating many segments at once: start angle
    and span (rad), start lift s₀ (mm or rad), the scale Δ/βⁿ of each derivative n = 0…3 of
    the law (per radianⁿ), and which of the distinct *laws* each segment follows."""

    start: Array
    span: Array
    s0: Array
    scale: Array
    law: Index
    laws: tuple[Law, ...]

    @classmethod
    def of(cls, segments: Sequence[ProgramSegment]) -> SegmentTable:
        laws: dict[int, int] = {}
        for seg in segments:
            laws.setdefault(id(seg.law), len(laws))
        distinct = {id(seg.law): seg.law for seg in segments}
        # the scale as ProgramSegment.evaluate_local computes it, so the values are the same
        scale = [seg.delta / seg.span ** np.arange(4) for seg in segments]
        return cls(np.array([seg.start for seg in segments]),
                   np.array([seg.span for seg in segments]),
                   np.array([seg.s0 for seg in segments]),
                   np.array(scale).reshape(len(segments), 4),
                   np.array([laws[id(seg.law)] for seg in segments], dtype=np.intp),
                   tuple(distinct[key] for key in laws))


class MotionProgram:
    """A periodic follower motion over one turn of the cam."""

    def __init__(self, segments: Sequence[ProgramSegment]) -> None:
        self.segments = tuple(segments)
        self._starts = np.array([seg.start for seg in self.segments])

    @functools.cached_property
    def table(self) -> SegmentTable:
        """The segments as arrays (built on first use)."""
        return SegmentTable.of(self.segments)

    def evaluate_local(self, index: Index, t: ArrayLike) -> Array:
        """s, s′, s″, s‴ at *t* radians into segments *index* (both (N,), 0 ≤ t ≤ span),
        as (4, N): the values :meth:`ProgramSegment.evaluate_local` gives, computed with one
        call of each law the segments follow (a law's values at u depend on u alone)."""
        table = self.table
        index = np.asarray(index, dtype=np.intp)
        u = np.asarray(t, dtype=np.float64) / table.span[index]
        law = table.law[index]
        order = np.argsort(law, kind="stable")
        bounds = np.searchsorted(law[order], np.arange(len(table.laws) + 1))
        f = np.empty((4, u.size))
        for k, rule in enumerate(table.laws):
            picked = order[bounds[k] : bounds[k + 1]]
            if picked.size:
                f[:, picked] = rule.evaluate(u[picked])
        out = f * table.scale[index].T
        out[0] += table.s0[index]
        return out

    def segment_grid(self, step: float) -> tuple[Index, Array, Array]:
        """Cam angles at most *step* (rad) apart, segment by segment with both ends of each
        (so a joint appears twice, with each segment's one-sided values): the segment index
        and angle (N,) and s, s′, s″, s‴ there (4, N)."""
        span = self.table.span
        count = np.maximum(3, np.ceil(span / step).astype(np.intp) + 1)
        index, t = spaced(span, count)
        return index, self.table.start[index] + t, self.evaluate_local(index, t)

    def evaluate(self, theta: ArrayLike) -> Array:
        """s, s′, s″, s‴ at cam angles *theta* (rad, any value: wrapped to one turn).

        Returns an array of shape (4, N).
        """
        theta = np.mod(np.atleast_1d(np.asarray(theta, dtype=np.float64)), TWO_PI)
        index = np.clip(np.searchsorted(self._starts, theta, side="right") - 1, 0, None)
        return self.evaluate_local(index, theta - self._starts[index])

    def joints(self) -> list[Joint]:
        """Every boundary between segments, including the wrap from the last to the first."""
        n = len(self.segments)
        # each segment's end_values(), all at once: (n, 2, 4)
        t = np.stack((np.zeros(n), self.table.span), axis=1).ravel()
        ends = self.evaluate_local(np.repeat(np.arange(n), 2), t).T.reshape(n, 2, 4)
        return [
            Joint(self.segments[i].start, (i - 1) % n, i, ends[(i - 1) % n][1], ends[i][0])
            for i in range(n)
        ]

    @property
    def max_lift(self) -> float:
        """The largest displacement of the program (mm or rad)."""
        return max(max(seg.s0, seg.s1) for seg in self.segments)

    def peak(self, order: int) -> float:
        """max |s⁽ᵒʳᵈᵉʳ⁾| over the whole cycle, ignoring steps at joints (inf when unbounded)."""
        return max(seg.peak(order) for seg in self.segments)


def build_program(specs: Sequence[SegmentSpec]) -> MotionProgram:
    """Place *specs* around the cycle and construct each segment's law.

    Raises
    ------
    ProgramError
        The angles do not sum to one turn, the lift goes below zero or does not come back to
        zero, or a segment's law cannot be built from its data.
    """
    if not specs:
        raise ProgramError(None, "", "the motion program has no segments")
    total = sum(spec.angle for spec in specs)
    if not math.isclose(total, TWO_PI, rel_tol=0.0, abs_tol=1e-9):
        raise ProgramError(
            None, "", f"the segment angles sum to {_degrees(total)}°; they must sum to 360°"
        )
    builder = _LawBuilder(specs, _place(specs))
    builder.build_all()
    return MotionProgram([builder.segment(i) for i in range(len(specs))])


def _place(specs: Sequence[SegmentSpec]) -> list[tuple[float, float, float]]:
    """(start angle, start lift, signed lift change) of each segment."""
    out = []
    angle, level = 0.0, 0.0
    scale = max((abs(spec.lift or 0.0) for spec in specs), default=1.0) or 1.0
    for i, spec in enumerate(specs):
        if spec.kind == "dwell":
            delta = 0.0
        else:
            lift = spec.lift if spec.lift is not None else _table_lift(i, spec, level)
            if spec.kind == "rise":
                if lift is None:
                    raise ProgramError(i, "lift", "required for a rise")
                delta = lift
            else:
                if lift is None:
                    if level <= 1e-12 * scale:
                        raise ProgramError(
                            i, "", "a return from zero lift (nothing to return from)"
                        )
                    lift = level
                if lift > level + 1e-9 * scale:
                    raise ProgramError(
                        i, "lift",
                        f"returns {_fmt(lift)} from a lift of {_fmt(level)}: the follower would go "
                        "below zero lift",
                    )
                delta = -lift
        out.append((angle, level, delta))
        angle += spec.angle
        level = level + delta if abs(level + delta) > 1e-9 * scale else 0.0
    if level != 0.0:
        raise ProgramError(
            None, "",
            f"the program ends at a lift of {_fmt(level)}, not 0: add or lengthen a return so the "
            "motion is periodic",
        )
    return out


def _table_lift(index: int, spec: SegmentSpec, level: float) -> float | None:
    """The lift a table segment's points imply (their last displacement from the start)."""
    if spec.law != "table" or not spec.points:
        return None
    return abs(spec.points[-1][1] - level)


def _fmt(value: float) -> str:
    return f"{value:.6g}"


def _degrees(angle: float) -> str:
    """*angle* (rad) in degrees with the digits that tell it from a whole turn."""
    for digits in (6, 9, 12, 17):
        text = f"{math.degrees(angle):.{digits}g}"
        if float(text) != 360.0:
            return text
    return text


class _LawBuilder:
    """Builds each segment's law, resolving ``match`` conditions from neighbouring segments."""

    def __init__(self, specs: Sequence[SegmentSpec], placed: list[tuple[float, float, float]]):
        self.specs = specs
        self.placed = placed
        self.laws: list[tuple[str, Law] | None] = [None] * len(specs)

    def build_all(self) -> None:
        pending = list(range(len(self.specs)))
        while pending:
            still = [i for i in pending if not self._try(i)]
            if len(still) == len(pending):
                raise ProgramError(
                    still[0], "",
                    "'match' cannot be resolved: the neighbouring segment matches this one back",
                )
            pending = still

    def _try(self, i: int) -> bool:
        spec = self.specs[i]
        if spec.kind == "dwell":
            self.laws[i] = ("dwell", DWELL)
            return True
        name = spec.law or ""
        if name not in DATA_LAWS:
            try:
                law = standard_law(name, spec.blend)
            except (KeyError, ValueError) as exc:
                raise ProgramError(i, "law", str(exc)) from None
            self.laws[i] = (name, law.for_return() if spec.kind == "return" else law)
            return True
        start = self._conditions(i, spec.start, at_end=False)
        end = self._conditions(i, spec.end, at_end=True)
        if start is None or end is None:
            return False  # a neighbour is not built yet
        build = {"polynomial": self._polynomial, "table": self._table, "spline": self._spline}
        self.laws[i] = (name, build[name](i, start, end))
        return True

    def _conditions(self, i: int, given: Any, at_end: bool) -> list[tuple[int, float]] | None:
        """(order, physical value) pairs, or None while a matched neighbour is missing."""
        if given is None:
            return []
        out = []
        key = "end" if at_end else "start"
        for order, value in given.items():
            if value == "match":
                j = (i + 1) % len(self.specs) if at_end else (i - 1) % len(self.specs)
                if j == i:
                    raise ProgramError(i, key, "'match' needs a neighbouring segment")
                if self.laws[j] is None:
                    return None
                neighbour = self.segment(j)
                if order > neighbour.law.top_order:
                    raise ProgramError(
                        i, f"{key}.{CONDITION_KEYS[order]}",
                        f"cannot match the {CONDITION_KEYS[order]}: the neighbouring "
                        f"{neighbour.law_name} law gives derivatives up to the "
                        f"{CONDITION_KEYS[neighbour.law.top_order]} (a polynomial, "
                        "polynomial-56789 or spline of order 6 or more gives the snap)")
                value = neighbour.end_values(order)[0 if at_end else 1][order]
            out.append((order, float(value)))
        return out

    def segment(self, j: int) -> ProgramSegment:
        """Segment *j* placed in the cycle (its law must be built)."""
        start, s0, delta = self.placed[j]
        name, law = self.laws[j]  # type: ignore[misc]
        return ProgramSegment(j, self.specs[j].kind, name, law, start, self.specs[j].angle, s0,
                              delta)

    def _normalised(self, i: int, order: int, value: float) -> float:
        """A physical derivative (per radianⁿ) in the law's normalised units."""
        _, _, delta = self.placed[i]
        return value * self.specs[i].angle ** order / delta

    def _points(self, i: int) -> list[tuple[float, float]]:
        """The segment's points as normalised (u, f), checked against its ends."""
        spec = self.specs[i]
        _, s0, delta = self.placed[i]
        pts = list(spec.points or ())
        out = []
        for k, (angle, disp) in enumerate(pts):
            out.append((angle / spec.angle, (disp - s0) / delta))
            if disp < -POINT_SLACK:
                raise ProgramError(i, f"points[{k}]", "displacement below zero")
        u = [p[0] for p in out]
        if any(b <= a for a, b in itertools.pairwise(u)):
            raise ProgramError(i, "points", "the angles must increase strictly")
        return out

    def _polynomial(self, i: int, start: list[tuple[int, float]],
                    end: list[tuple[int, float]]) -> Law:
        conditions = [Condition(0.0, o, self._normalised(i, o, v)) for o, v in start]
        conditions += [Condition(1.0, o, self._normalised(i, o, v)) for o, v in end]
        for k, (u, f) in enumerate(self._points(i)):
            if not 0.0 < u < 1.0:
                raise ProgramError(i, f"points[{k}]",
                                   "a polynomial's points must lie strictly inside the segment")
            conditions.append(Condition(u, 0, f))
        if len(conditions) > 14:
            raise ProgramError(i, "", "too many conditions for a polynomial (at most 16 in all)")
        try:
            return solve_polynomial(conditions)
        except SingularConditionsError as exc:
            raise ProgramError(i, "", str(exc)) from None

    def _table(self, i: int, start: list[tuple[int, float]], end: list[tuple[int, float]]) -> Law:
        from camfab.motion.table import SplineLaw

        points = self._points(i)
        if len(points) < 2:
            raise ProgramError(i, "points", "a table needs at least 2 points")
        (u0, f0), (u1, f1) = points[0], points[-1]
        span = self.specs[i].angle
        _, _, delta = self.placed[i]
        if abs(u0) * span > POINT_SLACK or abs(f0 * delta) > POINT_SLACK:
            raise ProgramError(i, "points[0]",
                               "the first point must be at angle 0 and the segment's start lift")
        if abs(u1 - 1.0) * span > POINT_SLACK or abs((f1 - 1.0) * delta) > POINT_SLACK:
            raise ProgramError(i, f"points[{len(points) - 1}]",
                               "the last point must be at the segment's angle and its end lift")
        ends = {"start": dict(start), "end": dict(end)}
        for key, given in ends.items():
            for order in given:
                if order > 2:
                    raise ProgramError(i, f"{key}.{CONDITION_KEYS[order]}", "a table takes "
                                       f"velocity and acceleration conditions, not "
                                       f"{CONDITION_KEYS[order]}")
        bc = {key: (self._normalised(i, 1, given.get(1, 0.0)),
                    self._normalised(i, 2, given.get(2, 0.0))) for key, given in ends.items()}
        u = [p[0] for p in points]
        f = [p[1] for p in points]
        u[0], f[0], u[-1], f[-1] = 0.0, 0.0, 1.0, 1.0
        return SplineLaw(u, f, bc["start"], bc["end"])

    def _spline(self, i: int, start: list[tuple[int, float]],
                end: list[tuple[int, float]]) -> Law:
        """The B-spline law of the segment's order: its end derivatives 1 … k − 2 those given
        (0 where not), its free control values those given, or *controls* of the smooth rise."""
        from camfab.motion.bspline import DEFAULT_SPLINE_CONTROLS, DEFAULT_SPLINE_ORDER, BSplineLaw

        spec = self.specs[i]
        order = spec.order if spec.order is not None else DEFAULT_SPLINE_ORDER
        ends = {}
        for key, given in (("start", dict(start)), ("end", dict(end))):
            for o in given:
                if o > order - 2:
                    *head, tail = (CONDITION_KEYS[n] for n in range(1, order - 1))
                    fixed = f"{', '.join(head)} and {tail}"
                    raise ProgramError(i, f"{key}.{CONDITION_KEYS[o]}",
                                       f"a spline of order {order} fixes the {fixed} at its "
                                       f"ends, not the {CONDITION_KEYS[o]} (a higher order does)")
            ends[key] = [self._normalised(i, o, given.get(o, 0.0)) for o in range(1, order - 1)]
        controls = spec.controls if spec.controls is not None else DEFAULT_SPLINE_CONTROLS
        try:
            if isinstance(controls, int):
                return BSplineLaw.smooth(order, controls, ends["start"], ends["end"])
            return BSplineLaw(order, controls, ends["start"], ends["end"])
        except ValueError as exc:  # end conditions past floating point
            raise ProgramError(i, "", str(exc)) from None
