"""The record of one design's analysis: everything computed about it before any file is made,
which the kinds fill in, the writers serialise and the pipeline carries to the files.

The cam at its speed (:mod:`camfab.speed`) lies in the layer above: the record carries its
result and the kind's contact without knowing their types, and the layers that read them
(the writers, the kinds) import those from :mod:`camfab.speed`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from camfab.analysis.findings import Finding, exit_status
from camfab.analysis.kinematics import MotionUnits, SegmentStats
from camfab.design import Design
from camfab.motion.program import MotionProgram

if TYPE_CHECKING:
    from camfab.analysis.dynamics import Dynamics
    from camfab.analysis.setup_sheet import Setup
    from camfab.analysis.verification import Verification
    from camfab.arrays import Array
    from camfab.geometry.disc_geometry import LiftCheck


class CamResult:
    """A kind's part of an analysis: its geometry and key numbers (``numbers``, with the worst
    pressure angle of each segment), and what the writers ask of it. The writers know formats,
    not kinds: every section of the report, column of the motion table, line of the terminal
    summary and figure that differs between kinds comes from here. The defaults serve a cam
    without the feature."""

    numbers: Any
    #: The heading of the report's drawing.
    drawing_title = "The cam turning, the follower on it"
    #: ``camfab inspect`` with another follower runs it over the working curve sampled finer
    #: than the cam's outline (a disc cam's), rather than over the outline as computed.
    refine_for_inspection = False

    def kind_name(self, design: Design) -> str:
        """What the cam is called in a sentence ("disc cam")."""
        return f"{design.cam.type} cam"

    def motion_words(self, design: Design) -> str:
        """How the cam moves: its sense of rotation."""
        return design.cam.rotation

    def report_geometry(self, analysis: Analysis) -> dict[str, Any]:
        """The report's ``geometry`` section (mm, deg)."""
        return {}

    def report_motion(self, analysis: Analysis) -> dict[str, Any]:
        """What the report's ``motion`` section adds for this kind (a shaped cam's key
        points)."""
        return {}

    def dynamics_note(self, analysis: Analysis) -> str | None:
        """Why there are no dynamics, where the kind has its own reason."""
        return None

    def contact(self, analysis: Analysis) -> Any:
        """How the follower touches the cam over the analysis grid (a
        :class:`camfab.speed.contact.Contact`), for the contact stress and the roller's life;
        None for a kind whose contact is not modelled."""
        return None

    def sampled_lift(self) -> LiftCheck | None:
        """The follower run over the sampled outline, before any file is read back."""
        return None

    def table_leading(self, theta: Array) -> list[tuple[str, Array]]:
        """Columns of the motion table after the cam angle (a linear cam's travel)."""
        return []

    def table_columns(self, theta: Array, motion: Array) -> list[tuple[str, Array]]:
        """The motion table's pressure angle and radii of curvature at the cam angles *theta*
        (rad) of the follower *motion* (its s, s′, s″, s‴ rows)."""
        import numpy as np

        return [(name, np.full(theta.size, np.nan)) for name in TABLE_COLUMNS]

    def summary(self, analysis: Analysis) -> list[str]:
        """Lines of the terminal summary on the cam's geometry (rich markup)."""
        return []

    def contact_changes(self, report: dict[str, Any]) -> dict[str, Any] | None:
        """The report page's table of where the load passes between the follower's sides."""
        return None

    def pressure_panels(self, analysis: Analysis, top: Any, bottom: Any) -> None:
        """Draw the pressure angle on *top* and the radii of curvature on *bottom*
        (:class:`camfab.export.chart.Axes`)."""

    def drawing(self, analysis: Analysis) -> str | None:
        """The report's drawing of the cam as inline SVG."""
        return None


def terse(value: float | None, digits: int = 4) -> str:
    """A number for the terminal: *digits* significant digits, ∞ for none or unbounded."""
    import math

    if value is None or not math.isfinite(value):
        return "∞"
    return f"{value:.{digits}g}"


#: The motion table's columns of the cam's geometry.
TABLE_COLUMNS = ("pressure_angle_deg", "pitch_radius_of_curvature_mm",
                 "profile_radius_of_curvature_mm")


@dataclass(frozen=True)
class Analysis:
    """Everything computed about a design, before any file is made: what every cam has, and
    the kind's ``result``. The result's fields read through the analysis as well
    (``analysis.geometry`` is ``analysis.result.geometry``; None for a kind without one)."""

    design: Design
    program: MotionProgram
    units: MotionUnits
    segments: list[SegmentStats]
    findings: list[Finding]
    result: CamResult
    verification: Verification | None = None
    dynamics: Dynamics | None = None
    #: The cam at its speed: the elastic follower train, the contact stress and the roller's
    #: life (a :class:`camfab.speed.model.AtSpeed`; None until :func:`camfab.speed.model.at_speed`
    #: has run).
    at_speed: Any = None
    #: The setup sheets of the machining programs written (:mod:`camfab.machining`), one per
    #: program file; empty when no program was asked for.
    machining: tuple[Setup, ...] = ()

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_") or name == "result":  # (copy and pickle look for these)
            raise AttributeError(name)
        return getattr(self.result, name, None)

    @property
    def exit_code(self) -> int:
        """0 when every error-severity check passed, 1 otherwise."""
        return exit_status(self.findings)
