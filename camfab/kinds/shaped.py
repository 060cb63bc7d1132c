"""Shaped cams, whose shape defines the motion: the circular-arc cam and the tangent cam (flanks
and nose of given radii, THEORY §D). Built as a plate cam, with the key points of the shape."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

from camfab.analysis.record import terse
from camfab.kinds.disc import (
    PlateResult,
    analyse_plate,
    disc_scene,
    no_checks,
    plate_part,
    plate_verify,
)

if TYPE_CHECKING:
    from camfab.analysis.findings import Finding
    from camfab.analysis.kinematics import MotionUnits, SegmentStats
    from camfab.analysis.record import Analysis
    from camfab.analysis.shape_numbers import ShapeNumbers
    from camfab.design import Design
    from camfab.export.part import Part
    from camfab.geometry.plate import Plate
    from camfab.motion.program import MotionProgram


@dataclass(frozen=True)
class ShapedResult(PlateResult):
    """A plate cam's result with its shape's numbers (radii, centres, key points)."""

    shape: ShapeNumbers
    refine_for_inspection = False

    def report_geometry(self, analysis: Analysis) -> dict[str, Any]:
        shape = self.shape
        return {**super().report_geometry(analysis),
                "flank_radius_mm": shape.flank_radius,
                "flank_centre_distance_mm": shape.flank_centre_distance,
                "nose_radius_mm": shape.nose_radius,
                "nose_centre_distance_mm": shape.nose_centre_distance,
                "lift_angle_deg": math.degrees(shape.lift_angle),
                "top_dwell_deg": math.degrees(shape.top_dwell),
                "flank_end_angle_deg": math.degrees(shape.flank_end_angle)}

    def report_motion(self, analysis: Analysis) -> dict[str, Any]:
        """The follower's motion at the start of lift, the end of the flank, the start of the
        nose and the apex: per radian, and in SI at the design speed."""
        units, omega = analysis.units, analysis.design.cam.omega
        rows = []
        for point in self.shape.points:
            row: dict[str, Any] = {"point": point.name,
                                   "cam_angle_deg": math.degrees(point.angle),
                                   units.displacement_column: units.lift_value(point.motion[0])}
            for order in (1, 2):
                key = units.per_rad_key(order).removeprefix("max_")
                row[key] = float(point.motion[order])
                if omega is not None:
                    row[units.key(order)] = units.to_si(order, float(point.motion[order]), omega)
            rows.append(row)
        return {"key_points": rows}

    def summary(self, analysis: Analysis) -> list[str]:
        shape = self.shape
        flank = ("straight flanks" if shape.flank_radius is None else
                 f"flank radius {terse(shape.flank_radius)} mm")
        return [*super().summary(analysis),
                f"shape: {flank}, nose radius {terse(shape.nose_radius)} mm, nose centre "
                f"{terse(shape.nose_centre_distance)} mm from the cam centre; contact passes from "
                f"flank to nose at {terse(math.degrees(shape.flank_end_angle))}°"]


class Shaped:
    """The circular-arc and tangent cams (``cam.type: circular-arc``, ``tangent``)."""

    drives_both_ways = False
    mounted = "plate"
    check = staticmethod(no_checks)
    inspect_refusal = None
    verify = staticmethod(plate_verify)
    scene = staticmethod(disc_scene)

    @staticmethod
    def analyse(design: Design, program: MotionProgram, units: MotionUnits,
                stats: list[SegmentStats], findings: list[Finding]) -> Analysis:
        """A plate cam's analysis with the shape's numbers (radii, centres, key points)."""
        from camfab.analysis.shape_numbers import shape_numbers

        exact = design.shape.profile(design.cam.sigma)
        analysis = analyse_plate(design, program, units, stats, findings, exact=exact)
        plate = analysis.result
        assert isinstance(plate, PlateResult)
        return replace(analysis, result=ShapedResult(plate.geometry, plate.numbers,
                                                     shape_numbers(design, program)))


    @staticmethod
    def part(analysis: Analysis) -> Part:
        """A plate cam's part, its note giving the exact outline's flank and nose."""
        design = analysis.design
        scale, unit = 1.0 / design.mm_per_unit, design.units
        shape = design.shape
        flank = ("straight flanks" if shape.flank_radius is None else
                 f"flank radius {shape.flank_radius * scale:.6g} {unit}")

        def note(plate: Plate) -> str:
            return (f"exact outline of {len(plate.outline.vertices)} lines and arcs: {flank}, "
                    f"nose radius {shape.nose_radius * scale:.6g} {unit}")

        return plate_part(analysis, outline_note=note)


KIND = Shaped()
