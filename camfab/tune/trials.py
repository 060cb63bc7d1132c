"""One candidate of a tuning: the design's data with its families' values written in, checked
and measured.

A candidate's objective comes first, from its motion program where the objective allows
(:mod:`camfab.tune.objectives`): the program is built straight from the design's validated
segments with the families' values put in (:meth:`Family.updates
<camfab.tune.families.ContinuousFamily.updates>`, some tens of microseconds, where validating
the design's data again takes milliseconds). Its limits come from its whole analysis of the
data written (the values as the file will hold them), checked as a sweep
checks a variant (:func:`camfab.sweep.rows.checked`: status ``OK``, ``FAIL`` with the checks that
failed, ``INVALID`` with the design's message), and every limit's margin
(:mod:`camfab.tune.margins`). A candidate that makes the motion less continuous than the
design's at any joint (a velocity or acceleration step where the design had none; a jerk step
counts as continuous, as the continuity check counts it) is out before it is measured.

Candidates are kept by the values written, so the search never measures one twice.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from camfab.arrays import Array
from camfab.design import Design
from camfab.motion.laws import LAWS
from camfab.motion.program import MotionProgram
from camfab.tune.families import ChoiceFamily, ContinuousFamily, Family, Written
from camfab.tune.margins import Margin, margins, violation
from camfab.tune.objectives import Objective

#: A value of each family: a law's name, or a continuous family's normalised parameters.
Assignment = tuple[Any, ...]

#: The order of a joint without a step of the velocity, acceleration or jerk.
SMOOTH = 4

#: A segment's keys that belong to its law (the laws' parameters, as the registry names them):
#: dropped where a standard law takes its place.
LAW_KEYS = tuple(dict.fromkeys(key for info in LAWS for key in info.params))


@dataclass
class Trial:
    """One candidate: the values written (key paths and values, in the families' order), its
    data, its objective (inf where it has none), why it is out (an invalid design, a joint
    made less continuous), and once checked its status, message, margins and violation."""

    assignment: Assignment
    written: tuple[Written, ...]
    data: dict[str, Any]
    objective: float = math.inf
    tiebreak: float = math.inf
    out: str | None = None
    status: str | None = None
    message: str = ""
    margins: list[Margin] = field(default_factory=list)
    violation: float = 0.0

    @property
    def rank(self) -> tuple[float, float]:
        """What candidates are compared by: the objective, then its tie-break."""
        return self.objective, self.tiebreak

    @property
    def checked(self) -> bool:
        return self.status is not None

    @property
    def feasible(self) -> bool:
        """Checked and meets every limit."""
        return self.status == "OK" and self.out is None and math.isfinite(self.objective)


def joint_orders(program: MotionProgram,
                 tolerances: dict[int, float] | None = None) -> list[int]:
    """The lowest derivative that steps at each joint (1 velocity, 2 acceleration, 3 jerk;
    :data:`SMOOTH` where none does), by the segment that starts there; *tolerances* as
    :func:`~camfab.motion.continuity.joint_steps` takes them."""
    from camfab.motion.continuity import joint_steps

    orders = [SMOOTH] * len(program.segments)
    for step in joint_steps(program, tolerances):
        orders[step.after] = min(orders[step.after], step.order)
    return orders


def with_motion(design: Design, motion: Sequence[Any]) -> Design:
    """*design* with the segments *motion* (design models, internal units), its program built
    afresh when asked for."""
    copy = design.model_copy(update={"motion": tuple(motion)})
    for cached in ("program", "output_program"):  # the copy's are the original's
        copy.__dict__.pop(cached, None)
    return copy


class Evaluator:
    """Candidates of *design*, whose data is *base*, from *file* (its files found from
    *folder*): the *families*' values written in, measured by *objective*, the joints held to
    the design's continuity (:func:`joint_orders`, each candidate's steps judged by the
    design's scale: :func:`~camfab.motion.continuity.step_tolerances`)."""

    def __init__(self, design: Design, base: dict[str, Any], file: str, folder: Path,
                 families: Sequence[Family], objective: Objective):
        from camfab.motion.continuity import step_tolerances

        self.design = design
        self.tolerances = step_tolerances(design.program)
        orders = joint_orders(design.program, self.tolerances)
        self.base = base
        self.file = file
        self.folder = folder
        self.families = tuple(families)
        self.objective = objective
        self.required = [min(order, 3) for order in orders]
        self.trials: dict[tuple[Written, ...], Trial] = {}
        self.measured = 0
        self.analysed = 0

    def written(self, assignment: Assignment) -> tuple[Written, ...]:
        out: list[Written] = []
        for family, value in zip(self.families, assignment, strict=True):
            if isinstance(family, ChoiceFamily):
                out += family.written(value)
            else:
                assert isinstance(family, ContinuousFamily)
                out += family.written(value)
        return tuple(out)

    def trial(self, assignment: Assignment) -> Trial:
        """The candidate of *assignment*, measured (its objective; checked too when the
        objective needs its analysis)."""
        from camfab.sweep.vary import with_values

        written = self.written(assignment)
        found = self.trials.get(written)
        if found is not None:
            return found
        data = with_values(self.base, [k for k, _ in written], [v for _, v in written])
        trial = Trial(assignment, written, data)
        self.trials[written] = trial
        self.measured += 1
        design = self.design_of(assignment)
        try:
            program = design.program
        except Exception as exc:  # a law the segment's conditions (or a polydyne cam's rules)
            trial.out = " ".join(str(exc).split())  # do not allow: out, not the end
            return trial
        orders = joint_orders(program, self.tolerances)
        worse = [i for i, (got, need) in enumerate(zip(orders, self.required, strict=True))
                 if got < need]
        if worse:
            i = worse[0]
            what = {1: "velocity", 2: "acceleration"}.get(orders[i], "jerk")
            trial.out = (f"the {what} steps at the start of motion[{i}], where the design's "
                         "does not")
            return trial
        if self.objective.needs_analysis:
            self.check(trial)
        else:
            with _quiet():
                trial.objective, trial.tiebreak = self.objective.measure(design)
        return trial

    def standard(self, indices: Sequence[int]) -> tuple[str, Trial] | None:
        """The best standard law put in place of the laws of the segments *indices* (the same
        law in each), among those that keep every joint as continuous as the design's: its
        name and its candidate, measured and checked as any (the candidates tried in the order
        of their objective until one meets every limit); None where none does. What a tuned
        design is compared with."""
        import copy

        from camfab.tune.families import standard_laws

        found = []
        for law in standard_laws():
            data = copy.deepcopy(self.base)
            motion = list(self.design.motion or ())
            for i in indices:
                entry = data["motion"][i]
                key = next(iter(entry))
                entry[key] = {**{k: v for k, v in entry[key].items() if k not in LAW_KEYS},
                              "law": law}
                motion[i] = motion[i].model_copy(update={**dict.fromkeys(LAW_KEYS),
                                                         "law": law})
            trial = Trial((), (), data)
            design = with_motion(self.design, motion)
            try:
                orders = joint_orders(design.program, self.tolerances)
            except Exception:  # a law the design's rules refuse here (a polydyne cam's)
                continue
            if any(got < need for got, need in zip(orders, self.required, strict=True)):
                continue
            if self.objective.needs_analysis:
                self.check(trial)
            else:
                with _quiet():
                    trial.objective, trial.tiebreak = self.objective.measure(design)
            if math.isfinite(trial.objective):
                found.append((law, trial))
        for law, trial in sorted(found, key=lambda pair: pair[1].rank):
            self.check(trial)
            if trial.feasible:
                return law, trial
        return None

    def design_of(self, assignment: Assignment) -> Design:
        """The design with the values of *assignment* (its program built when asked for)."""
        motion = list(self.design.motion or ())
        for family, value in zip(self.families, assignment, strict=True):
            motion[family.index] = motion[family.index].model_copy(
                update=family.updates(value))  # type: ignore[arg-type]
        return with_motion(self.design, motion)

    def check(self, trial: Trial) -> None:
        """Analyse *trial* (once): its status, message, margins and violation (and its
        objective, where that needs the analysis)."""
        from camfab.sweep.rows import checked

        if trial.checked or trial.out is not None:
            return
        self.analysed += 1
        with _quiet():
            trial.status, trial.message, analysis = checked(trial.data, self.file,
                                                            self.folder)
        if analysis is None:
            trial.out = trial.message
            return
        trial.margins = margins(analysis.findings)
        trial.violation = violation(trial.margins)
        with _quiet():  # the objective of the design as the file will hold it
            trial.objective, trial.tiebreak = self.objective.measure_analysis(analysis)


@contextmanager
def _quiet() -> Iterator[None]:
    """numpy's warnings on extreme candidates kept off the terminal: what a candidate does
    wrong is its status."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        yield


def normalised(x: Array) -> Array:
    """*x* clipped into [0, 1] (the optimiser's steps may leave its bounds by a rounding)."""
    import numpy as np

    return np.clip(np.asarray(x, dtype=np.float64), 0.0, 1.0)
