"""Sizing: the least base radius (a drum's: its radius) that meets every limit of a design, and
the offset or pivot distance that lets it be least.

A cam kind states its limits at a size as :class:`LimitValue` rows (:class:`SizeProblem`),
measured by the exact evaluators and on the grid of cam angles the checks of a build use, so
that a sized cam passes them as built, and on a grid four times finer besides, which puts a
smooth extreme within some 1e-7 of its exact value. :func:`least_size` scans sizes
geometrically from the smallest the part's fit allows to :data:`SEARCH_FACTOR` times the
follower's lift — the sizes that pass need not begin at the bottom (an arm that must reach the
prime circle bounds a base radius from above too) — then narrows the bracket between the last
size that fails and the first that passes, to :data:`SIZE_TOLERANCE_MM`.
:func:`best_parameter` finds the offset (or pivot distance) with the least such size by a
bounded golden-section search.

Lengths are millimetres and angles degrees.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Literal, Protocol

import numpy as np

from camfab.arrays import Array
from camfab.geometry.disc_geometry import ANALYSIS_STEP

if TYPE_CHECKING:
    from camfab.curves.follower import FollowerGeometry
    from camfab.design import Design
    from camfab.motion.program import MotionProgram

#: The keys sized (:attr:`SizeProblem.key`), in words.
SIZE_NAMES = {"base_radius": "base radius", "radius": "drum radius"}

#: How close (mm) the sized radius comes to the least one that passes on the grids (it is on the
#: side that passes).
SIZE_TOLERANCE_MM = 1e-6

#: Sizes are searched up to this many times the follower's lift (at the trace point), above the
#: least the part's fit allows.
SEARCH_FACTOR = 100.0

#: Sizes tried in the scan before the bracket is narrowed (geometrically spaced).
SCAN_STEPS = 48

#: Sizes tried in the scan of each step of an offset's or pivot's search, and how close each
#: such size comes (relative): the search needs the shape of the curve, not its last digit.
SEARCH_SCAN_STEPS = 24
SEARCH_TOLERANCE = 1e-5

#: An offset or pivot distance is found to within this (mm): finer than it can be mounted, and
#: the least size at it is within about twice that of the least at the best one.
PARAMETER_TOLERANCE_MM = 1e-3

#: Intervals of the scan that brackets the golden-section search of an offset or pivot.
PARAMETER_SCAN = 8


@dataclass(frozen=True)
class Grid:
    """Cam angles (rad) and the motion there, (4, N): s, s′, s″, s‴."""

    theta: Array
    motion: Array


@functools.lru_cache(maxsize=4)
def grids(program: MotionProgram, step: float = ANALYSIS_STEP) -> tuple[Grid, Grid]:
    """The build's grid of *program* (segment by segment, joints twice, *step* apart), and that
    grid with one four times finer besides. Their arrays are read-only: the last few pairs are
    kept (by the program object, not its value), for a sizing asks for the same program's
    several times."""
    _, theta, motion = program.segment_grid(step)
    _, fine_theta, fine_motion = program.segment_grid(step / 4.0)
    pair = (Grid(theta, motion), Grid(np.concatenate((theta, fine_theta)),
                                      np.concatenate((motion, fine_motion), axis=1)))
    for grid in pair:
        grid.theta.flags.writeable = grid.motion.flags.writeable = False
    return pair


@dataclass(frozen=True)
class LimitValue:
    """One limit of a design at one size.

    Attributes
    ----------
    id
        The id of the build's check it is (``pressure_angle``, ``undercut``, ``curvature``,
        ``face_width``, ``groove``; ``_b`` for a conjugate's cam b), or of the part's fit
        (``bore``, ``keyway``, ``tolerance``, ``offset``, ``reach``).
    what
        The limit in words, for messages.
    ok
        Whether the size meets it.
    value, limit
        The measured value and its limit (``unit``; None where the size leaves nothing to
        measure).
    sense
        ``max``: the value must stay at or below the limit; ``min``: at or above it.
    at_deg
        The cam angle where the value is measured (deg), or None for a limit of the fit.
    least
        The exact size that meets it with nothing to spare, where a closed form gives it (mm).
    of_size
        True when the value measured is the size itself (a bore's wall, the export tolerance):
        the limit is then the least size it allows, and says so alone.
    """

    id: str
    what: str
    ok: bool
    value: float | None = None
    limit: float | None = None
    unit: str = "mm"
    sense: Literal["max", "min"] = "min"
    at_deg: float | None = None
    least: float | None = None
    of_size: bool = False

    @property
    def margin(self) -> float | None:
        """How far the value is inside its limit (its unit; negative: outside), or None where
        there is no value to measure."""
        if self.value is None or self.limit is None:
            return None
        return self.limit - self.value if self.sense == "max" else self.value - self.limit

    def better(self, other: LimitValue) -> bool:
        """Whether this value is nearer to meeting the limit than *other*'s."""
        if other.value is None:
            return self.value is not None
        if self.value is None:
            return False
        return self.value < other.value if self.sense == "max" else self.value > other.value


class Evaluate(Protocol):
    """The limits at a size (mm), measured on the build's grid or also on the finer one
    (*fine*); with *until*, those up to the first that fails (all a search needs)."""

    def __call__(self, size: float, fine: bool, until: bool = False) -> list[LimitValue]: ...


@dataclass(frozen=True)
class SizeProblem:
    """What a kind gives the sizing: its limits at a size, and the sizes to search (mm): from
    *low*, the least the part's fit allows (a hole inside the base circle, ...), to *high*."""

    key: str
    evaluate: Evaluate
    low: float
    high: float


@dataclass(frozen=True)
class Found:
    """The least size that meets every limit (mm), or None; the limits at it (or, when there is
    none, at the largest size searched), the limit that governs it, and for each limit that no
    size met, the best value the search reached (with ``least`` the size it was reached at)."""

    size: float | None
    limits: tuple[LimitValue, ...]
    governing: LimitValue | None
    unmet: tuple[LimitValue, ...] = field(default=())
    #: When no size meets the limits: the largest size searched (mm), and the limits whose
    #: value is the same at every size.
    searched_to: float | None = None
    unchanged: frozenset[str] = frozenset()
    #: When no size meets the limits and one of them holds on small sizes only (a roller's
    #: life, which falls as the cam grows): its value at the least size from which it fails at
    #: every size searched (``least``: that size), and the limits that fail at the largest size
    #: where it still holds (``least``: that size).
    capped: tuple[LimitValue, ...] = ()
    below_cap: tuple[LimitValue, ...] = ()


def passes(limits: list[LimitValue]) -> bool:
    return all(limit.ok for limit in limits)


def least_size(problem: SizeProblem, tolerance: float = SIZE_TOLERANCE_MM,
               steps: int = SCAN_STEPS, fine: bool = True) -> Found:
    """The least size of *problem* that meets every limit, within *tolerance* (mm, on the side
    that passes), found by a scan of *steps* sizes and a narrowing of the bracket
    (:func:`_bisect`), on the build's grid and then (*fine*) on the finer grid too."""
    low, high = problem.low, max(problem.high, problem.low * (1.0 + 1e-9))
    ratio = (high / low) ** (1.0 / steps) if low > 0.0 else 0.0
    sizes = [low * ratio**k for k in range(steps + 1)] if low > 0.0 else [
        high * k / steps for k in range(1, steps + 1)]
    first = next((k for k, size in enumerate(sizes)
                  if passes(problem.evaluate(size, False, True))), None)
    if first is None:
        return _none(problem, sizes)
    below = sizes[first - 1] if first > 0 else None
    size = sizes[first]
    if below is not None:
        below, size = _bisect(problem, below, size, tolerance, False)
    if fine:
        below, size = _fine(problem, below, size, tolerance)
    limits = problem.evaluate(size, fine)
    governing = _governing(problem, below, size, fine, limits)
    if governing is not None and governing.least is not None and governing.least < size:
        exact = problem.evaluate(governing.least, fine)
        if passes(exact):  # a closed form's exact size
            size, limits = governing.least, exact
    return Found(size, tuple(limits), governing)


def _none(problem: SizeProblem, sizes: list[float]) -> Found:
    """No size meets the limits: for each limit that fails at every size of the scan, the best
    value it reached (``least``: the size where); for one that holds on the smaller sizes
    only, where it starts failing for good, and what fails where it still holds."""
    best: dict[str, LimitValue] = {}
    seen: dict[str, set[float]] = {}
    measured = [(size, problem.evaluate(size, False)) for size in sizes]
    held: dict[str, int] = {}  # the last size (its index) where each limit holds
    for k, (size, limits) in enumerate(measured):
        for limit in limits:
            if limit.value is not None:
                seen.setdefault(limit.id, set()).add(round(limit.value, 9))
            if limit.ok:
                held[limit.id] = k
            elif limit.id not in best or limit.better(best[limit.id]):
                best[limit.id] = _at(limit, size)
    limits = measured[-1][1]
    failing = [limit for limit in limits if not limit.ok and limit.id in best]
    unmet = tuple(best[limit.id] for limit in failing if limit.id not in held)
    capped: list[LimitValue] = []
    below: tuple[LimitValue, ...] = ()
    for limit in failing:
        if limit.id in held:
            size, at = measured[held[limit.id] + 1]
            capped.append(_at(next(x for x in at if x.id == limit.id), size))
    if capped:
        size, at = measured[min(held[limit.id] for limit in capped)]
        ids = {limit.id for limit in capped}
        below = tuple(_at(x, size) for x in at if not x.ok and x.id not in ids)
    return Found(None, tuple(limits), None, unmet, sizes[-1],
                 frozenset(key for key, values in seen.items() if len(values) == 1),
                 tuple(capped), below)


def _at(limit: LimitValue, size: float) -> LimitValue:
    """*limit* with the size it was measured at as its ``least``."""
    return replace(limit, least=size)


def _bisect(problem: SizeProblem, below: float, size: float, tolerance: float,
            fine: bool) -> tuple[float, float]:
    """Narrow [*below* (fails), *size* (passes)] to *tolerance* (mm): by false position on the
    margin of the limit that fails at *below* (with the Illinois modification, which keeps
    either end from sticking), halving the bracket instead where a step gains too little or
    the limit has no margin to interpolate."""
    at_size = problem.evaluate(size, fine)
    failing = _first_failing(problem.evaluate(below, fine, True))
    f_below = failing.margin if failing is not None else None
    kept = 0  # which end stayed in the last step: -1 below, +1 size
    while size - below > tolerance:
        width = size - below
        f_size = _margin_of(at_size, failing)
        if f_below is None or f_size is None or f_size - f_below <= 0.0:
            trial = 0.5 * (below + size)
        else:
            trial = size - f_size * width / (f_size - f_below)
            trial = min(max(trial, below + 0.01 * width), size - 0.01 * width)
        if trial in (below, size):
            break
        limits = problem.evaluate(trial, fine, True)
        if passes(limits):
            size = trial
            at_size = problem.evaluate(trial, fine) if failing is not None else limits
            if kept == -1 and f_below is not None:
                f_below *= 0.5  # Illinois: the end kept twice counts half
            kept = -1
        else:
            below = trial
            failing = _first_failing(limits)
            f_below = failing.margin if failing is not None else None
            kept = 1
        if size - below > 0.5 * width and kept == -1 and trial != 0.5 * (below + size):
            # a false-position step that gained little: halve the bracket as well
            middle = 0.5 * (below + size)
            limits = problem.evaluate(middle, fine, True)
            if passes(limits):
                size, at_size = middle, problem.evaluate(middle, fine)
            else:
                below, failing = middle, _first_failing(limits)
                f_below = failing.margin if failing is not None else None
            kept = 0
    return below, size


def _first_failing(limits: list[LimitValue]) -> LimitValue | None:
    return next((limit for limit in limits if not limit.ok), None)


def _margin_of(limits: list[LimitValue], like: LimitValue | None) -> float | None:
    """The margin in *limits* of the limit of *like*'s id."""
    if like is None:
        return None
    return next((limit.margin for limit in limits if limit.id == like.id), None)


def _fine(problem: SizeProblem, below: float | None, size: float,
          tolerance: float) -> tuple[float | None, float]:
    """The bracket [*below*, *size*] of the build's grid made good on the finer grid too: a size
    that passes there may miss an extreme between its points."""
    if passes(problem.evaluate(size, True, True)):
        return below, size
    step = tolerance
    below = size
    for _ in range(200):
        upper = size + step
        if passes(problem.evaluate(upper, True, True)):
            return _bisect(problem, below, upper, tolerance, True)
        below, step = upper, step * 2.0
    return below, upper  # not reached: the finer grid moves an extreme by far less


def _governing(problem: SizeProblem, below: float | None, size: float, fine: bool,
               limits: list[LimitValue]) -> LimitValue | None:
    """The limit that governs *size*: the first that fails just below it (its value at
    *size*), or, at the least size the fit allows, the fit limit that sets it."""
    if below is not None:
        failing = [limit.id for limit in problem.evaluate(below, fine) if not limit.ok]
    else:
        failing = [limit.id for limit in limits if limit.least is not None
                   and math.isclose(limit.least, problem.low, rel_tol=1e-9, abs_tol=1e-9)]
    return next((limit for limit in limits if limit.id in failing), None)


def best_parameter(size_at: Callable[[float], Found], low: float, high: float,
                   tolerance: float = PARAMETER_TOLERANCE_MM,
                   scan: int = PARAMETER_SCAN) -> tuple[float, Found]:
    """The parameter in [*low*, *high*] (mm) whose least size (*size_at*) is smallest, to
    *tolerance* (mm), and its sizing: a scan of *scan* intervals, then a golden-section search
    in the two round the best (the least size taken as unimodal there). A parameter with no
    size counts as infinitely large."""
    def cost(x: float) -> float:
        found = size_at(x)
        return math.inf if found.size is None else found.size

    # a scan first: a parameter with no size on one side must not steer the golden section
    xs = [low + (high - low) * k / scan for k in range(scan + 1)]
    costs = [cost(x) for x in xs]
    k = min(range(len(xs)), key=costs.__getitem__)
    if math.isinf(costs[k]):
        return xs[k], size_at(xs[k])
    golden = (math.sqrt(5.0) - 1.0) / 2.0
    a, b = xs[max(k - 1, 0)], xs[min(k + 1, scan)]
    c, d = b - golden * (b - a), a + golden * (b - a)
    fc, fd = cost(c), cost(d)
    while b - a > tolerance:
        if fc <= fd:
            b, d, fd = d, c, fc
            c = b - golden * (b - a)
            fc = cost(c)
        else:
            a, c, fc = c, d, fd
            d = a + golden * (b - a)
            fd = cost(d)
    x = 0.5 * (a + b)
    return x, size_at(x)


#: A kind's sizing: the problem of *design* with the follower *follower* (its offset or pivot
#: distance the search's), its limits measured on a pair of grids (the build's, and with a
#: finer one; the search passes coarser ones).
ProblemOf = Callable[["Design", "FollowerGeometry", tuple[Grid, Grid]], SizeProblem]

#: The searches for an offset or pivot distance measure on a grid this many times coarser than
#: the build's: the search needs where the least size is smallest, not its last digit.
SEARCH_COARSENING = 8

#: A search for an offset or pivot looks for each size within this factor of the last one found
#: first, trying this many sizes before narrowing the bracket.
NEAR = 1.25
NEAR_STEPS = 4

#: The pivot distances searched, as multiples of the arm's length.
PIVOT_RANGE = (0.25, 4.0)


@dataclass(frozen=True)
class Sizing:
    """The answer of a sizing: the key sized (``base_radius``, a drum's ``radius``), the least
    size found (mm, rounded up to ``rounded_to`` where the design asks), the limits there and
    the one that governs it; the offset and the pivot distance chosen (mm) where they were
    sized too."""

    key: str
    found: Found
    offset: float | None = None
    pivot_distance: float | None = None
    rounded_to: float | None = None

    @property
    def size(self) -> float | None:
        return self.found.size


def size_design(design: Design, keys: frozenset[str], problem_of: ProblemOf,
                pivot: bool = False, precise: bool = True) -> Sizing:
    """The least size of *design*'s cam (see :class:`Sizing`), with the offset of a
    translating follower when *keys* holds ``follower.offset`` and the pivot distance of an
    oscillating one when *pivot*: for a flat face, the offset that centres the face on the
    contact (the least face width: the base radius does not depend on it); else the one
    whose least size is smallest, found to :data:`PARAMETER_TOLERANCE_MM` (not *precise*: as
    the search on the coarse grid finds it, some tenths of a millimetre off at a kink of the
    motion; the size at it is exact all the same)."""
    from camfab.curves.follower import FollowerGeometry

    follower = FollowerGeometry.from_design(design)
    program = design.program
    build = grids(program)
    coarse = grids(program, ANALYSIS_STEP * SEARCH_COARSENING)[0]
    offset = pivot_distance = None

    def search(vary: Callable[[float], FollowerGeometry], low: float, high: float) -> float:
        """The parameter in [low, high] with the least size: found on the coarse grid, then
        on the build's grid within a quarter step of the first search's scan of it. Each size
        is looked for near the one found last (the parameter moves a little from one to the
        next), and from the bottom where it is not there."""
        def least(grid: Grid) -> Callable[[float], Found]:
            last: list[float] = []

            def size_at(x: float) -> Found:
                problem = problem_of(design, vary(x), (grid, grid))
                if last:
                    near = last[-1]
                    narrow = SizeProblem(problem.key, problem.evaluate,
                                         max(problem.low, near / NEAR), near * NEAR)
                    found = least_size(narrow, max(near, 1.0) * SEARCH_TOLERANCE, NEAR_STEPS,
                                       fine=False)
                    if found.size is not None and found.size > narrow.low:
                        last.append(found.size)
                        return found
                found = least_size(problem, max(problem.high, 1.0) * SEARCH_TOLERANCE,
                                   SEARCH_SCAN_STEPS, fine=False)
                if found.size is not None:
                    last.append(found.size)
                return found
            return size_at

        first, found = best_parameter(least(coarse), low, high, (high - low) * 1e-3,
                                      PARAMETER_SCAN)
        if found.size is None or not precise:
            return first
        step = (high - low) / PARAMETER_SCAN / 4
        best, _ = best_parameter(least(build[0]), max(low, first - step),
                                 min(high, first + step), PARAMETER_TOLERANCE_MM, 4)
        return best

    if "follower.offset" in keys and not follower.oscillating:
        rate = design.cam.sigma * build[0].motion[1]
        low, high = float(rate.min()), float(rate.max())
        if follower.flat:
            offset = 0.5 * (low + high)
        else:
            offset = search(lambda e: replace(follower, offset=e), low, high)
        offset = _to_tolerance(offset)
        follower = replace(follower, offset=offset)
    if pivot and follower.oscillating:
        arm = follower.arm_length
        pivot_distance = _to_tolerance(search(lambda a: replace(follower, pivot_distance=a),
                                              PIVOT_RANGE[0] * arm, PIVOT_RANGE[1] * arm))
        follower = replace(follower, pivot_distance=pivot_distance)
    problem = problem_of(design, follower, build)
    found = least_size(problem)
    step = design.sizing.round_to
    if found.size is not None and step is not None:
        found = _rounded(problem, found, step)
    return Sizing(problem.key, found, offset, pivot_distance, step)


def _to_tolerance(parameter: float) -> float:
    """An offset or pivot distance (mm) as its search finds it, to within
    :data:`PARAMETER_TOLERANCE_MM`, rounded to that: a symmetric motion's best offset is 0 mm,
    not −0.0002 mm (the least size at it is measured anew)."""
    return round(parameter / PARAMETER_TOLERANCE_MM) * PARAMETER_TOLERANCE_MM + 0.0


def _rounded(problem: SizeProblem, found: Found, step: float) -> Found:
    """*found* rounded up to a multiple of *step* (mm), the next multiple that meets every limit
    (a hundred steps at most, else *found* as it was)."""
    assert found.size is not None
    size = math.ceil(found.size / step - 1e-9) * step
    for _ in range(100):
        limits = problem.evaluate(size, True)
        if passes(limits):
            governing = found.governing
            if governing is not None:
                governing = next((limit for limit in limits if limit.id == governing.id),
                                 governing)
            return Found(size, tuple(limits), governing)
        size += step
    return found


def fmt(value: float | None, unit: str = "") -> str:
    """A value in a sizing's words: 4 decimals for millimetres, 4 significant digits else,
    with its unit."""
    if value is None:
        return "–"
    text = f"{value:.4f}" if unit == "mm" else f"{value:.4g}"
    return f"{text}{'°' if unit == 'deg' else f' {unit}' if unit else ''}"


def unmet_words(sizing: Sizing, name: str) -> str:
    """Why no size meets the limits: for each limit no size met, the best value it reached and
    at which size, or that no size changes it; for each that holds on the smaller sizes only,
    the size from which it fails, and what fails where it still holds (*name*: the key sized,
    in words)."""
    found = sizing.found
    parts = []
    for limit in found.unmet:
        if limit.id in found.unchanged:
            where = f"whatever the {name}"
        else:
            where = f"at best, at a {name} of {fmt(limit.least, 'mm')}"
        parts.append(f"{_measured(limit)} {where}{_must(limit)}")
    for limit in found.capped:
        at = fmt(limit.least, "mm")
        if limit.value is None:  # a fit, which says why
            parts.append(f"from a {name} of {at} on, {limit.what}")
        else:
            parts.append(f"{_measured(limit)} at a {name} of {at}{_must(limit)} and fails at "
                         f"every larger {name} searched")
    if found.below_cap:
        size = found.below_cap[0].least
        parts.append(f"at a {name} of {fmt(size, 'mm')}, where "
                     f"{'it holds' if len(found.capped) == 1 else 'they hold'}, "
                     + ", ".join(f"{_measured(limit)}{_must(limit)}"
                                 for limit in found.below_cap))
    if not parts:
        parts = [limit.what for limit in found.limits if not limit.ok]
    reach = f" up to {fmt(found.searched_to, 'mm')}" if found.searched_to else ""
    return f"no {name}{reach} meets the limits: {'; '.join(parts)}"


def _measured(limit: LimitValue) -> str:
    """A limit's value in words (its description alone where it has no value: a fit that
    fails, which says why)."""
    if limit.value is None:
        return limit.what
    return f"{limit.what} is {fmt(limit.value, limit.unit)}"


def _must(limit: LimitValue) -> str:
    """What a limit asks, in parentheses after its value (nothing for a fit's)."""
    if limit.value is None or limit.limit is None:
        return ""
    bound = "at most" if limit.sense == "max" else "at least"
    return f" (it must be {bound} {fmt(limit.limit, limit.unit)})"


#: The checks a sizing can answer, when the sizing sees them fail too (a roller's envelope that
#: crosses itself at a velocity step is an undercut no radius removes).
ADVISED = ("pressure_angle", "undercut", "curvature", "groove", "face_width",
           "contact_stress", "roller_life")

#: The checks that are one of both cams of a pair and a limit of each.
_ONE_CHECK = {"contact_stress_b": "contact_stress", "roller_life_b": "roller_life"}


def advice(design: Design, problem_of: ProblemOf, failing: set[str]) -> dict[str, str]:
    """For each check in *failing* (ids) that the sizing sees fail at the design's size, the
    size that passes, computed: the least at the design's offset and, for a translating
    follower off a flat face, the least with the best offset (by check id)."""
    from camfab.curves.follower import FollowerGeometry

    follower = FollowerGeometry.from_design(design)
    problem = problem_of(design, follower, grids(design.program))
    name = SIZE_NAMES[problem.key]
    current = design.cam.radius if problem.key == "radius" else design.cam.base_radius
    assert current is not None
    # the contact stress and the roller life are one check of both cams of a pair
    seen = {_ONE_CHECK.get(limit.id, limit.id)
            for limit in problem.evaluate(current, False) if not limit.ok} & failing
    if not seen:
        return {}
    here = size_design(design, frozenset({f"cam.{problem.key}"}), problem_of)
    if here.size is None:
        text = unmet_words(here, name)
    else:
        text = f"a {name} of {fmt(here.size, 'mm')} passes"
        if not follower.oscillating and not follower.flat and problem.key == "base_radius":
            # the offset as a quick search finds it: camfab size --offset finds it exactly
            best = size_design(design, frozenset({"cam.base_radius", "follower.offset"}),
                               problem_of, precise=False)
            text += " with this offset"
            if best.size is None or best.offset is None:
                pass
            elif fmt(best.offset, "mm") == fmt(_to_tolerance(follower.offset), "mm"):
                text += ", which is about the best (camfab size --offset)"
            else:
                text += (f", and {fmt(best.size, 'mm')} with the offset {fmt(best.offset, 'mm')} "
                         "(near the least: camfab size --offset)")
    return {key: text for key in seen}
