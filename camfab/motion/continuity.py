"""Continuity of a motion program at its joints: where velocity, acceleration or jerk step."""

from __future__ import annotations

import math
from dataclasses import dataclass

from camfab.motion.program import MotionProgram

ORDER_NAMES = {1: "velocity", 2: "acceleration", 3: "jerk"}

#: A derivative steps at a joint when the two sides differ by more than this fraction of the
#: program's largest value of that derivative. Matched polynomials and closed-form laws agree to
#: ~1e-12 relative; a real step is a sizeable fraction of the peak.
RELATIVE_STEP = 1e-7


@dataclass(frozen=True)
class Step:
    """A jump of derivative *order* at cam angle *angle* (rad) from *left* to *right*."""

    angle: float
    order: int
    left: float
    right: float
    before: int  # segment index ending at the joint
    after: int  # segment index starting at the joint

    @property
    def size(self) -> float:
        return abs(self.right - self.left)


def step_tolerances(program: MotionProgram) -> dict[int, float]:
    """How much each derivative (order 1, 2, 3) may differ across a joint of *program* and
    still count as continuous: :data:`RELATIVE_STEP` of its largest value in the program."""
    joints = program.joints()
    tolerances = {}
    for order in (1, 2, 3):
        finite = [p for p in (seg.peak(order) for seg in program.segments) if math.isfinite(p)]
        sides = [abs(v) for j in joints for v in (j.left[order], j.right[order])]
        tolerances[order] = max(RELATIVE_STEP * max([*finite, *sides, 0.0]), 1e-12)
    return tolerances


def joint_steps(program: MotionProgram,
                tolerances: dict[int, float] | None = None) -> list[Step]:
    """The lowest-order step (velocity, acceleration or jerk) at each joint that has one.

    Where a derivative steps, every higher one is unbounded at that joint, so only the lowest
    stepping order is recorded there. *tolerances*: :func:`step_tolerances` (of *program*, or
    of another program to judge this one by its scale: the variants of one design).
    """
    joints = program.joints()
    if tolerances is None:
        tolerances = step_tolerances(program)
    steps = []
    for joint in joints:
        for order in (1, 2, 3):
            left, right = float(joint.left[order]), float(joint.right[order])
            if abs(right - left) > tolerances[order]:
                steps.append(Step(joint.angle, order, left, right, joint.before, joint.after))
                break
    return sorted(steps, key=lambda s: (s.order, s.angle))


def unbounded_orders(program: MotionProgram, steps: list[Step]) -> list[set[int]]:
    """For each segment, the derivative orders that are unbounded (infinite) in or at it.

    A step of order m at a joint makes every order above m infinite there, for both segments that
    meet at the joint; a law with an inner step (uniform acceleration) does the same inside.
    """
    out: list[set[int]] = [set() for _ in program.segments]
    for i, seg in enumerate(program.segments):
        if seg.delta != 0.0 and seg.law.inner_step_order is not None:
            out[i].update(range(seg.law.inner_step_order + 1, 4))
    for step in steps:
        for i in (step.before, step.after):
            out[i].update(range(step.order + 1, 4))
    return out
