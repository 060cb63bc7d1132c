"""The design file's ``machining:`` section: the tool, the feeds and the program's form for the
machining programs camfab writes (``outputs: [gcode]``, :mod:`camfab.machining`).

Lengths are millimetres and feeds millimetres per minute here (a bare number in the design's
``units``, or a string with a unit); ``spindle_rpm`` is rpm. Every key but ``tool_diameter`` and
``feed`` has a default a shop would start from, stated on its field.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated, Any, Literal

from pydantic import Field, ValidationInfo, field_validator, model_validator

from camfab.design import units as U
from camfab.design.fields import (
    Frozen,
    Length,
    NonNegativeLength,
    PositiveLength,
    as_kind,
    problem,
)

if TYPE_CHECKING:
    from camfab.design.model import Design
    from camfab.motion.program import MotionProgram

PositiveFeed = Annotated[float, as_kind(U.FEED), Field(gt=0)]
PositiveSpeed = Annotated[float, as_kind(U.SPEED), Field(gt=0)]

#: The spindle speed (rpm) when the section gives none: a 6 mm carbide end mill in aluminium.
DEFAULT_SPINDLE_RPM = 10000.0
#: The material left by the roughing passes for the finishing pass (mm) when none is given.
DEFAULT_FINISH_ALLOWANCE_MM = 0.2
#: The height (mm above the work's top) of rapid moves when none is given.
DEFAULT_SAFE_Z_MM = 5.0
#: The plunge feed, as a fraction of ``feed``, when none is given.
DEFAULT_PLUNGE_FRACTION = 1 / 3


class GloboidMachine(Frozen):
    """Where a table-table machine's B axis stands (mm), for a globoidal cam's program
    (:mod:`camfab.machining.globoid`): the cam on the rotary A axis (about X), which the B axis
    (about Y) tilts. Measured from the work zero, the cam's axis at its middle plane, with A
    and B at 0: ``b_axis_x`` along X (the cam's axis), ``b_axis_z`` up. X and Z make up for
    B's axis not passing through the follower's pivot."""

    b_axis_x: Length = 0.0
    b_axis_z: Length = 0.0


class Machining(Frozen):
    """The tool and how to cut (mm, mm/min, rpm).

    ``cut_length`` defaults to three tool diameters and ``step_down`` to half a tool diameter
    (at most the length of cut); ``plunge_feed`` to a third of ``feed``; ``compensation`` to
    ``control``, or ``path`` for ``dialect: grbl`` (Grbl has no cutter compensation)."""

    tool_diameter: PositiveLength
    flutes: Annotated[int, Field(ge=1, le=16)] = 2
    cut_length: PositiveLength | None = None
    spindle_rpm: PositiveSpeed = DEFAULT_SPINDLE_RPM
    feed: PositiveFeed
    plunge_feed: PositiveFeed | None = None
    step_down: PositiveLength | None = None
    finish_allowance: NonNegativeLength = DEFAULT_FINISH_ALLOWANCE_MM
    safe_z: PositiveLength = DEFAULT_SAFE_Z_MM
    direction: Literal["climb", "conventional"] = "climb"
    compensation: Literal["control", "path"] = "control"
    dialect: Literal["linuxcnc", "grbl"] = "linuxcnc"
    #: A globoidal cam's machine: where its B axis stands.
    machine: GloboidMachine = GloboidMachine()
    #: A grinding wheel's diameter: given, a plate cam that turns also gets its grinding
    #: table and C/X program (:mod:`camfab.machining.grinding`). After ``dialect``, which it
    #: is checked against.
    wheel_diameter: PositiveLength | None = None

    @model_validator(mode="before")
    @classmethod
    def _grbl_path(cls, data: Any) -> Any:
        """Without a ``compensation``, a Grbl program carries the tool centre's path."""
        if isinstance(data, dict) and "compensation" not in data and data.get("dialect") == "grbl":
            return {**data, "compensation": "path"}
        return data

    def check(self, design: Design, program: MotionProgram,
              sizing: frozenset[str] = frozenset()) -> None:
        """The design file's rules of these settings for *design*'s cam
        (:func:`camfab.design.machining_rules.check_machining`)."""
        from camfab.design.machining_rules import check_machining

        check_machining(design, self, program, sizing)

    @field_validator("wheel_diameter")
    @classmethod
    def _wheel_needs_c(cls, value: float | None, info: ValidationInfo) -> float | None:
        """A grinding program turns the cam on a C axis, which Grbl does not have."""
        if value is not None and info.data.get("dialect") == "grbl":
            raise problem("a grinding program turns the cam on a C axis, which Grbl does not have",
                          hint="give dialect: linuxcnc for the grinding program")
        return value

    @property
    def wheel_radius(self) -> float | None:
        """Half the grinding wheel's diameter (mm), None without a wheel."""
        return None if self.wheel_diameter is None else self.wheel_diameter / 2

    @property
    def tool_radius(self) -> float:
        """Half the tool's diameter (mm)."""
        return self.tool_diameter / 2

    @property
    def length_of_cut(self) -> float:
        """``cut_length``, or three tool diameters (mm)."""
        return self.cut_length if self.cut_length is not None else 3 * self.tool_diameter

    @property
    def depth_step(self) -> float:
        """``step_down``, or half a tool diameter, at most the length of cut (mm)."""
        if self.step_down is not None:
            return self.step_down
        return min(self.tool_diameter / 2, self.length_of_cut)

    @property
    def plunge(self) -> float:
        """``plunge_feed``, or a third of ``feed`` (mm/min)."""
        return self.plunge_feed if self.plunge_feed is not None else (
            self.feed * DEFAULT_PLUNGE_FRACTION)
