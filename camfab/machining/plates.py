"""The machining programs of plate cams: disc, circular-arc, tangent, constant-breadth, linear,
groove plates and each plate of a conjugate pair, milled on three axes with a flat end mill.

One program per plate (``NAME.ngc``, or ``NAME-a.ngc`` and ``NAME-b.ngc`` for a pair). Work
zero: the cam's centre (the bore's axis) on the top face, X and Y as in the DXF, Z up (a linear
cam: X and Y as in its DXF, travel 0 on the plate's bottom edge). In order:

- the bore (and its keyway where the tool fits in it), by helical interpolation;
- a groove plate's groove, with a tool no wider than it: a pass down its middle, roughing
  passes out to each wall, then a finishing pass along each wall;
- the outline, last, so that the part is held until it comes free.

Each contour is roughed ``finish_allowance`` off the part, then finished on it, each pass
ramping down along its contour (laps of at most ``step_down``, no steeper than
:data:`RAMP_DEG`) from :data:`ENTRY_CLEARANCE_MM` above the top face to its depth — through the
plate and :data:`BREAK_THROUGH_MM` into the spoil board under it, or the groove's floor — and
ending with a level lap there. The tool's centre runs one tool radius (plus the allowance) off
the exact contours of lines and arcs, the joins and trims of an exact offset
(:mod:`camfab.machining.plate_offset`), written as the arcs they are. A profile concave
tighter than the tool (the ``cutter`` check's own measure) gets no program: the refusal says
where.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from camfab import __version__
from camfab.analysis.setup_sheet import Operation, Setup, Tool, Toolpath
from camfab.curves.profile import Profile
from camfab.machining import Machined
from camfab.machining.plate_offset import OffsetError, offset
from camfab.machining.plate_paths import (
    Lead,
    Move,
    along_centre,
    directed,
    edges_length,
    minutes,
    pass_moves,
    plan,
    start_tangent,
    write,
)
from camfab.machining.rs274 import Program

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.design import Design
    from camfab.design.machining import Machining
    from camfab.export.part import Part

#: The steepest a ramp descends along its contour (deg): what an end mill not made for plunging
#: takes in aluminium and steel alike.
RAMP_DEG = 3.0
#: How far a through cut goes below the plate's bottom face (mm), into a spoil board under the
#: blank, so that no skin is left.
BREAK_THROUGH_MM = 0.5
#: How far above the top face each pass comes down and begins its ramp (mm): in the air, over
#: a face that may stand a little proud.
ENTRY_CLEARANCE_MM = 0.5
#: A groove's roughing passes lie at most this share of the tool's diameter apart, so that no
#: rib is left between them.
STEPOVER = 0.8
#: The rim of stock the blank keeps outside the roughing cut, in tool diameters.
BLANK_RIM = 1.0
#: The plan view's arcs are drawn as chords within this share of the toolpath's extent.
PLAN_SHARE = 1e-4


@dataclass(frozen=True)
class Edge:
    """A contour of the part the tool runs along: its lines and arcs (mm), whether the waste
    lies outside it (the outline, a groove's inner wall) or inside (a hole, a groove's outer
    wall), and what it is, in words."""

    name: str
    profile: Profile
    outward: bool


@dataclass(frozen=True)
class Pass:
    """One pass: round *edge* with the tool's centre *distance* (mm) off it, down to *bottom*
    (z, mm) in laps of at most *step* (mm) each."""

    edge: Edge
    distance: float
    bottom: float
    step: float


@dataclass(frozen=True)
class Step:
    """One operation of the setup sheet: its passes, in order."""

    name: str
    passes: tuple[Pass, ...]


class Refused(Exception):
    """No program can be made of a plate: the message says why and where."""


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
    return Machined(files, tuple(setups))


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
    through = -(thickness + BREAK_THROUGH_MM)
    if settings.length_of_cut < -through:
        raise Refused(f"the tool's length of cut, {words.length(settings.length_of_cut)}, "
                      f"does not reach through the plate and {words.length(BREAK_THROUGH_MM)} "
                      f"below it ({words.length(-through)})")
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
    made = Cutting(design, settings, keep, notes, analysis.linear is None)
    blocks = [made.step(step) for step in steps]
    return made.program(stem, blocks, outline, thickness, words)


class Words:
    """Lengths in the design's units, for the setup sheet and the program's comments."""

    def __init__(self, design: Design) -> None:
        self.unit = design.units
        self.per = design.mm_per_unit

    def length(self, mm: float) -> str:
        return f"{mm / self.per:.4g} {self.unit}"

    def point(self, xy: np.ndarray) -> str:
        return f"({xy[0] / self.per:.4g}, {xy[1] / self.per:.4g}) {self.unit}"


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


class Cutting:
    """The passes of one plate turned into moves: the program's (the tool centre's path, or
    the part's contour for the control to offset) and the tool centre's (for the cutting
    time, the plan view and the check that the tool clears the part)."""

    def __init__(self, design: Design, settings: Machining, keep: list[Profile],
                 notes: list[str], turning: bool) -> None:
        self.design = design
        self.turning = turning
        self.settings = settings
        self.keep = keep
        self.notes = notes
        self.control = settings.compensation == "control" and settings.dialect != "grbl"
        self.tolerance = design.manufacturing.tolerance
        self.lead = Lead(settings.tool_radius / 2.0, 0.0, ENTRY_CLEARANCE_MM, settings.safe_z,
                         settings.feed, settings.plunge)

    def step(self, step: Step) -> tuple[Step, list[Move], list[Move], int]:
        """The program's moves and the tool centre's for *step*, and its laps."""
        program: list[Move] = [Move("comment", words=f"{step.name}")]
        centre: list[Move] = []
        count = 0
        for one in step.passes:
            ours, theirs, laps = self.one_pass(one)
            program += theirs
            centre += ours
            count += laps
        return step, program, centre, count

    def one_pass(self, one: Pass) -> tuple[list[Move], list[Move], int]:
        """The tool centre's moves, the program's, and the laps of pass *one*."""
        settings = self.settings
        radius = settings.tool_radius
        edge = one.edge
        distance = one.distance
        centre = self.around(edge, distance)
        if centre is None:  # the allowance does not fit: rough on the part's contour
            self.notes.append(f"{edge.name} is roughed without the finishing allowance: "
                              "it is concave tighter than the tool's radius plus the allowance")
            distance = radius
            centre = self.around(edge, distance)
            assert centre is not None
        path, where, k, point = centre
        self.clear(path, edge, distance)
        clockwise = edge.outward == (settings.direction == "climb")
        left = settings.direction == "climb"
        along = along_centre(where, len(path.vertices), path, where)
        lap = edges_length(path, where)
        edge_start = path.vertices[where[k]]
        at = along[where[k]] + float(np.hypot(*(point - edge_start)))
        if path.bulges[where[k]] != 0.0:
            j = int(np.flatnonzero(path.arcs().index == where[k])[0])
            arcs = path.arcs()
            turned = np.arctan2(*(point - arcs.centre[j])[::-1]) - arcs.start_angle[j]
            turned = np.mod(turned * np.sign(arcs.sweep[j]), 2.0 * math.pi)
            at = along[where[k]] + float(arcs.radius[j] * turned)
        route, share = directed(path, int(where[k]), point, clockwise, along, at, lap)
        drop = min(one.step, lap * math.tan(math.radians(RAMP_DEG)))
        laps = max(1, math.ceil((self.lead.entry_z - one.bottom) / drop - 1e-9))
        lead = self.lead_out(route, left, edge, distance)
        ours = pass_moves(route, share, left, radius, False, lead, one.bottom, laps)
        theirs = ours
        if self.control:
            programmed = self.around(edge, distance - radius)
            assert programmed is not None
            shape, shape_where, _, shape_point = programmed
            shape_along = along_centre(shape_where, len(shape.vertices), path, where)
            route, share = directed(shape, int(shape_where[k]), shape_point, clockwise,
                                    shape_along, at, lap)
            theirs = pass_moves(route, share, left, radius, True, lead, one.bottom, laps)
        return ours, theirs, laps + 1

    def around(self, edge: Edge, distance: float
               ) -> tuple[Profile, np.ndarray, int, np.ndarray] | None:
        """The contour *distance* (mm) off *edge* on the waste's side, the index of the edge it
        made of each of the part's, the part's edge where a pass starts (its longest) and that
        start's point on the contour (off the edge's middle); None when the offset consumes an
        edge of the contour.

        Raises
        ------
        Refused
            An offset at the tool's own radius consumes an edge (a neck or hollow the check of
            the profile does not see).
        """
        part = edge.profile.ccw()
        signed = distance if edge.outward else -distance
        if distance > 0.0:
            try:
                path, where = offset(part, signed)
            except OffsetError as error:
                if distance > self.settings.tool_radius:
                    return None
                at = "; ".join(Words(self.design).point(p) for p in error.where[:4])
                raise Refused(f"the tool cannot follow {edge.name} at {at}: {error}") from None
        else:
            path, where = part, np.arange(len(part.vertices))
        k, point = middle_of_longest(part)
        return path, where, k, point + signed * outward_normal(part, k, point)

    def clear(self, path: Profile, edge: Edge, distance: float) -> None:
        """Refuse a centre *path* that comes nearer the part than the tool allows: *distance*
        (mm) from its own *edge*, the tool's radius from the part's other contours (a neck of
        the part narrower than the tool, which an offset alone does not see)."""
        points = path.points(self.tolerance)
        for contour in self.keep:
            own = contour is edge.profile
            least = distance - 1e-6 if own else self.settings.tool_radius - self.tolerance
            gap = contour.distance(points)
            if np.any(gap < least):
                at = Words(self.design).point(points[int(np.argmin(gap - least))])
                raise Refused(f"the tool's path round {edge.name} comes nearer the part than "
                              f"the tool's radius at {at}: the part is narrower there than the "
                              "tool")

    def lead_out(self, route: Profile, left: bool, edge: Edge, distance: float) -> Lead:
        """The lead for *route*: its tangent arc out, of half the tool's radius, or less where
        that would reach the part (none where even an eighth would)."""
        start = route.vertices[0]
        t = start_tangent(route)
        n = (1.0 if left else -1.0) * np.array([-t[1], t[0]])
        radius = self.settings.tool_radius / 2.0
        for _ in range(3):
            angle = np.linspace(0.0, math.pi / 2.0, 16)
            arc = (start + radius * n - radius * np.cos(angle)[:, None] * n
                   + radius * np.sin(angle)[:, None] * t)
            if all(np.all(c.distance(arc) >= (distance if c is edge.profile
                                               else self.settings.tool_radius) - 1e-6)
                   for c in self.keep):
                return replace(self.lead, lead_out=radius)
            radius /= 2.0
        return self.lead

    def program(self, stem: str, blocks: list[tuple[Step, list[Move], list[Move], int]],
                outline: Edge, thickness: float, words: Words) -> tuple[bytes, Setup]:
        """The program's text and its setup sheet."""
        design, settings = self.design, self.settings
        grbl = settings.dialect == "grbl"
        stock, zero = stock_words(design, outline.profile, thickness, settings, words,
                                  self.turning)
        tool = (f"tool 1: flat end mill, diameter {words.length(settings.tool_diameter)}, "
                f"{settings.flutes} flutes, length of cut {words.length(settings.length_of_cut)}")
        form = (f"cutter compensation G{41 if settings.direction == 'climb' else 42} D1 (the "
                "control offsets the part's contours by tool 1's radius)" if self.control else
                f"the tool centre's path for a tool of diameter "
                f"{words.length(settings.tool_diameter)} (no compensation by the control)")
        program = Program(design.units, settings.dialect)
        program.comment(f"camfab {__version__}: {stem}.ngc, design {design.name}")
        for line in (tool, f"work zero: {zero}", f"stock: {stock}", form):
            program.comment(line)
        program.block("G21" if design.units == "mm" else "G20")
        program.block("G17 G90 G94" if grbl else "G17 G90 G40 G49 G80 G94")
        if not grbl:
            program.block("T1 M6")
            program.block("G43 H1")
        program.block(f"S{_rpm(settings.spindle_rpm)} M3")
        program.block("G0", program.word("Z", settings.safe_z))
        first = next(m for _, moves, _, _ in blocks for m in moves if m.end is not None)
        assert first.end is not None
        position = np.array([first.end[0], first.end[1], settings.safe_z])
        written = np.array([math.inf, math.inf, settings.safe_z])
        operations, cutting, rapid = [], [], []
        gap = np.full((1, 2), np.nan)
        extent = max(1.0, float(np.abs(outline.profile.bounds()).max()))
        for step, moves, centre, laps in blocks:
            written = write(program, moves, written)
            operations.append(Operation(step.name, 1, settings.feed, minutes(centre, position),
                                        laps))
            cut, fast = plan(centre, position, PLAN_SHARE * extent)
            cutting += [gap, cut]
            rapid += [gap, fast]
            last = next(m for m in reversed(centre) if m.end is not None)
            assert last.end is not None
            position = np.array(last.end)
        program.block("M5")
        program.block("M30")
        notes = [f"passes: ramps along each contour, at most {words.length(settings.depth_step)} "
                 f"down a lap and no steeper than {RAMP_DEG:g}°, from "
                 f"{words.length(ENTRY_CLEARANCE_MM)} above the top face; each pass ends with "
                 f"a level lap at its depth; roughing leaves "
                 f"{words.length(settings.finish_allowance)} for the finishing pass",
                 f"a through cut goes {words.length(BREAK_THROUGH_MM)} below the plate into a "
                 "spoil board; clamp the blank outside the toolpath; the bore is cut first: a "
                 "bolt through it holds the part when the outline frees it (no tabs are left)",
                 *self.notes]
        if grbl:
            notes.append("Grbl: fit tool 1 and set its length before starting (the program "
                         "has no tool change)")
        toolpath = Toolpath("X (mm)", "Y (mm)", np.vstack(cutting[1:]), np.vstack(rapid[1:]))
        setup = Setup(f"{stem}.ngc", stock, zero, "XYZ",
                      (Tool(1, "flat end mill", settings.tool_diameter, settings.flutes,
                            settings.length_of_cut),),
                      tuple(operations), toolpath, tuple(notes))
        return program.text(), setup


def middle_of_longest(profile: Profile) -> tuple[int, np.ndarray]:
    """The longest edge of the counter-clockwise *profile* and its middle point (mm)."""
    v = profile.vertices
    following = np.roll(v, -1, axis=0)
    length = np.hypot(*(following - v).T)
    arcs = profile.arcs()
    length[arcs.index] = arcs.radius * np.abs(arcs.sweep)
    k = int(np.argmax(length))
    if profile.bulges[k] == 0.0:
        return k, (v[k] + following[k]) / 2.0
    j = int(np.flatnonzero(arcs.index == k)[0])
    angle = arcs.start_angle[j] + arcs.sweep[j] / 2.0
    return k, arcs.centre[j] + arcs.radius[j] * np.array([math.cos(angle), math.sin(angle)])


def outward_normal(profile: Profile, k: int, point: np.ndarray) -> np.ndarray:
    """The outward unit normal of edge *k* of the counter-clockwise *profile* at *point* on
    it."""
    v = profile.vertices
    if profile.bulges[k] == 0.0:
        d = v[(k + 1) % len(v)] - v[k]
        return np.array([d[1], -d[0]]) / math.hypot(*d)
    arcs = profile.arcs()
    j = int(np.flatnonzero(arcs.index == k)[0])
    radial = (point - arcs.centre[j]) / arcs.radius[j]
    return radial if arcs.sweep[j] > 0.0 else -radial


def stock_words(design: Design, outline: Profile, thickness: float, settings: Machining,
                words: Words, turning: bool) -> tuple[str, str]:
    """The blank and the work zero, in words: a round blank about the cam centre of a plate
    *turning* about it (a linear cam's: a rectangle), keeping a rim of :data:`BLANK_RIM` tool
    diameters outside the roughing cut, its size rounded up to a whole millimetre (an eighth
    of an inch)."""
    step = 1.0 if design.units == "mm" else 25.4 / 8.0
    rim = settings.finish_allowance + settings.tool_diameter * (1.0 + BLANK_RIM)
    low, high = outline.bounds()
    thick = words.length(thickness)
    if turning:
        reach = float(np.hypot(*outline.points(design.manufacturing.tolerance).T).max())
        diameter = math.ceil(2.0 * (reach + rim) / step) * step
        return (f"a round blank of diameter {words.length(diameter)} and thickness {thick}, "
                f"centred on the cam's centre (the outline reaches {words.length(reach)} from "
                "it)",
                "X0 Y0 on the cam's centre (the bore's axis), Z0 on the top face; X and Y as "
                "in the DXF, Z up")
    low = np.floor((low - rim) / step) * step
    high = np.ceil((high + rim) / step) * step
    return (f"a rectangular blank {words.length(high[0] - low[0])} by "
            f"{words.length(high[1] - low[1])}, thickness {thick}, from X {words.length(low[0])} "
            f"to {words.length(high[0])} and Y {words.length(low[1])} to "
            f"{words.length(high[1])}",
            "X0 Y0 where the DXF has them (travel 0 on the plate's bottom edge), Z0 on the top "
            "face, Z up")


def _rpm(rpm: float) -> str:
    text = f"{rpm:.1f}"
    return text.rstrip("0").rstrip(".")
