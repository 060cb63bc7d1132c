"""The machining program of a drum (cylindrical) cam: its groove cut on four axes.

The machine: a rotary A axis about the drum's axis, X along it, Z radial (the tool's axis
points at the drum's axis). Work zero: the drum's axis at its face z = 0 of the design's frame:
X is the design's axial coordinate z, Z the distance from the drum's axis (the drum's surface
at Z = its radius). A = σθ in degrees (θ the cam angle, σ = +1 for ``rotation: ccw``, −1 for
``cw``): at A = 0 the roller's line at θ = 0 (the design's +Y) is under the tool, and positive A
turns the drum counterclockwise seen from its +X end (the right-hand rule about +X), so the
drum turns on A as it turns in use as θ grows, and the point of the groove at cam angle θ
(the cam frame's polar angle −σθ) is under the tool at A = σθ.

How the groove is cut is :mod:`camfab.machining.drum_cuts`; this module writes it: each lap
round the drum one run of straight X–A moves at constant Z in inverse time (G93: F is 1/the
move's minutes, so that the tool runs over the work at ``feed`` on the helix the move makes at
the top of the layer it cuts), plunges and steps along X at G94. The program carries the tool
centre's path whatever ``compensation`` says: a control's cutter compensation offsets in the
XY plane, not round A.
"""

from __future__ import annotations

import textwrap
from typing import TYPE_CHECKING

import numpy as np

from camfab.analysis.findings import Finding
from camfab.analysis.record import terse
from camfab.analysis.setup_sheet import Operation, Setup, Tool, Toolpath
from camfab.machining import Machined
from camfab.machining.drum_cuts import SAME_SIZE_MM, Plan, plan
from camfab.machining.rs274 import DECIMALS, Program

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.design import Design
    from camfab.design.machining import Machining
    from camfab.export.part import Part
    from camfab.geometry.drum import Drum

#: What the toolpath's picture plots.
X_LABEL = "X: along the drum's axis (mm)"
Y_LABEL = "A: the drum's turn (°)"
#: The longest comment line written (characters): LinuxCNC reads blocks of at most 255.
COMMENT_WIDTH = 72


def machine(analysis: Analysis, part: Part, settings: Machining) -> Machined:
    """The drum's machining program (``NAME.ngc``), its setup sheet and the ``wall_error``
    finding; withheld when no program can cut the groove (it folds over itself, the tool is
    wider than the groove, the dialect has no rotary axis)."""
    design = analysis.design
    dense = analysis.drum
    assert dense is not None
    d = dense.drum
    why = _withheld(analysis, d, settings)
    if why is not None:
        return Machined(withheld=why)
    program = Program(design.units, settings.dialect)
    resolution = 10.0 ** -DECIMALS[design.units] * design.mm_per_unit
    cuts = plan(d, analysis.program, settings, design.manufacturing.tolerance, resolution)
    operations, toolpath = _write(program, design, settings, d, cuts)
    finding = wall_finding(design, settings, d, cuts)
    name = f"{design.name}.ngc"
    setup = Setup(name, _stock(design, d), work_zero(design, d), "XZA",
                  (Tool(1, "flat end mill, centre-cutting", settings.tool_diameter,
                        settings.flutes, settings.length_of_cut),),
                  tuple(operations), toolpath, _notes(design, settings, d, cuts, finding))
    return Machined({name: program.text()}, (setup,), (finding,))


def _withheld(analysis: Analysis, d: Drum, settings: Machining) -> str | None:
    if settings.dialect != "linuxcnc":
        return (f"a drum's groove is cut on a rotary A axis, which dialect "
                f"{settings.dialect} has not: use dialect: linuxcnc")
    if any(f.id == "groove" and not f.ok for f in analysis.findings):
        return ("the groove folds over itself (see the groove check): no tool can cut walls "
                "a roller could run between")
    if settings.tool_diameter > 2.0 * d.roller + SAME_SIZE_MM:
        return (f"the tool ({terse(settings.tool_diameter)} mm) is wider than the groove "
                f"({terse(2.0 * d.roller)} mm)")
    return None


def _length(design: Design, mm: float) -> str:
    """*mm* in the design's units, with the unit."""
    return f"{terse(mm / design.mm_per_unit)} {design.units}"


def _stock(design: Design, d: Drum) -> str:
    bore = f", bored ⌀{_length(design, 2.0 * d.bore)}" if d.bore > 0.0 else ""
    return (f"drum blank ⌀{_length(design, 2.0 * d.radius)} × "
            f"{_length(design, d.length)} long{bore}, its faces square to its axis")


def work_zero(design: Design, d: Drum, ascii: bool = False) -> str:
    """The work zero and the axes in words (in ASCII for the program's comments)."""
    theta = "theta" if ascii else "θ"
    sign = theta if d.sigma > 0 else ("-" if ascii else "−") + theta
    return (f"X0 on the drum's axis at its face z = 0 of the design, X along the axis as the "
            f"design's z; Z the distance from the drum's axis (its surface at Z "
            f"{_length(design, d.radius)}); A = {sign} in degrees ({design.cam.rotation} cam): "
            f"at A0 the roller's line at {theta} = 0 is under the tool, and positive A turns "
            f"the drum counterclockwise seen from its +X end (right-hand rule about +X)")


def _write(program: Program, design: Design, settings: Machining, d: Drum,
           cuts: Plan) -> tuple[list[Operation], Toolpath]:
    """The program's blocks into *program*; the operations with their estimated minutes (the
    length of each feed move over its feed), and the toolpath unrolled (X, A mod 360°)."""
    from camfab import __version__

    header = (f"camfab {__version__}: {design.name}, drum cam, groove cut on X, Z and A",
              f"tool T1: flat end mill, centre-cutting, diameter "
              f"{_length(design, settings.tool_diameter)}, {settings.flutes} flutes",
              f"work zero: {work_zero(design, d, ascii=True)}",
              "feeds: G93 inverse time on moves that turn A (the feed holds at the top of "
              "the layer each cuts), G94 on plunges and steps along X")
    program.opening([line for text in header for line in textwrap.wrap(text, COMMENT_WIDTH)],
                    settings.spindle_rpm)
    safe = d.radius + settings.safe_z
    program.block("G0", program.word("Z", safe))
    feed, plunge = settings.feed, settings.plunge
    a_now, x_now, z_now = 0.0, None, safe
    cutting: list[list[float]] = []
    rapid: list[list[float]] = []
    operations = []
    for cut in cuts.cuts:
        program.comment(f"operation: {cut.name}")
        minutes = 0.0
        for index, lap in enumerate(cut.laps):
            a, x = (lap.a_deg, lap.x) if lap.forward else (lap.a_deg[::-1], lap.x[::-1])
            base = a_now - a[0]  # every lap starts and ends at a whole turn
            if index == 0:
                words = [program.word("X", x[0])]
                if x_now is None:
                    words.append(program.word("A", a_now))
                program.block("G0", *words)
                rapid += [[np.nan, np.nan], [x_now if x_now is not None else x[0], 0.0],
                          [x[0], 0.0]]
            elif x[0] != x_now:
                program.block("G1", program.word("X", x[0]), program.word("F", feed))
                minutes += abs(x[0] - x_now) / feed
                cutting += [[np.nan, np.nan], [x_now, 0.0], [x[0], 0.0]]
            if lap.tip != z_now:
                program.block("G1", program.word("Z", lap.tip), program.word("F", plunge))
                minutes += abs(z_now - lap.tip) / plunge
            step = np.hypot(np.diff(x), lap.cutting_radius * np.radians(np.diff(a)))
            program.block("G93")
            program.moves("G1", "XA", np.column_stack((x[1:], a[1:] + base)), feed / step)
            program.block("G94")
            minutes += float(step.sum()) / feed
            cutting += [[np.nan, np.nan], *np.column_stack((x, a)).tolist()]
            a_now, x_now, z_now = float(a[-1] + base), float(x[-1]), lap.tip
        program.block("G0", program.word("Z", safe))
        z_now = safe
        operations.append(Operation(cut.name, 1, feed, float(minutes), len(cut.laps)))
    program.closing()
    return operations, Toolpath(X_LABEL, Y_LABEL, np.array(cutting).reshape(-1, 2),
                                np.array(rapid).reshape(-1, 2))


def wall_finding(design: Design, settings: Machining, d: Drum, cuts: Plan) -> Finding:
    """The ``wall_error`` check: the largest distance between the exact walls and the walls the
    program cuts, against ``manufacturing.tolerance``."""
    tolerance = design.manufacturing.tolerance
    error, ok = cuts.wall_error, cuts.wall_error <= tolerance
    tool, width = _length(design, settings.tool_diameter), _length(design, 2.0 * d.roller)
    said = (f"the walls cut lie within {_length(design, error)} of the exact walls (at "
            f"θ = {terse(cuts.wall_error_at_deg)}°)")
    if cuts.exact:
        text = (f"a tool the groove's width ({tool}) follows the roller's axis: {said}, the "
                f"program's chords and rounding")
    else:
        text = (f"a {tool} tool finishing the {width} groove against its exact walls: {said}; a "
                f"radial tool narrower than the groove touches a wall at the drum's surface and "
                f"leaves more towards the floor, where the wall is steeper")
    if ok:
        return Finding("wall_error", True, "error", f"{text}, within the tolerance "
                       f"{_length(design, tolerance)}", error, tolerance, "mm",
                       quantity="wall error", at_deg=cuts.wall_error_at_deg)
    advice = (f": a tool of at least {_length(design, cuts.smallest_tool)} meets it (the "
              f"groove's own width, {width}, cuts the walls exactly)"
              if cuts.smallest_tool is not None else "")
    return Finding("wall_error", False, "error", f"{text}, over the tolerance "
                   f"{_length(design, tolerance)}{advice}", error, tolerance, "mm",
                   quantity="wall error", at_deg=cuts.wall_error_at_deg)


def _notes(design: Design, settings: Machining, d: Drum, cuts: Plan,
           finding: Finding) -> tuple[str, ...]:
    floor = float(cuts.layers[-1])
    notes = [f"Wall error: {finding.message}.",
             f"Depth: {cuts.layers.size} layers down to Z {_length(design, floor)}; the floor's "
             f"radius is {_length(design, d.root)}: the tool's flat end goes "
             f"{_length(design, d.root - floor)} below it where the walls' feet lie beside its "
             f"axis, so that it reaches them.",
             f"Feeds: G93 inverse time on every move that turns A, so that the tool runs over "
             f"the work at {_length(design, settings.feed)}/min at the top of the layer it "
             f"cuts (the drum's surface for the first); plunges at "
             f"{_length(design, settings.plunge)}/min, steps along X at the feed (G94).",
             "Each layer starts with a plunge: the end mill must cut at its centre."]
    if settings.compensation == "control":
        notes.append("Compensation: the program carries the tool centre's path (a control's "
                     "cutter compensation offsets in the XY plane, not round A).")
    reach = d.radius - floor
    if reach > settings.length_of_cut:
        notes.append(f"The groove is cut {_length(design, reach)} deep, deeper than the tool's "
                     f"length of cut ({_length(design, settings.length_of_cut)}).")
    return tuple(notes)

