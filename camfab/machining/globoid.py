"""The machining program of a globoidal cam (concave or convex): its groove cut by a cutter
the size of the roller whose axis follows the roller's axis relative to the cam, on a
table-table machine — the cam on a rotary A axis, the arm's swing on a tilting B axis, X and Z
following the pivot round where B's axis does not pass through it (the machine and its frames:
:mod:`camfab.machining.globoid_path`; docs/machining.md, "Globoidal cams").

A cutter of the groove's width (the roller's diameter and the clearance) cuts it in one path
down the middle: its axis on the roller's, the walls are the roller's envelope by construction.
A smaller one (the roller's own diameter, say) cuts the middle, then each wall with its axis
moved off the roller's along the contact normal: how much that leaves on the walls is computed
(the normal turns along the roller), and a cutter that would leave more than a quarter of
``manufacturing.tolerance`` is refused with the smallest one that would not.

Each pass ramps down the groove in a spiral, ``step_down`` per turn, along the cutter's axis,
then turns once more at the full depth; a wall pass whose shift is within ``finish_allowance``
plunges to the full depth in the groove already cut and turns once. The program's points are
placed so that the cutter's axis, the axes interpolated linearly between them, stays within
the tolerance of the planned axis; moves that turn A and B run in inverse time (G93), each
as long as the fastest point of the cutter's edge, the tip or the blank's surface, takes at
``feed`` on the cam.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from camfab.machining import Machined
from camfab.machining.globoid_path import (
    WALL_ROWS,
    Cutter,
    Poses,
    TableTable,
    Walls,
    halved,
    move_minutes,
    revolution_stations,
    unrolled,
    wall_passes,
)
from camfab.machining.globoid_text import cl_csv, program_text, setup_sheet

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.design.machining import Machining
    from camfab.export.part import Part
    from camfab.geometry.globoid_cam import GloboidCam

#: The share of ``manufacturing.tolerance`` the cutter's axis may stray from the planned axis
#: between the program's points (the rest covers what a wall pass leaves and the rounding).
INTERPOLATION_SHARE = 0.7
#: The share of ``manufacturing.tolerance`` a cutter may leave on the walls: a cutter's radius
#: within it of the walls' cuts the groove in one path; a smaller one's wall passes must leave
#: no more.
WALL_SHARE = 0.25


@dataclass(frozen=True)
class Pass:
    """One pass of the cutter: its name, its side (0 the middle, ±1 a wall), the poses of
    its cut (the first where it enters at its first depth), the pose above the blank it
    comes down to, its time (min) at its feeds, the plunge's included, and the turns of the
    cam it takes."""

    name: str
    side: int
    cut: Poses
    above: Poses
    minutes: float
    turns: float


def machine(analysis: Analysis, part: Part, settings: Machining) -> Machined:
    """The globoidal cam's program ``NAME.ngc``, its cutter locations ``NAME-cl.csv`` and its
    setup sheet; or why none can be made (*part* is not needed: the groove is cut from its
    exact geometry)."""
    design = analysis.design
    dense = analysis.globoid
    assert dense is not None, "a globoidal cam's analysis has its groove"
    blank = dense.blank
    tolerance = design.manufacturing.tolerance
    walls, reason = _walls(analysis, blank, settings, tolerance)
    if reason is not None:
        return Machined(withheld=reason)
    g = blank.follower
    rows = np.linspace(blank.surface, blank.floor, WALL_ROWS)
    where = settings.machine
    table = TableTable(blank.inward, g.sigma, where.b_axis_x, where.b_axis_z)
    cutter = Cutter(g, analysis.program, table, blank.surface, blank.floor,
                    walls.shift if walls is not None else 0.0, rows)
    passes = plan(cutter, settings, blank.depth, walls, INTERPOLATION_SHARE * tolerance)
    name = design.name
    files = {f"{name}.ngc": program_text(design, settings, blank, table, passes),
             f"{name}-cl.csv": cl_csv(passes)}
    return Machined(files, (setup_sheet(design, settings, blank, table, passes, walls),))


def _walls(analysis: Analysis, blank: GloboidCam, settings: Machining,
           tolerance: float) -> tuple[Walls | None, str | None]:
    """The wall passes a cutter smaller than the groove needs (None: one path down the
    middle cuts it), or why no program can cut the groove with this cutter."""
    if settings.dialect != "linuxcnc":
        return None, ("a globoid's groove is cut on five axes (X, Y, Z and the rotary A and B), "
                      "which Grbl does not drive: dialect: linuxcnc")
    if any(f.id == "undercut" and not f.ok for f in analysis.findings):
        return None, ("a flank of the groove folds over itself (see the undercut check): no "
                      "cutter's path cuts a groove the roller could run in")
    g = blank.follower
    radius, share = settings.tool_radius, WALL_SHARE * tolerance
    if radius > g.radius + share:
        return None, (f"the cutter ({settings.tool_diameter:.6g} mm) is wider than the groove "
                      f"({2 * g.radius:.6g} mm): it would cut the walls away")
    if radius >= g.radius - share:
        return None, None
    rows = np.linspace(blank.surface, blank.floor, WALL_ROWS)
    walls = wall_passes(g, analysis.program, rows, radius)
    if walls.left <= share and radius >= g.radius / 3:
        return walls, None
    # (rounded up to 0.001 mm: a cutter of the size named cuts the groove)
    smallest = math.ceil(1000 * max(walls.smallest_tool(g.radius, share),
                                    2 * g.radius / 3)) / 1000
    why = (f"its wall passes would leave up to {walls.left:.3g} mm on the groove's walls (the "
           f"contact normal turns along the roller), over a quarter of the tolerance "
           f"({tolerance:g} mm)" if walls.left > share else
           "under a third of the groove's width, its passes would leave a ridge between them")
    return None, (f"a {settings.tool_diameter:.6g} mm cutter is too small for this groove: "
                  f"{why}; use a cutter of at least {smallest:.3f} mm, up to the groove's "
                  f"width, {2 * g.radius:.6g} mm (the roller's diameter and the clearance)")


def plan(cutter: Cutter, settings: Machining, depth: float, walls: Walls | None,
         target: float) -> list[Pass]:
    """The passes in order: the middle, ramping down the groove; then, with *walls*, each
    wall (climb or conventional milling as *settings* ask) — at *depth* (mm) along the arm, the
    cutter's axis within *target* (mm) of the planned axis between the points."""
    u = cutter.table.inward
    step = settings.depth_step
    passes = [_pass(cutter, "groove, down the middle", 0, 0.0, 1, depth, step, settings,
                    target)]
    if walls is None:
        return passes
    climb = 1 if settings.direction == "climb" else -1
    finishing = walls.shift <= settings.finish_allowance
    for side, label in ((1, "+"), (-1, "−")):
        start = passes[-1].cut.theta[-1]
        # climb milling turns the cam so the cutter's edge meets the wall against its feed
        direction = int(climb * side * u)
        passes.append(_pass(cutter, f"wall on the {label} side of the contact normal", side,
                            start, direction, depth, None if finishing else step, settings,
                            target))
    return passes


def _pass(cutter: Cutter, name: str, side: int, start: float, direction: int, depth: float,
          step: float | None, settings: Machining, target: float) -> Pass:
    """A pass from the cam angle *start* (rad) turning the cam *direction* (+1: θ grows):
    ramping down *step* (mm) a turn from the blank's surface to *depth* (mm) and turning once
    more there, or (*step* None) turning once at *depth*."""
    ramp = 2 * math.pi * depth / step if step is not None else 0.0
    span = ramp + 2 * math.pi
    end = start + direction * span
    stations = revolution_stations(cutter, side, target)
    theta = unrolled(stations, start, end, np.array([start + direction * ramp]))
    ascending = theta if direction > 0 else theta[::-1]
    ascending = halved(ascending, lambda t: cutter.stray(t, side), target)
    theta = ascending if direction > 0 else ascending[::-1]
    turned = np.abs(theta - start)
    down = (np.minimum(depth, step * turned / (2 * math.pi)) if step is not None
            else np.full(theta.size, depth))
    cut = cutter.poses(theta, down, side)
    above = cutter.poses(theta[:1], np.array([-settings.safe_z]), side)
    minutes = float(np.sum(move_minutes(cut, settings.feed)))
    minutes += (float(down[0]) + settings.safe_z) / settings.plunge
    return Pass(name, side, cut, above, minutes, span / (2 * math.pi))

