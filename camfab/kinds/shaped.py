"""Shaped cams, whose shape defines the motion: the circular-arc cam and the tangent cam (flanks
and nose of given radii, THEORY §E). Built as a plate cam, with the key points of the shape."""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

from camfab.kinds.disc import analyse_plate, plate_files

if TYPE_CHECKING:
    from camfab.analysis.findings import Finding
    from camfab.analysis.kinematics import MotionUnits, SegmentStats
    from camfab.analysis.record import Analysis
    from camfab.design import Design
    from camfab.motion.program import MotionProgram


class Shaped:
    """The circular-arc and tangent cams (``cam.type: circular-arc``, ``tangent``)."""

    drives_both_ways = False
    files = staticmethod(plate_files)

    @staticmethod
    def analyse(design: Design, program: MotionProgram, units: MotionUnits,
                stats: list[SegmentStats], findings: list[Finding]) -> Analysis:
        """A plate cam's analysis with the shape's numbers (radii, centres, key points)."""
        from camfab.analysis.shape_numbers import shape_numbers

        analysis = analyse_plate(design, program, units, stats, findings)
        return replace(analysis, shape=shape_numbers(design, program))


KIND = Shaped()
