"""A plate's passes turned into its program: the moves of each pass round its contour (the
tool centre's path, and the part's contour for the control's compensation), checked clear of
the part, written as G-code, timed, drawn in plan view, with the setup sheet in words (mm, the
design's units in words)."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from camfab import __version__
from camfab.analysis.setup_sheet import Operation, Setup, Tool, Toolpath
from camfab.curves.profile import Profile
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
    from camfab.design import Design
    from camfab.design.machining import Machining

#: The steepest a ramp descends along its contour (deg): what an end mill not made for plunging
#: takes in aluminium and steel alike.
RAMP_DEG = 3.0
#: How far a through cut goes below the plate's bottom face (mm), into a spoil board under the
#: blank, so that no skin is left; less where the tool's length of cut ends sooner (the flutes
#: must reach the top face when the tool is at full depth).
BREAK_THROUGH_MM = 0.5
#: How far above the top face each pass comes down and begins its ramp (mm): in the air, over
#: a face that may stand a little proud.
ENTRY_CLEARANCE_MM = 0.5
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


class Words:
    """Lengths in the design's units, for the setup sheet and the program's comments."""

    def __init__(self, design: Design) -> None:
        self.unit = design.units
        self.per = design.mm_per_unit

    def length(self, mm: float) -> str:
        return f"{mm / self.per:.4g} {self.unit}"

    def point(self, xy: np.ndarray) -> str:
        return f"({xy[0] / self.per:.4g}, {xy[1] / self.per:.4g}) {self.unit}"


class Cutting:
    """The passes of one plate turned into moves: the program's (the tool centre's path, or
    the part's contour for the control to offset) and the tool centre's (for the cutting
    time, the plan view and the check that the tool clears the part)."""

    def __init__(self, design: Design, settings: Machining, keep: list[Profile],
                 notes: list[str], turning: bool, below: float, bored: bool) -> None:
        """*keep*: the part's contours (mm) no tool may come nearer than its radius; *notes*
        for the setup sheet, added to as passes are made; *turning*: a plate that turns about
        its centre (not a linear cam's); *below*: how far a through cut goes under the plate
        (mm); *bored*: the plate has a bore."""
        self.design = design
        self.below = below
        self.bored = bored
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
        slope = math.tan(math.radians(RAMP_DEG))
        height = self.lead.entry_z - one.bottom
        count = max(1, math.ceil(height / min(one.step, lap * slope) - 1e-9))
        depths = self.lead.entry_z - height * np.arange(1, count + 1) / count
        depths = np.append(depths, one.bottom)  # and a level lap at the bottom
        ramp = height / count / slope / lap
        lead = self.lead_out(route, left, edge, distance)
        ours = pass_moves(route, share, left, radius, False, lead, depths, ramp)
        theirs = ours
        if self.control:
            programmed = self.around(edge, distance - radius)
            assert programmed is not None
            shape, shape_where, _, shape_point = programmed
            shape_along = along_centre(shape_where, len(shape.vertices), path, where)
            route, share = directed(shape, int(shape_where[k]), shape_point, clockwise,
                                    shape_along, at, lap)
            theirs = pass_moves(route, share, left, radius, True, lead, depths, ramp)
        return ours, theirs, len(depths)

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
        program.opening((f"camfab {__version__}: {stem}.ngc, design {design.name}", tool,
                         f"work zero: {zero}", f"stock: {stock}", form), settings.spindle_rpm)
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
        program.closing()
        feeds = f"{words.length(settings.plunge)}/min"
        notes = [f"each pass enters in the air {words.length(ENTRY_CLEARANCE_MM)} above the top "
                 f"face and goes round its contour once a depth: down a ramp along it (at most "
                 f"{words.length(settings.depth_step)} a lap, no steeper than {RAMP_DEG:g}°, at "
                 f"the plunge feed, {feeds}), then level; a last level lap at full depth; "
                 f"roughing leaves {words.length(settings.finish_allowance)} for finishing",
                 f"a through cut goes {words.length(self.below)} below the plate into a "
                 "spoil board; clamp the blank outside the toolpath; "
                 + ("the bore is cut first: a bolt through it holds the part when the outline "
                    "frees it; the bore's core and the outline's waste come free"
                    if self.bored else "the outline's waste comes free")
                 + " at the last laps (no tabs are left)",
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
