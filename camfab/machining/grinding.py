"""Cam grinding and C-axis turning: the wheel centre's radius X against the cam angle C, as a
table (``NAME-grind.csv``) and as a C/X program (``NAME-grind.ngc``) for a machine that turns
the cam on a C axis and moves a grinding wheel (or a turning tool) on X along a line through
the cam's axis (:mod:`camfab.machining.grind_table` computes the table from the exact profile).

Which plates are ground: every plate cam that turns on its axis with its profile outside —
a disc cam (any follower), a circular-arc or tangent cam, a constant-breadth (constant-diameter)
cam, and both plates of a conjugate pair (``NAME-a-grind``, ``NAME-b-grind``). A groove cam is
not: its walls face each other inside the groove, out of reach of a wheel coming from outside,
and its outer edge is a plain circle. A linear cam slides; it does not turn.

The program: X is the wheel centre's distance from the cam's axis — a radius; the program sets
G8 (radius mode), never diameter mode. C is the cam angle in degrees, growing as the cam turns
in its design's rotation; row 0 of the table is C = 0 with the plate's +Y, as drawn in its DXF,
on the wheel's line. The C–X moves use inverse-time feed (G93): each move's F is the feed asked
over the distance the wheel's contact travels on the cam's surface, so the surface passes the
wheel at ``feed``. One turn grinds with ``finish_allowance`` left, a second to size.
"""

from __future__ import annotations

import math
import textwrap
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from camfab import __version__
from camfab.machining import Machined
from camfab.machining.grind_table import (
    GrindTable,
    WheelCannot,
    WheelPath,
    grind_table,
    unreachable,
)

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.analysis.setup_sheet import Operation, Setup
    from camfab.arrays import Array
    from camfab.design.machining import Machining
    from camfab.geometry.disc_geometry import DiscGeometry
    from camfab.machining.rs274 import Program
    from camfab.motion.program import MotionProgram

#: The fastest a grinding wheel's rim is run (m/s) when ``spindle_rpm`` asks for more: 35 m/s
#: is the highest working speed of the common vitrified wheel (EN 12413, ANSI B7.1); a wheel
#: rated faster says so on its label, and a wheel spun past its rating can burst.
WHEEL_RIM_SPEED_M_S = 35.0

#: The longest comment line of the program (characters): LinuxCNC reads lines of at most 255.
COMMENT_WIDTH = 78

#: Why a cam of each kind that gets no grinding table gets none.
GROOVE_REFUSAL = ("a groove cam is not ground: its walls face each other inside the groove, "
                  "out of reach of a wheel coming from outside, and its outer edge is a plain "
                  "circle")
SLIDING_REFUSAL = "a linear cam slides; it does not turn on a C axis"
OTHER_REFUSAL = "grinding tables are made for plate cams that turn"
GRBL_REFUSAL = "a grinding program turns the cam on a C axis, which Grbl does not have"


@dataclass(frozen=True)
class GrindPlate:
    """One plate to grind: its file stem, its geometry (with the exact evaluators of its cam)
    and motion, where it is undercut (cam angles, deg), and *start*, the cam angle (rad, in the
    frame the cam is computed in) that is C = 0 of the plate as made (half a turn for a
    conjugate pair's cam b, made turned or mirrored)."""

    stem: str
    geometry: DiscGeometry
    program: MotionProgram
    undercut: tuple[tuple[float, float], ...]
    start: float = 0.0


def grind_plates(analysis: Analysis) -> tuple[GrindPlate, ...] | str:
    """The plates of *analysis* a wheel grinds, or why it grinds none."""
    from camfab.geometry.disc_geometry import DiscGeometry

    design, geom = analysis.design, analysis.geometry
    if design.cam.spec.span == "travel":
        return SLIDING_REFUSAL
    if analysis.groove is not None:
        return GROOVE_REFUSAL
    if not isinstance(geom, DiscGeometry):
        return OTHER_REFUSAL
    name = design.name
    partner = analysis.partner
    if partner is None or partner.geometry is None:
        return (GrindPlate(name, geom, analysis.program, analysis.numbers.undercut_ranges),)
    assert partner.program is not None and partner.numbers is not None
    return (GrindPlate(f"{name}-a", geom, analysis.program, analysis.numbers.undercut_ranges),
            GrindPlate(f"{name}-b", partner.geometry, partner.program,
                       partner.numbers.undercut_ranges, math.pi))


def plate_table(plate: GrindPlate, radius: float, tolerance: float) -> GrindTable:
    """The grinding table of *plate* for a wheel of *radius* (mm) within *tolerance* (mm).

    Raises
    ------
    WheelCannot
        The wheel cannot grind the plate's profile (where, in cam angles).
    """
    from camfab.analysis.cam_checks import where

    geom = plate.geometry
    if geom.undercut:
        raise WheelCannot(f"the cam is undercut at cam angles {where(plate.undercut)}: its "
                          "outline as cut is not the design's profile", plate.undercut)
    unreachable(geom.cam, geom.dense, geom.folds, radius)
    return grind_table(WheelPath(geom.cam, plate.program, radius), tolerance, plate.start)


def grind_files(analysis: Analysis, settings: Machining) -> Machined:
    """The grinding table and C/X program of each plate of *analysis* that turns, for the
    wheel of *settings* (``wheel_diameter``; nothing without one), or why there are none."""
    radius = settings.wheel_radius
    if radius is None:
        return Machined()
    if settings.dialect == "grbl":  # the design file's model refuses it; settings merged too
        return Machined(withheld=GRBL_REFUSAL)
    plates = grind_plates(analysis)
    if isinstance(plates, str):
        return Machined(withheld=plates)
    tolerance = analysis.design.manufacturing.tolerance
    tables = []
    for plate in plates:
        try:
            tables.append(plate_table(plate, radius, tolerance))
        except WheelCannot as refused:
            cam = f"cam {plate.stem[-1]}: " if len(plates) > 1 else ""
            return Machined(withheld=f"{cam}{refused.reason}")
    files: dict[str, bytes] = {}
    setups = []
    for plate, table in zip(plates, tables, strict=True):
        files[f"{plate.stem}-grind.csv"] = grind_csv(table, analysis.design.units)
        text, setup = grind_program(analysis, plate.stem, table, settings)
        files[f"{plate.stem}-grind.ngc"] = text
        setups.append(setup)
    return Machined(files, tuple(setups))


def grind_csv(table: GrindTable, units: str) -> bytes:
    """The table as CSV: ``c_deg``, ``x_mm`` (the wheel centre's radius) and, for a design in
    inches, ``x_in``; a header row, one row per position, C from 0 to 360°."""
    from camfab.export.motion_csv import csv_bytes

    columns, values = ["c_deg", "x_mm"], [np.degrees(table.c), table.x]
    if units == "in":
        columns.append("x_in")
        values.append(table.x / 25.4)
    return csv_bytes(columns, np.column_stack(values))


def wheel_rpm(settings: Machining, radius: float) -> tuple[float, bool]:
    """The wheel's speed (rpm): ``spindle_rpm``, at most the speed at which its rim runs
    :data:`WHEEL_RIM_SPEED_M_S`; and whether that limit lowered it."""
    most = WHEEL_RIM_SPEED_M_S * 60_000.0 / (2.0 * math.pi * radius)
    return min(settings.spindle_rpm, most), settings.spindle_rpm > most


def grind_program(analysis: Analysis, stem: str, table: GrindTable,
                  settings: Machining) -> tuple[bytes, Setup]:
    """The C/X program of one plate's *table* and its setup sheet."""
    from camfab.analysis.setup_sheet import Setup, Tool, Toolpath
    from camfab.machining.rs274 import Program

    design = analysis.design
    rpm, limited = wheel_rpm(settings, settings.wheel_radius or 0.0)
    safe = float(table.x.max()) + settings.finish_allowance + settings.safe_z
    rotation = "counter-clockwise" if design.cam.sigma > 0 else "clockwise"
    work_zero = (f"X0 on the cam's axis (the C axis), X the wheel centre's distance from it "
                 f"along the wheel's line (a radius, not a diameter); C0 with the plate's +Y, as "
                 f"drawn in its DXF, on the wheel's line, C growing as the cam turns {rotation} "
                 f"seen from the face the DXF draws")
    program = Program(design.units, settings.dialect)
    header = (f"camfab {__version__}: cam grinding program",
              f"design {design.name}, plate {stem}",
              f"tool 1: grinding wheel {settings.wheel_diameter:g} mm across",
              f"work zero: {work_zero}",
              f"{len(table.c)} positions within {design.manufacturing.tolerance:g} mm; C-X "
              f"moves in inverse time: the cam's surface passes the wheel at "
              f"{settings.feed:g} mm/min")
    # G8, radius mode: X is the wheel centre's radius; the speed in whole rpm, as the notes say
    program.opening([line for text in header for line in textwrap.wrap(text, COMMENT_WIDTH)],
                    round(rpm), modes=("G8",))
    program.moves("G0", "X", np.array([[safe]]))
    program.moves("G0", "C", np.array([[0.0]]))
    operations, cutting = _turns(program, table, settings, safe)
    program.block("G94")
    program.moves("G0", "X", np.array([[safe]]))
    program.closing()
    end = float(cutting[-1, 0])
    notes = [f"the wheel's centre moves on X, a radius from the cam's axis (G8: no diameter "
             f"mode); each turn is {len(table.c) - 1} C–X moves in inverse time (G93)"]
    if limited:
        notes.append(f"the wheel runs at {rpm:.0f} rpm, its rim at {WHEEL_RIM_SPEED_M_S:g} m/s, "
                     f"not the {settings.spindle_rpm:g} rpm of spindle_rpm: check the speed "
                     "on its label")
    setup = Setup(
        file=f"{stem}-grind.ngc",
        stock=(f"the plate {stem} cut to its outline with {settings.finish_allowance:g} mm "
               "left, on a C axis by its bore"),
        work_zero=work_zero, axes="XC",
        tools=(Tool(1, "grinding wheel", float(settings.wheel_diameter or 0.0)),),
        operations=operations,
        toolpath=Toolpath("cam angle C (deg)", "wheel centre's radius X (mm)", cutting,
                          np.array([[end, float(cutting[-1, 1])], [end, safe]])),
        notes=tuple(notes))
    return program.text(), setup


def _turns(program: Program, table: GrindTable, settings: Machining,
           safe: float) -> tuple[tuple[Operation, ...], Array]:
    """Write the turns of the wheel round the cam into *program*: one with
    ``finish_allowance`` left (when there is one), one to size, each fed in on X at
    ``plunge_feed`` from where the wheel stands (from *safe*, mm, before the first), its C–X
    moves in inverse time. Their operations, and the wheel centre's path (C in degrees, X in
    mm) from the first infeed on."""
    from camfab.analysis.setup_sheet import Operation

    allowance = settings.finish_allowance
    turns = [(f"grind the profile, {allowance:g} mm left", allowance)] if allowance > 0 else []
    turns.append(("grind the profile to size", 0.0))
    c_deg = np.degrees(table.c)
    inverse = settings.feed / table.length  # 1/min: each move takes its length at the feed
    operations = []
    path = [np.array([[0.0, safe]])]
    before = safe
    for k, (name, left) in enumerate(turns):
        program.comment(name + ": one turn")
        program.block("G94")
        program.block("G1", program.word("X", float(table.x[0]) + left),
                      program.word("F", settings.plunge))
        program.block("G93")
        program.moves("G1", "CX", np.column_stack((c_deg[1:] + 360.0 * k, table.x[1:] + left)),
                      inverse)
        infeed = before - (float(table.x[0]) + left)
        operations.append(Operation(name, 1, settings.feed,
                                    float(table.length.sum()) / settings.feed
                                    + infeed / settings.plunge))
        before = float(table.x[-1]) + left
        path.append(np.column_stack((c_deg + 360.0 * k, table.x + left)))
    return tuple(operations), np.concatenate(path)
