"""Setup sheets as the machining program writers make them, built here from an example design's
exact geometry, for the tests of the report's side: a plate's outline toolpath in plan view
(depth passes round the profile at one tool radius, a lead-in, the bore by a helix, rapids
between), a drum's unrolled groove (cam angle against the axial position, a pass down the middle
at each depth), a globoid's swing against the cam angle."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from camfab.analysis.record import Analysis
from camfab.analysis.setup_sheet import Operation, Setup, Tool, Toolpath
from camfab.pipeline import analyse, load_design

from .conftest import DESIGNS

GAP = np.full((1, 2), np.nan)


def joined(*pieces: np.ndarray) -> np.ndarray:
    """Pieces of path (each (N, 2)) one after the other, a row of NaN between them."""
    out: list[np.ndarray] = []
    for piece in pieces:
        out += [piece, GAP]
    return np.vstack(out[:-1])


def plate_setup(analysis: Analysis, tool_diameter: float = 6.0) -> Setup:
    """A plate's program: the profile in three depth passes and a finishing pass, the bore."""
    geom = analysis.geometry or analysis.linear  # (a linear cam's plate)
    outline = geom.outline_points()
    # the tool's centre one tool radius outside the outline (its normals from the chords)
    step = np.roll(outline, -1, axis=0) - np.roll(outline, 1, axis=0)
    normal = np.column_stack((step[:, 1], -step[:, 0])) / np.hypot(*step.T)[:, None]
    x, y = outline.T
    if np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)) < 0:  # clockwise: turned out
        normal = -normal
    centre = outline + tool_diameter / 2.0 * normal
    centre = np.vstack((centre, centre[:1]))
    bore = analysis.design.cam.bore or 10.0
    t = np.linspace(0.0, 2.0 * math.pi, 90)
    helix = np.column_stack(((bore - tool_diameter) / 2.0 * np.cos(t),
                             (bore - tool_diameter) / 2.0 * np.sin(t)))
    start = centre[0] + 3.0 * tool_diameter * normal[0]
    lead = np.vstack((start, centre[0]))
    rapid = joined(np.vstack((helix[-1], start)), np.vstack((centre[-1], helix[0])))
    length = float(np.sum(np.hypot(*np.diff(centre, axis=0).T)))
    feed = 600.0
    passes = 3
    ops = (Operation("profile, roughing in depth passes", 1, feed, passes * length / feed,
                     passes),
           Operation("profile, finishing at full depth", 1, feed, length / feed),
           Operation("bore, helical", 1, 200.0, 4 * math.pi * bore / 2.0 / 200.0, 4))
    return Setup(file=f"{analysis.design.name}.ngc",
                 stock="a plate 130 × 130 × 10 mm, faced both sides, bored 8 mm",
                 work_zero="X0 Y0 on the bore's axis, Z0 on the top face; X and Y as in the "
                           "DXF, Z up",
                 axes="XYZ",
                 tools=(Tool(1, "flat end mill", tool_diameter, 2, 18.0),),
                 operations=ops,
                 toolpath=Toolpath("X (mm)", "Y (mm)", joined(lead, centre, helix), rapid),
                 notes=("clamp the plate through its bore; the profile is cut climb",))


def drum_setup(analysis: Analysis) -> Setup:
    """A drum's program: a pass down the groove's middle at each of four depths, unrolled."""
    theta = np.radians(np.arange(0.0, 360.5, 0.5))
    geometry = analysis.result.report_geometry(analysis)
    axial = geometry["groove_start_mm"] + analysis.program.evaluate(theta)[0]
    one = np.column_stack((np.degrees(theta), axial))
    back = np.vstack((one[-1], one[0]))
    return Setup(file=f"{analysis.design.name}.ngc",
                 stock="a bored cylinder ⌀100 × 70 mm on a mandrel",
                 work_zero="X0 on the drum's face at axial position 0, on its axis; A0 at cam "
                           "angle 0 (A = θ, ccw); Z0 on the axis, Z radial",
                 axes="XZA",
                 tools=(Tool(1, "flat end mill", 12.0, 3, 30.0),
                        Tool(2, "flat end mill", 8.0, 2, 20.0)),
                 operations=(Operation("groove, roughing down the middle", 2, 400.0, 6.25, 4),
                             Operation("groove walls, roller-diameter tool", 1, 300.0, 3.5, 2)),
                 toolpath=Toolpath("cam angle A (deg)", "X, along the drum's axis (mm)",
                                   joined(one, one, one), joined(back, back)),
                 notes=("the walls a smaller tool leaves: 0.004 mm at most",
                        "moves that turn A are fed in inverse time (G93)"))


def globoid_setup(analysis: Analysis) -> Setup:
    """A globoid's program: the cutter on the turret's swing, over two depth passes."""
    theta = np.radians(np.arange(0.0, 360.5, 0.5))
    geometry = analysis.result.report_geometry(analysis)
    swing = geometry["rest_angle_deg"] + np.degrees(analysis.program.evaluate(theta)[0])
    one = np.column_stack((np.degrees(theta), swing))
    return Setup(file=f"{analysis.design.name}.ngc",
                 stock="the blank turned to its hourglass, bored 30 mm",
                 work_zero="the cam's centre: on its axis, halfway across its width",
                 axes="XZAB",
                 tools=(Tool(1, "flat end mill, the roller's size", 16.0, 3, 24.0),),
                 operations=(Operation("groove, in two depth passes", 1, 250.0, 11.0, 2),),
                 toolpath=Toolpath("cam angle A (deg)", "swing B (deg)", joined(one, one),
                                   joined(np.vstack((one[-1], one[0])))))


def with_setups(name: str, *make: object) -> Analysis:
    """The example design *name* analysed, with the setups *make* (functions of the analysis)
    as its machining programs."""
    analysis = analyse(load_design(DESIGNS / f"{name}.yaml"))
    return replace(analysis, machining=tuple(m(analysis) for m in make))  # type: ignore[operator]
