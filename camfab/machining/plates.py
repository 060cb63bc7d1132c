"""The machining programs of plate cams: disc, circular-arc, tangent, constant-breadth, linear,
groove plates and each plate of a conjugate pair, milled on three axes with a flat end mill.

One program per plate (``NAME.ngc``, or ``NAME-a.ngc`` and ``NAME-b.ngc`` for a pair). Work
zero: the cam's centre (the bore's axis) on the top face, X and Y as in the DXF, Z up (a linear
cam: X and Y as in its DXF, travel 0 on the plate's bottom edge). In order:

- the bore (and its keyway where the tool fits in it), by helical interpolation;
- a groove plate's groove, with a tool no wider than it: a pass down its middle, roughing
  passes out to each wall, then a finishing pass along each wall;
- the outline, last, so that the part is held until it comes free.

Each contour is roughed ``finish_allowance`` off the part, then finished on it. A pass goes
round its contour once per depth, each lap ramping down along the contour (at most
``step_down``, no steeper than :data:`~camfab.machining.plate_cutting.RAMP_DEG`, at the plunge
feed) from the air above the top face, then running level at the feed; a last level lap at the
full depth: through the plate into a spoil board, or the groove's floor. The tool's centre
runs one tool radius (plus the allowance) off the exact contours of lines and arcs, the joins
and trims of an exact offset (:mod:`camfab.machining.plate_offset`), written as the arcs they
are (:mod:`camfab.machining.plate_paths`, :mod:`camfab.machining.plate_cutting`). A profile
concave tighter than the tool (the ``cutter`` check's own measure) gets no program: the
refusal says where.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from camfab.curves.profile import Profile
from camfab.machining import Machined
from camfab.machining.plate_cutting import (
    BREAK_THROUGH_MM,
    Cutting,
    Edge,
    Pass,
    Refused,
    Step,
    Words,
)
from camfab.machining.plate_offset import OffsetError, offset

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.analysis.setup_sheet import Setup
    from camfab.design import Design
    from camfab.design.machining import Machining
    from camfab.export.part import Part

#: A groove's roughing passes lie at most this share of the tool's diameter apart, so that no
#: rib is left between them.
STEPOVER = 0.8


def machine(analysis: Analysis, part: Part, settings: Machining) -> Machined:
    """The program of each plate of *part* (by its file stem) with its setup sheet, or why
    none can be made."""
    files: dict[str, bytes] = {}
    setups: list[Setup] = []
    for stem in part.views:
        try:
            text, setup = plate_program(analysis, part, stem, settings)
        except Refused as refusal:
            return Machined(withheld=f"{stem}.ngc: {refusal}")
        files[f"{stem}.ngc"] = text
        setups.append(setup)
    milled = Machined(files, tuple(setups))
    return _with_grinding(milled, analysis, settings) if settings.wheel_radius else milled


def _with_grinding(milled: Machined, analysis: Analysis, settings: Machining) -> Machined:
    """*milled* with the grinding tables and C/X programs of ``wheel_diameter``
    (:mod:`camfab.machining.grinding`), or, where the wheel cannot grind the plate, with the
    ``grinding`` check that says why (the milling programs stay)."""
    from camfab.analysis.findings import Finding
    from camfab.machining.grinding import grind_files

    ground = grind_files(analysis, settings)
    findings = ground.findings
    if ground.withheld is not None:
        findings = (*findings, Finding("grinding", False, "error",
                                       f"no grinding files: {ground.withheld}"))
    return Machined({**milled.files, **ground.files}, (*milled.setups, *ground.setups),
                    (*milled.findings, *findings))


def plate_program(analysis: Analysis, part: Part, stem: str,
                  settings: Machining) -> tuple[bytes, Setup]:
    """The program and setup sheet of the plate *stem*.

    Raises
    ------
    Refused
        The plate has no thickness, the tool is too short for it, does not fit its bore or
        groove, or cannot follow its profile.
    """
    design = analysis.design
    walls = analysis.groove
    thickness = walls.thickness if walls is not None else design.cam.thickness
    if thickness is None:
        raise Refused("the plate's thickness is not given (cam.thickness): a program needs "
                      "the depth to cut")
    words = Words(design)
    radius = settings.tool_radius
    below = min(BREAK_THROUGH_MM, settings.length_of_cut - thickness)
    if below < 0.0:  # (the settings' rules refuse it first)
        raise Refused(f"the tool's length of cut, {words.length(settings.length_of_cut)}, "
                      f"does not reach through the plate, {words.length(thickness)} thick")
    through = -(thickness + below)
    tight = too_tight(analysis, stem, radius)
    if tight is not None:
        raise Refused(f"the tool (diameter {words.length(settings.tool_diameter)}) is too "
                      f"large for the profile: {tight}")
    notes: list[str] = []
    holes = bore_edges(design, settings, notes, words)
    outline = Edge("the outline", outline_profile(analysis, part, stem), True)
    steps = [*through_steps(holes, through, settings)]
    grooved: list[Edge] = []
    if walls is not None:
        grooved = [Edge("the groove's inner wall", walls.inner, True),
                   Edge("the groove's outer wall", walls.outer, False)]
        steps += groove_steps(grooved, walls.radius, -walls.depth, settings, notes, words)
    steps += through_steps([outline], through, settings)
    keep = [outline.profile, *(h.profile for h in holes), *(g.profile for g in grooved)]
    made = Cutting(design, settings, keep, notes, analysis.linear is None, below, bool(holes))
    blocks = [made.step(step) for step in steps]
    return made.program(stem, blocks, outline, thickness, words)


def too_tight(analysis: Analysis, stem: str, radius: float) -> str | None:
    """Why a tool of *radius* (mm) cannot follow the outline of plate *stem* (where the profile
    is concave tighter than it, or has a sharp hollow), as the design's ``cutter`` check says
    for a cutter of that radius; None where it can."""
    design = analysis.design
    if analysis.groove is not None:  # a round plate
        return None
    sized = design.model_copy(update={"manufacturing": design.manufacturing.model_copy(
        update={"cutter_radius": radius})})
    if analysis.linear is not None:
        from camfab.analysis.linear_checks import cutter_finding as linear_cutter

        finding = linear_cutter(sized, analysis.linear, analysis.numbers)
    else:
        from camfab.analysis.cam_checks import cutter_finding

        partner = analysis.partner
        if stem.endswith("-b") and partner is not None and partner.geometry is not None:
            finding = cutter_finding(sized, partner.geometry, partner.numbers, partner.program)
        else:
            finding = cutter_finding(sized, analysis.geometry, analysis.numbers)
    return None if finding is None or finding.ok else finding.message


def outline_profile(analysis: Analysis, part: Part, stem: str) -> Profile:
    """The part's outline (mm, lines and arcs): the CUT outline, or where a laser's kerf moved
    that off the part, the part's own; a groove plate's round rim."""
    walls = analysis.groove
    if walls is not None:
        return circle(walls.outer_radius)
    cut, _ = part.views[stem]
    if analysis.design.manufacturing.kerf <= 0.0:
        return cut.profiles[0]
    if analysis.linear is not None:
        return analysis.linear.outline
    plates = part.made[0] if isinstance(part.made, tuple) else {"": part.made}
    key = stem.removeprefix(analysis.design.name).lstrip("-")
    return plates[key].outline


def circle(radius: float) -> Profile:
    """A circle about the cam centre (mm) as two half circles."""
    return Profile(np.array([[radius, 0.0], [-radius, 0.0]]), np.array([1.0, 1.0]))


def bore_edges(design: Design, settings: Machining, notes: list[str], words: Words
               ) -> list[Edge]:
    """The bore, with its keyway where the tool fits in it (else a note says it is cut
    otherwise).

    Raises
    ------
    Refused
        The tool does not fit the bore.
    """
    from camfab.geometry.plate import bore_contour

    cam = design.cam
    if cam.bore is None:
        return []
    radius = settings.tool_radius
    if settings.tool_diameter >= cam.bore:
        raise Refused(f"the tool (diameter {words.length(settings.tool_diameter)}) does not "
                      f"fit the bore (diameter {words.length(cam.bore)}): a tool under the "
                      "bore's diameter cuts it by helical interpolation")
    round_bore = Edge("the bore", circle(cam.bore / 2.0), False)
    if cam.keyway is None:
        return [round_bore]
    hole = bore_contour(cam.bore, (cam.keyway.width, cam.keyway.depth))
    assert hole is not None
    keyway = f"{words.length(cam.keyway.width)} × {words.length(cam.keyway.depth)}"
    try:
        offset(hole, -radius)
    except OffsetError:
        notes.append(f"the keyway ({keyway}) is not cut: the tool is wider than it; the bore "
                     "is cut round, and the keyway is cut otherwise (broached, or slotted)")
        return [round_bore]
    notes.append(f"the keyway ({keyway}) is milled with its two far corners round, of the "
                 f"tool's radius {words.length(radius)}: square them (or broach the keyway) "
                 "where the key's edges need it")
    return [Edge("the bore and its keyway", hole, False)]


def through_steps(edges: list[Edge], bottom: float, settings: Machining) -> list[Step]:
    """Roughing then finishing each of *edges* through the plate (down to *bottom*, mm); one
    operation when there is no finishing allowance (its last level lap finishes)."""
    radius, allowance = settings.tool_radius, settings.finish_allowance
    steps = []
    for edge in edges:
        if allowance <= 0.0:
            steps.append(Step(edge.name, (Pass(edge, radius, bottom, settings.depth_step),)))
            continue
        steps += [Step(f"{edge.name}: roughing",
                       (Pass(edge, radius + allowance, bottom, settings.depth_step),)),
                  Step(f"{edge.name}: finishing", (Pass(edge, radius, bottom, math.inf),))]
    return steps


def groove_steps(walls: list[Edge], half_width: float, floor: float, settings: Machining,
                 notes: list[str], words: Words) -> list[Step]:
    """The groove (its walls *walls*, inner then outer, *half_width* mm either side of the pitch
    curve, its floor at z = *floor*, mm): a pass down its middle, roughing passes out to
    ``finish_allowance`` off each wall at most :data:`STEPOVER` tool diameters apart, then a
    finishing pass along each wall.

    Raises
    ------
    Refused
        The tool is wider than the groove.
    """
    radius, allowance, step = settings.tool_radius, settings.finish_allowance, settings.depth_step
    inner, outer = walls
    if radius > half_width * (1.0 + 1e-9):
        raise Refused(f"the tool (diameter {words.length(settings.tool_diameter)}) is wider "
                      f"than the groove ({words.length(2.0 * half_width)}): a tool at most as "
                      "wide mills it")
    steps = [Step("the groove: its middle", (Pass(inner, half_width, floor, step),))]
    room = half_width - radius - allowance
    if room > 1e-6:
        count = math.ceil(room / (STEPOVER * settings.tool_diameter))
        distances = radius + allowance + room * np.arange(count - 1, -1, -1) / count
        steps.append(Step("the groove: roughing out to its walls",
                          tuple(Pass(wall, float(d), floor, step)
                                for d in distances for wall in (inner, outer))))
    if half_width - radius > 1e-6:
        steps += [Step(f"{wall.name}: finishing", (Pass(wall, radius, floor, math.inf),))
                  for wall in (inner, outer)]
    else:
        notes.append(f"the tool is as wide as the groove ({words.length(2 * half_width)}): its "
                     "pass down the middle cuts both walls")
    return steps
