"""The disc (plate) cam: a plate turning about its centre, its outline the working curve of the
follower's motion (THEORY §B). Its analysis is shared by the plate cams built on it (shaped,
groove, conjugate and constant-breadth)."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from camfab.analysis.findings import Finding
    from camfab.analysis.kinematics import MotionUnits, SegmentStats
    from camfab.analysis.record import Analysis
    from camfab.design import Design
    from camfab.kinds.readback import Verification
    from camfab.motion.program import MotionProgram


def analyse_plate(design: Design, program: MotionProgram, units: MotionUnits,
                  stats: list[SegmentStats], findings: list[Finding]) -> Analysis:
    """A plate cam's exact curves, key numbers and geometric checks (before *findings*)."""
    from camfab.analysis.cam_checks import cam_findings, cam_numbers
    from camfab.analysis.record import Analysis
    from camfab.geometry.disc_geometry import disc_geometry

    geometry = disc_geometry(design)
    numbers = cam_numbers(geometry, len(program.segments))
    findings = [*cam_findings(design, geometry, numbers), *findings]
    return Analysis(design, program, units, stats, findings, geometry, numbers)


def plate_files(analysis: Analysis, requested: tuple[str, ...]) -> tuple[
        Analysis, Verification, dict[str, dict[str, bytes]], dict[str, str]]:
    """A plate's DXF, SVG and STL (``NAME.dxf``, ...), made and read back."""
    from camfab.kinds.readback import named, verify_plate

    check, single, _ = verify_plate(analysis, requested)
    return analysis, check, named(analysis.design.name, single), {}


class Disc:
    """The disc cam (``cam.type: disc``)."""

    drives_both_ways = False
    analyse = staticmethod(analyse_plate)
    files = staticmethod(plate_files)


KIND = Disc()
