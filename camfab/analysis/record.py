"""The record of one design's analysis: everything computed about it before any file is made,
which the kinds fill in, the writers serialise and the pipeline carries to the files."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from camfab.analysis.findings import Finding, exit_status
from camfab.analysis.kinematics import MotionUnits, SegmentStats
from camfab.design import Design
from camfab.motion.program import MotionProgram

if TYPE_CHECKING:
    from camfab.analysis.cam_checks import CamNumbers
    from camfab.analysis.drum_checks import DrumNumbers
    from camfab.analysis.dynamics import Dynamics
    from camfab.analysis.linear_checks import LinearNumbers
    from camfab.analysis.shape_numbers import ShapeNumbers
    from camfab.geometry.conjugate import Partner
    from camfab.geometry.disc_geometry import DiscGeometry
    from camfab.geometry.drum import DrumDense
    from camfab.geometry.groove import GrooveWalls
    from camfab.geometry.linear import LinearGeometry
    from camfab.kinds.readback import Verification

@dataclass(frozen=True)
class Analysis:
    """Everything computed about a design, before any file is made."""

    design: Design
    program: MotionProgram
    units: MotionUnits
    segments: list[SegmentStats]
    findings: list[Finding]
    geometry: DiscGeometry | None = None
    numbers: CamNumbers | DrumNumbers | LinearNumbers | None = None
    verification: Verification | None = None
    drum: DrumDense | None = None
    dynamics: Dynamics | None = None
    shape: ShapeNumbers | None = None
    linear: LinearGeometry | None = None
    groove: GrooveWalls | None = None
    partner: Partner | None = None

    @property
    def exit_code(self) -> int:
        """0 when every error-severity check passed, 1 otherwise."""
        return exit_status(self.findings)
