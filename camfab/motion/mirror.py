"""Motions that mirror another: the half turn of a constant-breadth cam and the opposite cam of a
conjugate pair (THEORY §F).

A constant-breadth (or constant-diameter) cam holds its follower between two faces (or rollers)
a fixed distance apart on opposite sides, so only half a turn of motion is free:
``s(θ + π) = h − s(θ)``. A conjugate pair's second cam drives its roller the other way:
``s_b(θ) = h − s(θ)``. Both keep each segment's law and negate its lift, so the mirrored motion
is exact, segment by segment (a return's law is not swapped for its time mirror).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from camfab.arrays import Array
from camfab.motion.program import (
    DATA_LAWS,
    MotionProgram,
    ProgramError,
    ProgramSegment,
    SegmentSpec,
    build_program,
)

FLIPPED = {"rise": "return", "return": "rise", "dwell": "dwell"}


def _mirrored(seg: ProgramSegment, top: float, start: float, index: int) -> ProgramSegment:
    """*seg* as ``top − s``, placed at *start* (rad) as segment *index*."""
    return replace(seg, index=index, kind=FLIPPED[seg.kind], start=start, s0=top - seg.s0,
                   delta=-seg.delta)


def opposite(program: MotionProgram) -> MotionProgram:
    """The motion ``h − s(θ)`` (h: the program's largest lift), segment by segment."""
    top = program.max_lift
    return MotionProgram([_mirrored(seg, top, seg.start, seg.index) for seg in program.segments])


def half_turn(specs: Sequence[SegmentSpec]) -> MotionProgram:
    """The whole turn of a constant-breadth cam from the segments of its first half turn: the
    second half is ``h − s(θ − π)``, with h the lift at 180°.

    Raises
    ------
    ProgramError
        The first half does not make a motion (its angles do not sum to 180° once completed, or
        a segment cannot be built).
    """

    class _Mirror:
        """The second half's spec of a first-half segment: the same angle and lift, the kind
        flipped (its law is replaced by the first half's after the build)."""

        def __init__(self, spec: SegmentSpec) -> None:
            self.kind = FLIPPED[spec.kind]
            self.angle = spec.angle
            self.lift = spec.lift
            self.law = spec.law if spec.law not in DATA_LAWS else "cycloidal"
            self.blend = spec.blend
            self.start = self.end = self.points = self.order = self.controls = None

    first = list(specs)
    count = len(first)
    try:
        whole = build_program([*first, *(_Mirror(spec) for spec in first)])
    except ProgramError as exc:  # the completion's trouble is its first half's
        index = None if exc.index is None else exc.index % count
        raise ProgramError(index, exc.field, exc.problem) from None
    top = whole.segments[count].s0 if count < len(whole.segments) else whole.max_lift
    head = whole.segments[:count]
    tail = [_mirrored(seg, top, seg.start + math.pi, count + seg.index) for seg in head]
    return MotionProgram([*head, *tail])


def half_turn_mismatch(program: MotionProgram, step: float = math.radians(0.25)) -> tuple[Array,
                                                                                          Array]:
    """How far *program* is from ``s(θ + π) = h − s(θ)``: the angles θ + π (rad) over the second
    half turn and ``s(θ + π) + s(θ) − h`` there (mm or rad)."""
    count = math.ceil(math.pi / step)
    theta = np.linspace(0.0, math.pi, count + 1)[:-1]
    first = program.evaluate(theta)[0]
    second = program.evaluate(theta + math.pi)[0]
    return theta + math.pi, second + first - program.max_lift
