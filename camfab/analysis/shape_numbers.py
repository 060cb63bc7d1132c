"""The numbers of a cam drawn from its shape (circular-arc, tangent): its derived dimensions and
the follower's motion at the points the textbooks tabulate — the start of the lift, the end of
the flank, the start of the nose and the apex (THEORY §D).

Where contact passes from flank to nose the acceleration steps (the radius of the cam changes),
so the end of the flank and the start of the nose are the same cam angle seen from either side.
Lengths in mm, angles in radians; motion per radian of cam angle (see
:class:`~camfab.analysis.kinematics.MotionUnits` for SI at speed).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from camfab.arrays import Array
from camfab.design import Design
from camfab.motion.program import MotionProgram


@dataclass(frozen=True)
class KeyPoint:
    """The follower at cam angle *angle* (rad): s, s′, s″, s‴ (mm, per radian)."""

    name: str
    angle: float
    motion: Array


@dataclass(frozen=True)
class ShapeNumbers:
    """Derived dimensions (mm, rad) and the key points of the rise.

    ``flank_end_angle`` is where contact passes from the flank to the nose for this follower
    (0 when it meets the nose at once: a flat face on a tangent cam's straight flank).
    """

    flank_radius: float | None
    flank_centre_distance: float | None
    nose_radius: float
    nose_centre_distance: float
    lift_angle: float
    top_dwell: float
    flank_end_angle: float
    points: tuple[KeyPoint, ...]


#: Motion values smaller than this (mm per radianⁿ) are rounding at a point where the value is 0
#: in theory (the velocity at the start of lift and at the apex).
ZERO = 1e-9


def _cleaned(motion: Array) -> Array:
    values = np.asarray(motion, dtype=np.float64)
    return np.where(np.abs(values) < ZERO, 0.0, values)


def shape_numbers(design: Design, program: MotionProgram) -> ShapeNumbers:
    """The dimensions of *design*'s shape and its follower's motion at the key points."""
    shape = design.shape
    rise = [seg for seg in program.segments if seg.kind == "rise"]
    flank = next((seg for seg in rise if seg.law_name == "flank"), None)
    nose = next((seg for seg in rise if seg.law_name == "nose"), None)
    points = [] if not rise else [KeyPoint("start of lift", 0.0, rise[0].end_values()[0])]
    if flank is not None:
        points.append(KeyPoint("end of flank", flank.end, flank.end_values()[1]))
    if nose is not None:
        points += [KeyPoint("start of nose", nose.start, nose.end_values()[0]),
                   KeyPoint("apex", nose.end, nose.end_values()[1])]
    return ShapeNumbers(
        flank_radius=shape.flank_radius,
        flank_centre_distance=shape.flank_centre_distance,
        nose_radius=shape.nose_radius,
        nose_centre_distance=shape.nose_distance,
        lift_angle=shape.lift_angle,
        top_dwell=shape.top_dwell,
        flank_end_angle=0.0 if flank is None else flank.end,
        points=tuple(KeyPoint(p.name, p.angle, _cleaned(p.motion)) for p in points),
    )
