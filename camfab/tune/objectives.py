"""What ``camfab tune`` minimises.

- ``residual`` — the largest residual vibration over the speeds of a band (mm, peak to peak at
  the trace point): at each speed, the largest peak-to-peak swing of the elastic follower
  train's dynamic error over a dwell, as the at-speed analysis reports it at the design speed
  (:attr:`camfab.speed.vibration.Vibration.residual_m`: the mass's swing over the dwell,
  :func:`~camfab.speed.vibration.dwell_swings`). It is computed straight from the
  train's exact periodic response (:func:`camfab.speed.elastic.periodic_error`, every
  speed of the band in one call, on the analysis grid) rather than a whole analysis per speed.
- ``acceleration``, ``jerk`` — the peak |s″| or |s‴| over the segments tuned (by default every
  rise and return: the cycle's peak), per radian² or radian³ of cam angle (mm, or rad of an
  arm's swing): the motion program's own peaks, inside the segments (a step at a joint is the
  continuity check's, which the search keeps as it was). Over the segments tuned, not the
  whole cycle: a segment left as it is would otherwise hide what tuning the others gains.

Each objective is measured with a tie-break (:meth:`Objective.measure`): the sum of the parts whose
largest is the objective (each tuned segment's peak; the residual at each speed), so that a
change that lowers one part without lowering the largest counts as a gain — the search changes
one segment's law at a time, and with two segments at the same peak neither alone lowers it.
- ``stress`` — the largest Hertz contact stress over the cycle at the design speed (MPa).
- ``torque`` — the largest camshaft torque at the design speed (N·m): camfab's rigid dynamics,
  T = F·ds/dθ with F the contact force along the follower's motion (spring, preload, loads and
  inertia), without friction.

The first three come from the motion program alone (cheap); the last two need the candidate's
analysis.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from camfab.arrays import Array
from camfab.design import Design

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis

#: The objectives by name, in the order the help lists them.
NAMES = ("residual", "acceleration", "jerk", "stress", "torque")
#: The most speeds one evaluation of the residual takes at once (their responses' arrays are
#: held together: some 0.1 MB a speed on the analysis grid).
SPEED_CHUNK = 32


class Objective(ABC):
    """One objective: its *name*, its *unit*, a phrase for it, and whether it needs the
    candidate's whole analysis (:attr:`needs_analysis`)."""

    name: str = ""
    unit: str = ""
    needs_analysis: bool = False

    @abstractmethod
    def words(self) -> str:
        """The objective in words: ``the largest residual vibration over 1350–1650 rpm``."""

    def why_not(self, design: Design, analysis: Analysis) -> str | None:
        """Why *design* (with its *analysis*) has no value of this objective, or None."""
        return None

    def measure(self, design: Design) -> tuple[float, float]:
        """The objective of *design* from its motion program (not :attr:`needs_analysis`),
        and its tie-break: which of two candidates of the same objective is better (less; 0
        where nothing tells them apart)."""
        raise NotImplementedError

    def measure_analysis(self, analysis: Analysis) -> tuple[float, float]:
        """The objective of a candidate and its tie-break from its *analysis*."""
        return self.measure(analysis.design)


def _nan_as_inf(value: float | None) -> float:
    return math.inf if value is None or not math.isfinite(value) else float(value)


class Residual(Objective):
    """The largest residual vibration in a dwell over the speeds *speeds_rpm* (mm)."""

    name, unit = "residual", "mm"

    def __init__(self, speeds_rpm: Array) -> None:
        self.speeds_rpm = np.asarray(speeds_rpm, dtype=np.float64)

    def words(self) -> str:
        speeds = self.speeds_rpm
        if speeds.size == 1:
            return f"the residual vibration at {speeds[0]:.6g} rpm"
        return (f"the largest residual vibration over {speeds[0]:.6g}–{speeds[-1]:.6g} rpm "
                f"({speeds.size} speeds)")

    def why_not(self, design: Design, analysis: Analysis) -> str | None:
        return residual_missing(design, analysis)

    def measure(self, design: Design) -> tuple[float, float]:
        found = residuals(design, self.speeds_rpm)
        return _nan_as_inf(float(np.max(found))), _nan_as_inf(float(np.sum(found)))


def residual_missing(design: Design, analysis: Analysis) -> str | None:
    """Why *design* has no residual vibration to tune, or None: it needs the follower train's
    stiffness (with a mass, a speed and what holds the follower) and a dwell."""
    from camfab.speed.model import force_note

    note = force_note(design, design.spring is not None, design.cam.spec.two_sided)
    if note is not None:
        return f"the residual vibration needs the forces: {note}"
    if design.follower.stiffness is None:
        return ("the residual vibration needs the follower train's stiffness: give "
                "follower.stiffness (N/mm)")
    if not any(seg.kind == "dwell" for seg in design.program.segments):
        return "the residual vibration is the ringing left in a dwell, and the motion has none"
    speed = analysis.at_speed
    if speed is None or speed.vibration is None:
        return "the follower train's vibration is not computed for this design"
    return None


def residuals(design: Design, speeds_rpm: Array) -> Array:
    """The residual vibration (mm, the largest peak-to-peak swing of the mass over a dwell)
    of *design*'s elastic follower train at each of *speeds_rpm*: the periodic response on the
    analysis grid, every speed at once."""
    from camfab.analysis.dynamics import STEP, trace_scale
    from camfab.design.train import train_of
    from camfab.speed.elastic import periodic_error, rigid_force
    from camfab.speed.vibration import dwell_swings

    train = train_of(design, design.spring is not None)
    assert train is not None
    program = design.program
    segment, theta, motion = program.segment_grid(STEP)
    motion = motion * trace_scale(design)
    speeds = np.asarray(speeds_rpm, dtype=np.float64)
    out = np.empty(speeds.size)
    for first in range(0, speeds.size, SPEED_CHUNK):
        omega = speeds[first:first + SPEED_CHUNK] * (math.pi / 30.0)
        with np.errstate(all="ignore"):
            force, rate = rigid_force(train, omega[:, None], motion[:, None, :])
            error = periodic_error(train, omega, theta, force, rate)
        swings = [swing for _, swing in dwell_swings(program, segment, motion[0], error)]
        out[first:first + SPEED_CHUNK] = 1000.0 * np.max(swings, axis=0)
    return out


class Peak(Objective):
    """The peak |s″| (*order* 2) or |s‴| (3) over the segments *indices*, per radianⁿ of cam
    angle."""

    def __init__(self, order: int, oscillating: bool, indices: Sequence[int]) -> None:
        self.order = order
        self.indices = tuple(indices)
        self.name = "acceleration" if order == 2 else "jerk"
        lift = "rad" if oscillating else "mm"
        self.unit = f"{lift}/rad{'²' if order == 2 else '³'}"

    def words(self) -> str:
        where = ", ".join(f"motion[{i}]" for i in self.indices)
        return f"the peak {self.name} |s{'″' if self.order == 2 else '‴'}| over {where}"

    def peaks(self, design: Design) -> list[float]:
        """The peak of each segment tuned."""
        segments = design.program.segments
        return [segments[i].peak(self.order) for i in self.indices]

    def measure(self, design: Design) -> tuple[float, float]:
        found = self.peaks(design)
        return _nan_as_inf(max(found)), _nan_as_inf(sum(found))


class Stress(Objective):
    """The largest contact stress over the cycle at the design speed (MPa)."""

    name, unit, needs_analysis = "stress", "MPa", True

    def words(self) -> str:
        return "the peak contact stress at the design speed"

    def why_not(self, design: Design, analysis: Analysis) -> str | None:
        speed = analysis.at_speed
        if speed is None or speed.stress is None:
            note = None if speed is None else speed.stress_note
            return f"the contact stress is not computed: {note or 'no speed'}"
        return None

    def measure_analysis(self, analysis: Analysis) -> tuple[float, float]:
        speed = analysis.at_speed
        return _nan_as_inf(None if speed is None or speed.stress is None
                           else speed.stress.max_MPa), 0.0


class Torque(Objective):
    """The largest camshaft torque at the design speed (N·m; rigid dynamics, no friction)."""

    name, unit, needs_analysis = "torque", "N·m", True

    def words(self) -> str:
        return "the peak camshaft torque at the design speed"

    def why_not(self, design: Design, analysis: Analysis) -> str | None:
        dyn = analysis.dynamics
        if dyn is None or dyn.max_torque_N_m is None:
            return ("the camshaft torque needs the follower's mass, the cam's speed and a "
                    "spring (follower.mass, cam.speed_rpm, spring)")
        return None

    def measure_analysis(self, analysis: Analysis) -> tuple[float, float]:
        dyn = analysis.dynamics
        return _nan_as_inf(None if dyn is None else dyn.max_torque_N_m), 0.0


def objective_of(name: str, design: Design, speeds_rpm: Array,
                 indices: Sequence[int]) -> Objective:
    """The objective called *name* for *design*, the residual's over *speeds_rpm*, the
    peaks' over the segments *indices*."""
    if name == "residual":
        return Residual(speeds_rpm)
    if name in ("acceleration", "jerk"):
        return Peak(2 if name == "acceleration" else 3, design.follower.oscillating, indices)
    return Stress() if name == "stress" else Torque()


def default_objective(design: Design) -> str:
    """``residual`` where the design has an elastic follower train (a stiffness), else
    ``acceleration``."""
    return "residual" if design.follower.stiffness is not None else "acceleration"
