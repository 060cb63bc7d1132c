"""A face-groove cam's scan model (:class:`~camfab.inspect.models.plate.PlateScan`): the
groove's inner wall (side −1: it pushes the roller away from the cam centre, toward +q) and
outer wall (side +1: it pulls the roller back), each from the groove's floor up to the plate's
face, and a gauge roller of the roller's radius plus half the groove's clearance run over each
(the roller the build sizes both walls with), so that on a groove as designed both runs are the
design's q and the real roller's play is the clearance plus the outer wall's run less the inner
wall's.

Rows, columns and normals as :mod:`camfab.inspect.models.plate` says: row *i* of each wall is
the exact wall the build samples at cam angle θᵢ (the pitch curve moved the gauge roller's
radius inward: the disc cam's working curve, and outward:
:func:`camfab.geometry.disc_geometry.outer_wall`), ``across`` from the groove's floor; the
normals point into the groove.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from camfab.geometry.disc_geometry import outer_wall
from camfab.inspect.models.plate import (
    PlateScan,
    flank_grid,
    motion_of,
    outward,
    plate_scan,
    working,
)
from camfab.inspect.models.plate_run import Rider
from camfab.motion.program import cycle_angles

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.arrays import Array


def scan_model(analysis: Analysis, step: float) -> PlateScan:
    """The scan model of a groove cam (``groove``), rows *step* rad of cam angle apart over the
    turn: "inner wall" (side −1) and "outer wall" (side +1); its ``clearance`` is the groove's
    (mm, or for an oscillating follower that over the arm's length, rad: the play along the
    follower's path is the clearance over the cosine of the pressure angle, which the runs of
    the gauge roller measure from the part)."""
    walls, cam, program = analysis.groove, analysis.geometry.cam, analysis.program
    assert walls is not None
    theta = cycle_angles(step)
    m = program.evaluate(theta)
    floor, face = walls.thickness - walls.depth, walls.thickness
    inner = flank_grid("inner wall", -1, *working(cam, theta, m), floor, face)
    outer = flank_grid("outer wall", 1, outer_wall(cam, theta, m).xy,
                       -outward(cam, theta, m), floor, face)
    fol = cam.follower

    def pressure(q: Array, dq: Array) -> Array:
        return cam.pressure_angle(theta, motion_of(q - cam.rest, dq))

    clearance = walls.clearance / (fol.arm_length if fol.oscillating else 1.0)
    return plate_scan(analysis, theta, [(inner, Rider(cam, -1)), (outer, Rider(cam, 1))],
                      cam.rest + m[0], pressure, clearance)
