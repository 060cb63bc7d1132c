"""A conjugate pair's scan model (:class:`~camfab.inspect.models.plate.PlateScan`): one flank
per plate, each touched by its own roller of the one follower.

The frame is that of the pair's one STL file (``NAME.stl``): plate a from z = 0 to the
thickness t in the frame cam a is computed in, plate b on it from z = t to 2t, turned half a
turn (a translating follower) or mirrored in the line of centres (an oscillating one) from the
frame cam b is computed in, as the build stacks them. The scan of the pair is one scan of that
part (or of both plates mounted so), and ``reference_mesh`` is that solid.

"plate a" (side −1) pushes roller a, and with it the follower, toward +q; "plate b" (side +1)
pushes roller b toward its own +y_b (or +Ψ_b), which moves the follower toward −q: q = spacing
− y_b, the spacing the rollers' distance (mm) or the arms' angle (rad). On a pair as designed
both runs are the design's q: the pair's play (``clearance`` 0) is plate b's run less plate
a's, positive where the follower is free (it rattles), negative where the plates jam it, as the
build's hold check measures it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from camfab.geometry.conjugate import half_turned, mirrored
from camfab.inspect.models.plate import (
    PlateScan,
    flank_grid,
    motion_of,
    plate_scan,
    plate_thickness,
    working,
)
from camfab.inspect.models.plate_run import Rider
from camfab.motion.program import cycle_angles

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.arrays import Array


def scan_model(analysis: Analysis, step: float) -> PlateScan:
    """The scan model of a conjugate pair (``conjugate``), rows *step* rad of cam angle apart
    over the turn: "plate a" (side −1) and "plate b" (side +1); its pressure angle at each
    row is the larger of the two rollers' (signed, each in its cam's frame)."""
    partner, cam_a, program = analysis.partner, analysis.geometry.cam, analysis.program
    assert partner is not None and partner.geometry is not None and partner.program is not None, \
        "a conjugate pair has cam b"
    cam_b, spacing = partner.geometry.cam, partner.spacing
    thickness = plate_thickness(analysis)
    theta = cycle_angles(step)
    m_a, m_b = program.evaluate(theta), partner.program.evaluate(theta)
    move = mirrored if partner.mirror else half_turned
    plate_a = flank_grid("plate a", -1, *working(cam_a, theta, m_a), 0.0, thickness)
    xy_b, normal_b = working(cam_b, theta, m_b)
    plate_b = flank_grid("plate b", 1, move(xy_b), move(normal_b), thickness, 2.0 * thickness)

    def pressure(q: Array, dq: Array) -> Array:
        phi_a = cam_a.pressure_angle(theta, motion_of(q - cam_a.rest, dq))
        phi_b = cam_b.pressure_angle(theta, motion_of(spacing - q - cam_b.rest, -dq))
        return np.where(np.abs(phi_b) > np.abs(phi_a), phi_b, phi_a)

    return plate_scan(analysis, theta,
                      [(plate_a, Rider(cam_a, -1)),
                       (plate_b, Rider(cam_b, -1, spacing, partner.mirror))],
                      cam_a.rest + m_a[0], pressure)
