"""A globoidal cam's program as text: the G-code (``NAME.ngc``), the cutter locations in the
cam's frame (``NAME-cl.csv``) and the setup sheet (:mod:`camfab.machining.globoid` plans the
passes)."""

from __future__ import annotations

import io
import math
import textwrap
from typing import TYPE_CHECKING

import numpy as np

from camfab import __version__
from camfab.analysis.setup_sheet import Operation, Setup, Tool, Toolpath
from camfab.machining.globoid_path import move_minutes
from camfab.machining.rs274 import Program

if TYPE_CHECKING:
    from camfab.design import Design
    from camfab.design.machining import Machining
    from camfab.geometry.globoid_cam import GloboidCam
    from camfab.machining.globoid import Pass
    from camfab.machining.globoid_path import TableTable, Walls

#: The longest comment a block holds (characters): LinuxCNC reads lines of at most 255.
COMMENT_WIDTH = 120
#: The columns of ``NAME-cl.csv``.
CL_COLUMNS = ("pass", "move", "cam_angle_deg", "swing_deg", "tip_x_mm", "tip_y_mm", "tip_z_mm",
              "axis_x", "axis_y", "axis_z")


#: What the program's comments write for the setup sheet's letters (a program is ASCII).
_ASCII = str.maketrans({"θ": "theta", "ψ": "psi", "−": "-", "°": " deg"})


def clearance(blank: GloboidCam, table: TableTable, safe_z: float) -> float:
    """The height (mm) above which the cutter's tip clears the blank whatever A and B: the
    blank lies within a sphere about the work zero, which B turns about its axis."""
    reach = math.hypot(max(blank.outer_radius, blank.ends_radius()), blank.width / 2.0)
    return table.b_z + math.hypot(table.b_x, table.b_z) + reach + safe_z


def axes_of(passes: list[Pass]) -> str:
    """The axes the cuts drive: Y only for wall passes."""
    return "XYZAB" if any(p.side != 0 for p in passes) else "XZAB"


def work_zero(design: Design, blank: GloboidCam, table: TableTable) -> str:
    """The work zero and the axes, in words."""
    g = blank.follower
    where = "above" if table.inward > 0 else "below"
    a = "θ" if table.sigma > 0 else "−θ"
    b = "ψ" if table.inward > 0 else "−ψ"
    return (f"on the cam's axis at its middle plane (the plane of the pivot); X along the cam's "
            f"axis (the design's z), Z up, the cutter pointing down. With A = B = 0 the line "
            f"of centres stands vertical, the pivot {g.centre:.6g} mm {where} the cam's axis. "
            f"A = {a} (the cam turns {design.cam.rotation}; A turns the cam by the right-hand "
            f"rule about +X), B = {b}, the arm's swing from the line of centres (B turns A and "
            f"the cam about +Y by the right-hand rule, its axis at X {table.b_x:.6g}, "
            f"Z {table.b_z:.6g} mm)")


def program_text(design: Design, settings: Machining, blank: GloboidCam, table: TableTable,
                 passes: list[Pass]) -> bytes:
    """The RS274NGC program of *passes* (LinuxCNC; lengths in the design's units)."""
    p = Program(design.units, settings.dialect)
    zero = textwrap.wrap(f"work zero {work_zero(design, blank, table)}; a table-table "
                         "machine without tool-centre point control: X Y Z are the "
                         "cutter's tip with the tables turned".translate(_ASCII), COMMENT_WIDTH)
    p.opening((f"camfab {__version__}: {design.name}, globoidal cam ({design.cam.globoid})",
               f"T1: {settings.tool_diameter:.6g} mm flat end mill, {settings.flutes} flutes, "
               f"{settings.length_of_cut:.6g} mm length of cut", *zero), settings.spindle_rpm)
    top = clearance(blank, table, settings.safe_z)
    p.block("G0", p.word("Z", top))
    axes = axes_of(passes)
    columns = ["XYZAB".index(a) for a in axes]
    for done in passes:
        cut, above = done.cut, done.above
        turns = f"{done.turns:.4g} turn{'' if done.turns == 1 else 's'}"
        p.comment(f"{done.name}: {turns} of the cam".translate(_ASCII))
        p.block("G0", p.word("X", above.xyz[0, 0]), p.word("Y", above.xyz[0, 1]),
                p.word("A", above.a_deg[0]), p.word("B", above.b_deg[0]))
        p.block("G0", p.word("Z", above.xyz[0, 2]))
        p.block("G93")
        plunge = abs(above.xyz[0, 2] - cut.xyz[0, 2]) / settings.plunge
        p.block("G1", p.word("Z", cut.xyz[0, 2]), f"F{1.0 / max(plunge, 1e-9):.4f}")
        points = np.column_stack((cut.xyz, cut.a_deg, cut.b_deg))[:, columns]
        p.moves("G1", axes, points[1:], 1.0 / move_minutes(cut, settings.feed))
        p.block("G94")
        p.block("G0", p.word("Z", top))
    p.closing()
    return p.text()


def cl_csv(passes: list[Pass]) -> bytes:
    """The cutter's locations in the cam's frame (mm): per point of each pass its cam angle
    and the arm's swing (deg), the tip and the axis (unit, from the tip to the spindle)."""
    out = io.StringIO()
    out.write(",".join(CL_COLUMNS) + "\n")
    for number, done in enumerate(passes, start=1):
        for move, poses in (("approach", done.above), ("cut", done.cut)):
            tip, axis = poses.on_cam(poses.tip), poses.on_cam(poses.axis)
            values = np.column_stack((np.degrees(poses.theta), np.degrees(poses.psi), tip,
                                      axis))
            text = np.char.mod("%.6f", np.round(values, 6) + 0.0)
            for row in text:
                out.write(f"{number},{move}," + ",".join(row) + "\n")
    return out.getvalue().encode("ascii")


def setup_sheet(design: Design, settings: Machining, blank: GloboidCam, table: TableTable,
                passes: list[Pass], walls: Walls | None) -> Setup:
    """The setup sheet of the program."""
    g = blank.follower
    shape = "waist" if blank.inward > 0 else "crown"
    bore = f", bore {2 * blank.bore:.6g} mm" if blank.bore else ""
    stock = (f"the blank turned to its half-section (the DXF's CUT layer): {blank.outer_radius:.6g}"
             f" mm radius at its {shape}, {blank.width:.6g} mm wide{bore}")
    tool = Tool(1, "flat end mill", settings.tool_diameter, settings.flutes,
                settings.length_of_cut)
    operations = tuple(Operation(p.name, 1, settings.feed, p.minutes, math.ceil(p.turns))
                       for p in passes)
    notes = [f"The cutter's axis follows the roller's axis (ψ the arm's swing about the pivot "
             f"{g.centre:.6g} mm from the cam's axis): the groove's walls are the roller's "
             f"envelope by construction, {blank.depth:.6g} mm deep along the arm; cutter "
             f"locations in the cam's frame for another post-processor: {design.name}-cl.csv",
             "Moves that turn A and B run in inverse time (G93); X and Z make up for B's axis "
             "not passing through the pivot, so the machine must not add its own tool-centre "
             "point control",
             f"The cutter goes {blank.depth:.6g} mm into the blank along its axis: its holder "
             f"must stay clear of the blank's surface, a circle of radius "
             f"{blank.surface:.6g} mm about the pivot revolved about the cam's axis"]
    if walls is None:
        notes.append(f"One path down the middle: the cutter is the groove's width "
                     f"({2 * g.radius:.6g} mm, the roller's diameter and the clearance)")
    else:
        notes.append(f"The cutter is {2 * walls.shift:.4g} mm under the groove's width "
                     f"({2 * g.radius:.6g} mm): after the middle, a pass each side with its axis "
                     f"{walls.shift:.4g} mm off the roller's along the contact normal, which "
                     f"leaves at most {walls.left:.2g} mm on the walls")
    return Setup(f"{design.name}.ngc", stock, work_zero(design, blank, table), axes_of(passes),
                 (tool,), operations, _toolpath(passes), tuple(notes))


def _toolpath(passes: list[Pass]) -> Toolpath:
    """The swing (deg) against the cam angle (deg, over one turn) of every pass, split where
    a pass comes round."""
    pieces = []
    for done in passes:
        theta = np.mod(np.degrees(done.cut.theta), 360.0)
        points = np.column_stack((theta, np.degrees(done.cut.psi)))
        wrap = np.flatnonzero(np.abs(np.diff(theta)) > 180.0) + 1
        for piece in np.split(points, wrap):
            pieces.extend((piece, np.full((1, 2), np.nan)))
    cutting = np.concatenate(pieces[:-1]) if pieces else np.empty((0, 2))
    return Toolpath("cam angle θ (deg)", "the arm's swing ψ (deg)", cutting, np.empty((0, 2)))
