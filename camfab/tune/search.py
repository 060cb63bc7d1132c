"""The search of a tuning: the standard laws tried, then the continuous parameters optimised
from several deterministic starts, every candidate held to the design's limits.

1. The choices (:class:`~camfab.tune.families.LawChoice`): each segment's standard laws are
   tried in turn, the others held (coordinate descent over the segments, until a round changes
   nothing, at most :data:`CHOICE_ROUNDS` rounds); the best candidate that meets every limit
   keeps its law.
2. The continuous parameters (a polynomial's points, a blend), normalised to [0, 1] each, are
   optimised by the Nelder–Mead simplex with bounds (:func:`scipy.optimize.minimize`,
   ``method="Nelder-Mead"``, its first simplex a tenth of the range along each parameter): it
   needs no derivatives — the residual vibration is the largest of peak-to-peak swings over
   dwells and speeds, a function with kinks where the largest changes, on which gradient
   methods (SLSQP) stall — and its simplex stretches along the long curved valleys that the
   lifts of a polynomial's points make (they act together: one raised, the other must follow),
   where Powell's line searches were seen to stop half way. The limits enter as a
   penalty: a candidate that breaks a limit scores its objective plus the design's own
   objective times (1 + its violation, :func:`~camfab.tune.margins.violation`), one the design's
   rules refuse or whose joints are less continuous than the design's scores a wall above
   every other. The starts: the design's own values, then (for the peak acceleration or jerk
   of polynomial and spline laws, a convex problem; not of a polydyne cam's, whose lift is the
   train's equation's solution) the linear programme's global optimum
   (:mod:`camfab.tune.convex`), then random points from a generator seeded with :data:`SEED`
   (sorted along each polynomial's points and spline's control values, which then rise in
   order), up to ``--starts``. Where the linear programme's optimum meets every limit it is
   the global optimum of the tuned laws, and no other start is tried.

Each start is first optimised on the objective alone (no candidate analysed: the program's
objectives take milliseconds, an analysis a tenth of a second), and its answer analysed: most
often it meets every limit, the limits not binding. Where it does not, the start is optimised
again from that answer on the penalised objective. There a candidate is analysed in full (its
limits checked) only when its objective beats the best candidate found so far that meets
every limit: one that does not cannot be the answer, and its objective alone (a lower bound of
its penalised score) steers the optimiser. The best so far is always at hand
(:attr:`Search.best`): a stop keeps it.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from camfab.arrays import Array
from camfab.tune.families import AFFINE, ContinuousFamily, PolynomialPoints, SplineControls
from camfab.tune.objectives import Peak
from camfab.tune.trials import Assignment, Evaluator, Trial, normalised

#: The random starts' seed: the same design and options give the same search.
SEED = 20240607
#: The most rounds of the choices' coordinate descent.
CHOICE_ROUNDS = 3
#: The most cycles of the choices and then the continuous parameters (the choices tried again
#: with the parameters found; the parameters again where a choice changed).
CYCLES = 2
#: The simplex's tolerances (on the normalised parameters, and on the score as a share of the
#: design's objective), the size of its first simplex (a share of each parameter's range) and
#: its most evaluations a start, a base and per parameter.
XTOL, FTOL, SIMPLEX = 1e-4, 1e-6, 0.1
MOST_EVALUATIONS, PER_PARAMETER = 120, 80
#: A candidate that is out (refused by the rules, less continuous) scores this many times the
#: penalty's scale: above any candidate that is measured.
WALL = 1e6


@dataclass
class Tried:
    """One law tried on a segment: the family's position, the law, and its candidate."""

    family: int
    option: str
    trial: Trial


@dataclass
class Search:
    """A tuning's search over the *evaluator*'s families from the design's own *start*
    (see the module); *starts* for the continuous parameters; *report* is told of progress
    (the candidates measured so far, the best objective)."""

    evaluator: Evaluator
    start: Assignment
    starts: int = 4
    report: Callable[[Search], None] | None = None
    before: Trial | None = None
    best: Trial | None = None
    closest: Trial | None = None
    tried: list[Tried] = field(default_factory=list)
    global_optimum: bool = False
    convex_note: str | None = None
    phase: str = "the design"
    scale: float = 1.0

    def run(self) -> None:
        """Search (see the module); :attr:`best` holds the best candidate that meets every
        limit at every moment, None while there is none."""
        self.before = self.evaluator.trial(self.start)
        self.evaluator.check(self.before)
        self.scale = (abs(self.before.objective)
                      if math.isfinite(self.before.objective) and self.before.objective else 1.0)
        self._offer(self.before)
        assignment = list(self.start)
        for cycle in range(CYCLES):
            self.phase = "the laws"
            if not self._choices(assignment) and cycle > 0:
                break
            self.phase = "the parameters"
            if not self._continuous(assignment):
                break
            if self.best is not None:
                assignment = list(self.best.assignment)

    # --- scoring -------------------------------------------------------------------------------

    def score(self, trial: Trial, penalised: bool = True) -> float:
        """*trial*'s penalised objective, it checked when it could be the best (see the
        module); its objective alone without *penalised*."""
        if self.report is not None:
            self.report(self)
        if trial.out is not None or not math.isfinite(trial.objective):
            return WALL * self.scale
        if not penalised and not trial.checked:
            return trial.objective
        if not trial.checked and (self.best is None or trial.rank < self.best.rank):
            self.evaluator.check(trial)
            if trial.out is not None or not math.isfinite(trial.objective):
                return WALL * self.scale
        if not trial.checked:
            return trial.objective  # no better than the best: its limits do not matter
        self._offer(trial)
        if trial.feasible:
            return trial.objective
        return trial.objective + self.scale * (1.0 + trial.violation)

    def _offer(self, trial: Trial) -> None:
        if trial.feasible:
            if self.best is None or trial.rank < self.best.rank:
                self.best = trial
        elif trial.checked and trial.out is None and (
                self.closest is None or trial.violation < self.closest.violation):
            self.closest = trial

    # --- the choices ---------------------------------------------------------------------------

    def _choices(self, assignment: list) -> bool:
        """Coordinate descent over the choices, from *assignment* (changed in place); True
        when a choice changed. :attr:`tried` holds the first round's candidates."""
        families = self.evaluator.families
        if not any(f.discrete for f in families):
            return False
        tried: list[Tried] = []
        any_change = False
        for round_ in range(CHOICE_ROUNDS):
            changed = False
            for pos, family in enumerate(families):
                if not family.discrete:
                    continue
                kept = assignment[pos]
                winner: Trial | None = None
                for option in family.options:  # type: ignore[attr-defined]
                    trial = self.evaluator.trial((*assignment[:pos], option,
                                                  *assignment[pos + 1:]))
                    self.score(trial)
                    if round_ == 0:
                        tried.append(Tried(pos, option, trial))
                    if trial.feasible and (winner is None or trial.rank < winner.rank):
                        winner = trial
                if winner is not None and winner.assignment[pos] != kept:
                    assignment[pos] = winner.assignment[pos]
                    changed = any_change = True
            if not changed:
                break
        self.tried = tried
        return any_change

    # --- the continuous parameters -------------------------------------------------------------

    def _continuous(self, assignment: list) -> bool:
        """The continuous parameters optimised (see the module), the choices of the best so
        far (or of *assignment*) held; False when there are none."""
        from scipy.optimize import minimize

        families = self.evaluator.families
        positions = [pos for pos, f in enumerate(families) if not f.discrete]
        if not positions:
            return False
        # the best so far keeps the laws chosen; its continuous values are the first start
        base = list(self.best.assignment) if self.best is not None else list(assignment)
        parts = [families[pos] for pos in positions]
        sizes = [f.size for f in parts]  # type: ignore[attr-defined]
        bounds = [(0.0, 1.0)] * sum(sizes)

        def assign(x: Array) -> Assignment:
            out = list(base)
            at = 0
            for pos, size in zip(positions, sizes, strict=True):
                out[pos] = normalised(x[at:at + size])
                at += size
            return tuple(out)

        def fun(x: Array, penalised: bool = True) -> float:
            return self.score(self.evaluator.trial(assign(x)), penalised)

        starts = [np.concatenate([np.asarray(base[pos], dtype=np.float64) for pos in positions])]
        if (isinstance(self.evaluator.objective, Peak) and all(isinstance(f, AFFINE)
                                                               for f in parts)
                and self.evaluator.design.motion_target == "cam"):
            x = self._convex(base, positions, assign)
            if x is not None:
                trial = self.evaluator.trial(assign(x))
                fun(x)
                if trial.feasible and self.best is trial:
                    self.global_optimum = True
                    return True
                starts.insert(0, x)
        rng = np.random.default_rng(SEED)
        while len(starts) < max(self.starts, 1):
            starts.append(np.concatenate([_sample(f, rng) for f in parts]))  # type: ignore[arg-type]
        most = MOST_EVALUATIONS + PER_PARAMETER * sum(sizes)
        free = not self.evaluator.objective.needs_analysis

        def optimised(x: Array, penalised: bool) -> Array:
            options = {"xatol": XTOL, "fatol": FTOL * self.scale, "maxfev": most,
                       "initial_simplex": _simplex(x)}
            return minimize(fun, x, (penalised,), method="Nelder-Mead", bounds=bounds,
                            options=options).x

        for k, x0 in enumerate(starts[:max(self.starts, 1)]):
            self.phase = f"the parameters, start {k + 1} of {min(len(starts), self.starts)}"
            x = x0
            if free:  # the objective alone, then its answer checked
                x = optimised(x, False)
                if self._checked(assign(x)):
                    continue
            self._checked(assign(optimised(x, True)))
        return True

    def _checked(self, assignment: Assignment) -> bool:
        """Analyse the candidate of *assignment* (an optimiser's answer); True when it meets
        every limit."""
        trial = self.evaluator.trial(assignment)
        if trial.out is None and math.isfinite(trial.objective):
            self.evaluator.check(trial)
            self._offer(trial)
        return trial.feasible

    def _convex(self, base: list, positions: list[int],
                assign: Callable[[Array], Assignment]) -> Array | None:
        """The parameters of the least peak of the tuned laws (:mod:`camfab.tune.convex`),
        or None where the programme cannot be set up or solved (:attr:`convex_note` says
        why)."""
        from camfab.tune.convex import derivative_pieces, least_peak

        ev = self.evaluator
        objective = ev.objective
        assert isinstance(objective, Peak)
        indices = [ev.families[pos].index for pos in positions]
        n = sum(ev.families[pos].size for pos in positions)  # type: ignore[attr-defined]

        def coefficients(x: Array) -> Array:
            return derivative_pieces(ev.design_of(assign(x)), indices, objective.order)[0]

        try:
            middle = coefficients(np.full(n, 0.5))
            lengths = derivative_pieces(ev.design_of(assign(np.full(n, 0.5))), indices,
                                        objective.order)[1]
            columns = [(coefficients(0.5 + 0.25 * np.eye(n)[i]) - middle) / 0.25
                       for i in range(n)]
        except Exception as exc:  # a point the rules refuse at these shares: no programme
            self.convex_note = f"the linear programme could not be set up: {exc}"
            return None
        basis = np.stack(columns, axis=-1)
        answer = least_peak(middle - basis @ np.full(n, 0.5), basis, lengths)
        if not answer.solved:
            self.convex_note = f"the linear programme was not solved: {answer.message}"
            return None
        self.convex_note = (f"the tuned laws' least peak {objective.name} is "
                            f"{answer.t:.10g} {objective.unit} (a linear programme solved by "
                            f"HiGHS, {answer.rounds} round(s) of its exchange)")
        return answer.x


def _simplex(x: Array) -> Array:
    """The first simplex about *x* (in [0, 1]ⁿ): *x*, and *x* moved by :data:`SIMPLEX` along
    each parameter (back, where forward leaves the range)."""
    x = np.clip(np.asarray(x, dtype=np.float64), 0.0, 1.0)
    points = [x]
    for i in range(x.size):
        moved = x.copy()
        moved[i] += SIMPLEX if x[i] + SIMPLEX <= 1.0 else -SIMPLEX
        points.append(moved)
    return np.array(points)


def _sample(family: ContinuousFamily, rng: np.random.Generator) -> Array:
    """A random start for *family*'s parameters in [0, 1]: a polynomial's points' shares and
    a spline's control values sorted, so that they rise in order."""
    x = rng.random(family.size)
    return np.sort(x) if isinstance(family, (PolynomialPoints, SplineControls)) else x


@dataclass
class Progress:
    """A progress line on stderr through *write* (which adds no line break) every
    :data:`EVERY` seconds once the search has run :data:`AFTER` seconds (on a terminal, one
    line rewritten)."""

    write: Callable[[str], None]
    terminal: bool
    started: float = field(default_factory=time.monotonic)
    last: float = 0.0
    shown: bool = False

    AFTER = 2.0
    EVERY = 1.0

    def __call__(self, search: Search) -> None:
        now = time.monotonic()
        if now - self.started < self.AFTER or now - self.last < self.EVERY:
            return
        self.last = now
        ev = search.evaluator
        best = ("none meeting every limit yet" if search.best is None else
                f"best {search.best.objective:.5g} {ev.objective.unit}")
        line = (f"tune: {ev.measured} candidates ({ev.analysed} analysed), {best} — "
                f"{search.phase}")
        self.shown = True
        self.write(f"\r{line}\033[K" if self.terminal else line + "\n")

    def finish(self) -> None:
        """End the rewritten line (on a terminal)."""
        if self.shown and self.terminal:
            self.write("\n")
