"""Plate cams' machining programs, run by LinuxCNC's interpreter (``rs274``) and measured from
the moves it makes against the exact part, not against camfab's own toolpath.

Each design is an example with a ``machining:`` section added, built through the pipeline.
The exact part is drawn from the design's own evaluators, sampled densely (the working curve
at cam angles a few hundredths of a millimetre apart; the bore and keyway from their sizes),
and from the moves rs274 made (after its own cutter compensation) the tests measure:

- no gouge: every tool centre below the top face stays at least a tool radius (less the
  tolerance) from the part and outside it;
- nothing left: every point of the part's edge lies within a tool radius (plus the tolerance)
  of a tool centre at full depth whose distance from the part is the radius within the
  tolerance (the finishing pass), and within the radius plus the allowance of a roughing one;
- a program for the control's compensation (G41/G42) and one carrying the tool centre's path
  make the same moves; Grbl's program too;
- the bore by helical moves about the cam centre, a groove's walls, a tool too large refused
  with where.
"""

from __future__ import annotations

import math
import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import shapely
from scipy.spatial import cKDTree

from camfab.pipeline import analyse, design_from_text, render

from .conftest import DESIGNS
from .rs274 import MM_PER_IN, Moves, interpret, parse

#: rs274's moves are sampled this finely (mm): a sample's distance from a point one tool
#: radius away differs from the move's by under a hundred-thousandth of a millimetre.
STEP = 0.02
#: The part's exact edges are sampled this finely (mm) for the nearest-point searches.
EDGE_STEP = 0.02
#: A program writes 0.1 µm (mm) or 0.01 thou (in), and rs274 prints its moves to four decimals
#: of the program's unit: each coordinate read back is off by up to half of each (mm).
ROUNDING = {"mm": (0.5e-4 + 0.5e-4) * math.sqrt(2),
            "in": (0.5e-5 + 0.5e-4) * MM_PER_IN * math.sqrt(2)}


def build(name: str, machining: str, edit: tuple[str, str] | None = None):  # type: ignore[no-untyped-def]
    """The example *name* built with the ``machining:`` section *machining* (flow YAML) and
    ``outputs: [gcode]``; *edit* replaces a line of its text first."""
    text = (DESIGNS / f"{name}.yaml").read_text()
    if edit is not None:
        assert edit[0] in text
        text = text.replace(*edit)
    text += f"\nmachining: {machining}\noutputs: [gcode]\n"
    analysis = analyse(design_from_text(text), advice=False)
    artifacts = render(analysis)
    assert artifacts.analysis is not None
    return artifacts


def run(artifacts, stem: str, tmp_path: Path) -> dict[str, Moves]:  # type: ignore[no-untyped-def]
    """rs274's moves of *stem*'s program (mm), whole (``""``) and by operation: the moves after
    the comment naming each operation of the setup sheet, up to the next."""
    design = artifacts.analysis.design
    units = design.units
    diameter = design.machining.tool_diameter / design.mm_per_unit
    whole = interpret(artifacts.files[f"{stem}.ngc"], {1: diameter}, tmp_path / stem, units)
    setup = next(s for s in artifacts.analysis.machining if s.file == f"{stem}.ngc")
    names = {op.name for op in setup.operations}
    chunks: dict[str, list[str]] = {"": []}
    name = ""
    for line in whole.canon.splitlines():
        said = re.search(r'COMMENT\("(.*)"\)', line)
        if said and said[1] in names:
            name = said[1]
            chunks[name] = []
        chunks[name].append(line)
    out = {"": whole, **{k: parse("\n".join(v)) for k, v in chunks.items() if k}}
    assert set(out) == names | {""}
    return {k: in_mm(v, units) for k, v in out.items()}


def in_mm(moves: Moves, units: str) -> Moves:
    if units == "mm":
        return moves
    scale = np.array([MM_PER_IN] * 3 + [1.0] * 3)
    return replace(moves, start=moves.start * scale, end=moves.end * scale,
                   centre=moves.centre * MM_PER_IN, feed=moves.feed * MM_PER_IN)


def below(moves: Moves) -> np.ndarray:
    """The tool centre (K, 3) along every feed and arc move (mm), every :data:`STEP`, where it
    is below the top face."""
    points = moves.cutting().sample(STEP)[:, :3]
    return points[points[:, 2] < -1e-6]


def polyline_distance(points: np.ndarray, line: np.ndarray, gap: float = math.inf
                      ) -> np.ndarray:
    """The distance of each of *points* from the open polyline through *line* (same
    dimension), its segments longer than *gap* (between pieces) left out; for points near it
    (the search looks at the segments either side of the nearest few vertices)."""
    line = line[np.concatenate(([True], np.linalg.norm(np.diff(line, axis=0), axis=1) > 1e-9))]
    _, nearest = cKDTree(line).query(points, k=min(6, len(line)))
    best = np.full(len(points), np.inf)
    for a_index in (*(nearest - 1).T, *nearest.T):
        ok = (a_index >= 0) & (a_index + 1 < len(line))
        a = line[np.clip(a_index, 0, len(line) - 1)]
        d = line[np.clip(a_index + 1, 0, len(line) - 1)] - a
        length2 = np.einsum("ij,ij->i", d, d)
        ok &= length2 <= gap * gap
        t = np.clip(np.einsum("ij,ij->i", points - a, d) / np.where(length2 > 0, length2, 1.0),
                    0.0, 1.0)
        dist = np.linalg.norm(points - (a + t[:, None] * d), axis=1)
        best = np.where(ok, np.minimum(best, dist), best)
    return best


def dense_closed(xy: np.ndarray) -> np.ndarray:
    """A closed chain of points (mm) with more put in where two lie over :data:`EDGE_STEP`
    apart (straight between them: for chains already within a micrometre of the curve), its
    first point again at its end."""
    following = np.roll(xy, -1, axis=0)
    count = np.maximum(1, np.ceil(np.hypot(*(following - xy).T) / EDGE_STEP)).astype(int)
    pieces = [a + np.linspace(0.0, 1.0, n, endpoint=False)[:, None] * (b - a)
              for a, b, n in zip(xy, following, count, strict=True)]
    return np.concatenate((*pieces, xy[:1]))


def exact_working(cam, program, move=None) -> np.ndarray:  # type: ignore[no-untyped-def]
    """A plate's exact working curve (mm) over a turn, its points :data:`EDGE_STEP` apart or
    closer: the cam's own evaluator at cam angles fine enough for that (moved into the frame
    the plate is made in by *move*)."""
    theta = np.linspace(0.0, 2 * math.pi, 4000, endpoint=False)
    xy = cam.working(theta, program.evaluate(theta)).xy
    length = float(np.sum(np.hypot(*np.diff(xy, axis=0).T)))
    theta = np.linspace(0.0, 2 * math.pi, int(length / EDGE_STEP * 1.5), endpoint=False)
    xy = cam.working(theta, program.evaluate(theta)).xy
    return xy if move is None else move(xy)


def circle_points(radius: float) -> np.ndarray:
    angle = np.linspace(0.0, 2 * math.pi, max(64, int(2 * math.pi * radius / EDGE_STEP)),
                        endpoint=False)
    return radius * np.stack((np.cos(angle), np.sin(angle)), axis=-1)


def keyed_bore(diameter: float, width: float, depth: float) -> np.ndarray:
    """The bore with its keyway on +Y, from their sizes (mm), as a closed chain."""
    r, half = diameter / 2, width / 2
    foot = math.sqrt(r * r - half * half)
    top = r + depth
    left, right = math.atan2(foot, -half), math.atan2(foot, half) + 2 * math.pi
    angle = np.linspace(left, right, int(2 * math.pi * r / EDGE_STEP))[1:-1]
    arc = np.stack((r * np.cos(angle), r * np.sin(angle)), -1)
    return dense_closed(np.vstack(([[half, foot], [half, top], [-half, top], [-half, foot]],
                                   arc)))


def check_pass(points: np.ndarray, edge: np.ndarray, distance: float, tol: float,
               floor: float | None = None, corners: np.ndarray | None = None) -> None:
    """The tool centres *points* (K, 3) of one operation along the exact *edge* (mm): none
    nearer it than *distance* less *tol* (no gouge, nothing of the allowance taken); at the
    operation's full depth (z = *floor*, by default its lowest) one within *distance* plus
    *tol* of every point of the edge (nothing left) — but within *distance* of its inside
    *corners* (K, 2), which a round tool leaves round. (The nearest points between the edge and
    the moves, both sampled within a few hundredths of a millimetre: each is off the exact
    nearest distance by under 2·10⁻⁵ mm.)"""
    gap, _ = cKDTree(points[:, :2]).query(edge)
    assert gap.min() >= distance - tol, f"{distance - gap.min():.4g} mm too near the part"
    floor = points[:, 2].min() if floor is None else floor
    deep = points[np.abs(points[:, 2] - floor) < 1e-6]
    if corners is not None:
        edge = edge[cKDTree(corners).query(edge)[0] > distance]
    reach, _ = cKDTree(deep[:, :2]).query(edge)
    assert reach.max() <= distance + tol, (
        f"material left {reach.max() - distance:.4g} mm over {distance:.4g} mm")


def outside(points: np.ndarray, outline: np.ndarray, holes: list[np.ndarray]) -> bool:
    """Whether every point (K, 2) lies off the plate: outside the outline or in a hole."""
    plate = shapely.Polygon(outline, holes)
    shapely.prepare(plate)
    return not np.any(shapely.contains_xy(plate, points[:, 0], points[:, 1]))


def check_plate(artifacts, stem: str, tmp_path: Path, outline: np.ndarray,  # type: ignore[no-untyped-def]
                holes: list[tuple[str, np.ndarray]], corners: np.ndarray | None = None
                ) -> dict[str, Moves]:
    """A through plate's program cuts it (its *outline* and named *holes* exact, mm): every
    tool centre below the top face off the plate; each contour roughed the allowance off it and
    finished on it, through the plate; the holes by helical moves about the cam centre; the
    time on the setup sheet that of rs274's feed moves at their feeds."""
    design = artifacts.analysis.design
    settings = design.machining
    radius, allowance = settings.tool_radius, settings.finish_allowance
    tol = design.manufacturing.tolerance + ROUNDING[design.units]
    moves = run(artifacts, stem, tmp_path)
    assert outside(below(moves[""])[:, :2], outline, [hole for _, hole in holes])
    bottom = -(design.cam.thickness + 0.5)
    for name, edge in (*holes, ("the outline", outline)):
        for step, distance in (("roughing", radius + allowance), ("finishing", radius)):
            points = below(moves[f"{name}: {step}"])
            assert points[:, 2].min() == pytest.approx(bottom, abs=ROUNDING[design.units])
            check_pass(points, edge, distance, tol, corners=corners if holes else None)
    if holes:  # helical moves about the cam centre
        arcs = moves[""].cutting()
        helix = ((arcs.kind == "arc") & (np.hypot(*arcs.centre.T) < 1e-6)
                 & (arcs.end[:, 2] < arcs.start[:, 2] - 1e-6))
        assert helix.sum() >= 3
    setup = next(s for s in artifacts.analysis.machining if s.file == f"{stem}.ngc")
    assert setup.minutes == pytest.approx(feed_minutes(moves[""]), rel=1e-3)
    # ramps, no plunge (the rounding of a small drop's ends allowed for), at the plunge feed
    assert steepest_descent_deg(moves[""]) <= 3.0 + 0.1
    cut = moves[""].cutting()
    down = (cut.end[:, 2] < cut.start[:, 2] - 1e-9) & (cut.end[:, 2] < 0.0)
    assert np.allclose(cut.feed[down], settings.plunge, rtol=1e-4)
    return moves


def plan_lengths(cut: Moves) -> np.ndarray:
    """The length (mm) of each of rs274's moves in plan (XY): a line's chord, an arc's
    radius times its sweep."""
    length = np.hypot(*(cut.end[:, :2] - cut.start[:, :2]).T)
    arc = cut.kind == "arc"
    a, b, c = cut.start[arc, :2], cut.end[arc, :2], cut.centre[arc]
    turn = cut.turn[arc]
    t0 = np.arctan2(*(a - c).T[::-1])
    t1 = np.arctan2(*(b - c).T[::-1])
    sweep = np.where(turn > 0, np.mod(t1 - t0, 2 * np.pi), np.mod(t0 - t1, 2 * np.pi))
    sweep = np.where(sweep < 1e-12, 2 * np.pi, sweep) + 2 * np.pi * (np.abs(turn) - 1)
    length[arc] = np.hypot(*(a - c).T) * sweep
    return length


def feed_minutes(moves: Moves) -> float:
    """The time (min) of rs274's feed and arc moves (mm) at its feed rates (mm/min)."""
    cut = moves.cutting()
    length = np.hypot(plan_lengths(cut), cut.end[:, 2] - cut.start[:, 2])
    return float(np.sum(length / cut.feed))


def steepest_descent_deg(moves: Moves) -> float:
    """The steepest (deg) any feed move descends below the top face: 90 for a plunge."""
    cut = moves.cutting()
    drop = cut.start[:, 2] - cut.end[:, 2]
    into = (drop > 1e-9) & (cut.end[:, 2] < -1e-9)
    return float(np.degrees(np.arctan2(drop[into], plan_lengths(cut)[into])).max())


def same_path(a: Moves, b: Moves, tol: float) -> None:
    """The tool centre's moves below the top face of *a* and *b* are one path, within
    *tol* (mm) both ways."""
    pa, pb = below(a), below(b)
    assert polyline_distance(pa, pb, gap=3 * STEP).max() <= tol
    assert polyline_distance(pb, pa, gap=3 * STEP).max() <= tol


# ---- the plates ------------------------------------------------------------------------------

def test_disc_roller_keyed_bore_control_and_path_and_grbl(tmp_path: Path) -> None:
    """Seed 10.4 (offset roller) with a keyed bore and a 3 mm tool that fits the keyway: the
    control's compensation, the tool centre's path and Grbl's program cut the same part."""
    edit = ("  bore: 10", "  bore: 10\n  keyway: {width: 4, depth: 1.4}")
    common = "tool_diameter: 3, cut_length: 12, feed: 500"
    control = build("seed-10-4", f"{{{common}}}", edit)
    design = control.analysis.design
    outline = exact_working(control.analysis.geometry.cam, design.program)
    holes = [("the bore and its keyway", keyed_bore(10.0, 4.0, 1.4))]
    corners = np.array([[-2.0, 6.4], [2.0, 6.4]])  # the keyway's far corners
    moves = check_plate(control, "seed-10-4", tmp_path / "control", outline, holes, corners)
    program = control.files["seed-10-4.ngc"].decode()
    assert "G41 D1" in program and "T1 M6" in program and "G43 H1" in program
    path = build("seed-10-4", f"{{{common}, compensation: path}}", edit)
    assert not re.search(r"G4[12]\b", path.files["seed-10-4.ngc"].decode())
    path_moves = check_plate(path, "seed-10-4", tmp_path / "path", outline, holes, corners)
    same_path(moves[""], path_moves[""], design.manufacturing.tolerance)
    grbl = build("seed-10-4", f"{{{common}, compensation: path, dialect: grbl}}", edit)
    assert not re.search(r"G4[1239]|G80|M6|\bT1", grbl.files["seed-10-4.ngc"].decode())
    grbl_moves = run(grbl, "seed-10-4", tmp_path / "grbl")[""]
    assert np.allclose(grbl_moves.cutting().end, path_moves[""].cutting().end, atol=1e-9)
    setup = control.analysis.machining[0]
    assert "keyway" in " ".join(setup.notes) and setup.axes == "XYZ"
    assert setup.tools[0].diameter_mm == 3.0 and setup.toolpath is not None


def test_disc_knife_conventional(tmp_path: Path) -> None:
    """A knife's plate (clockwise cam, round bore) cut conventionally: G42, the outline's laps
    counter-clockwise (climb would be clockwise with the spindle turning clockwise)."""
    built = build("demo-cnc-cutter", "{tool_diameter: 6, feed: 600, direction: conventional}")
    design = built.analysis.design
    assert "G42 D1" in built.files["demo-cnc-cutter.ngc"].decode()
    moves = check_plate(built, "demo-cnc-cutter", tmp_path,
                        exact_working(built.analysis.geometry.cam, design.program),
                        [("the bore", circle_points(8.0))])
    for name, turning in (("the outline: finishing", 1), ("the bore: finishing", -1)):
        cut = moves[name].cutting()
        deep = (cut.kind == "arc") & (cut.end[:, 2] < -1.0)
        assert np.mean(np.sign(cut.turn[deep]) == turning) > 0.9


def test_inch_design_keyway_wider_than_the_tool(tmp_path: Path) -> None:
    """An inch design (G20, a flat-faced follower): a ¼ in tool is wider than its ⅛ in keyway,
    which the setup sheet says is cut otherwise; the bore is cut round."""
    built = build("demo-inch-flat", "{tool_diameter: 0.25, cut_length: 0.75, feed: 20}")
    design = built.analysis.design
    assert "\nG20\n" in built.files["demo-inch-flat.ngc"].decode()
    setup = built.analysis.machining[0]
    assert any("keyway" in note and "not cut" in note for note in setup.notes)
    check_plate(built, "demo-inch-flat", tmp_path,
                exact_working(built.analysis.geometry.cam, design.program),
                [("the bore", circle_points(0.25 * MM_PER_IN))])


def test_conjugate_pair_one_program_per_plate(tmp_path: Path) -> None:
    """A conjugate pair: ``NAME-a.ngc`` and ``NAME-b.ngc``, each cutting its own plate (cam b
    as it is made, half a turn round), the keyway in both."""
    from camfab.geometry.conjugate import half_turned

    built = build("demo-conjugate", "{tool_diameter: 4, cut_length: 12, feed: 600}")
    analysis = built.analysis
    assert sorted(built.files) == ["demo-conjugate-a.ngc", "demo-conjugate-b.ngc"]
    partner = analysis.partner
    holes = [("the bore and its keyway", keyed_bore(16.0, 5.0, 2.3))]
    corners = np.array([[-2.5, 10.3], [2.5, 10.3]])
    check_plate(built, "demo-conjugate-a", tmp_path,
                exact_working(analysis.geometry.cam, analysis.design.program), holes, corners)
    check_plate(built, "demo-conjugate-b", tmp_path,
                exact_working(partner.geometry.cam, partner.program, half_turned), holes,
                corners)


def test_constant_breadth(tmp_path: Path) -> None:
    built = build("demo-constant-breadth", "{tool_diameter: 6, feed: 600, step_down: 2}")
    check_plate(built, "demo-constant-breadth", tmp_path,
                exact_working(built.analysis.geometry.cam, built.analysis.design.program),
                [("the bore", circle_points(6.0))])


def test_circular_arc_against_its_exact_arcs(tmp_path: Path) -> None:
    """A circular-arc cam: its outline is exact arcs, the shape's own; the program's moves are
    measured against them."""
    built = build("seed-7-10-circular-arc", "{tool_diameter: 6, feed: 600}")
    design = built.analysis.design
    outline = design.shape.profile(design.cam.sigma).points(1e-6)
    check_plate(built, "seed-7-10-circular-arc", tmp_path, dense_closed(outline),
                [("the bore", circle_points(6.0))])


def test_tangent_cam_cut_by_a_laser_is_milled_to_the_part(tmp_path: Path) -> None:
    """A tangent cam whose design has a laser's kerf: its CUT contours lie kerf/2 off the part,
    but the mill cuts the part itself, its keyway too (a 4 mm tool in a 6 mm keyway)."""
    built = build("demo-tangent-roller", "{tool_diameter: 4, cut_length: 12, feed: 600}")
    design = built.analysis.design
    assert design.manufacturing.kerf > 0.0
    outline = design.shape.profile(design.cam.sigma).points(1e-6)
    check_plate(built, "demo-tangent-roller", tmp_path, dense_closed(outline),
                [("the bore and its keyway", keyed_bore(20.0, 6.0, 2.8))],
                np.array([[-3.0, 12.8], [3.0, 12.8]]))


def test_linear_cam(tmp_path: Path) -> None:
    """A linear cam's plate: its working curve over the plate's length and its square ends and
    base line, from the evaluators and the plate's size; work zero as in its DXF."""
    built = build("demo-linear-roller", "{tool_diameter: 6, feed: 600}")
    analysis = built.analysis
    geom, design = analysis.linear, analysis.design
    cam = geom.cam
    left, right = -cam.overhang, cam.stroke + cam.overhang
    x = np.linspace(left - cam.radius, right + cam.radius, 40_000)
    working = cam.working(x, design.program.evaluate(x * cam.k)).xy
    ends = np.interp([right, left], working[:, 0], working[:, 1])
    working = working[(working[:, 0] > left) & (working[:, 0] < right)][::-1]
    outline = dense_closed(np.vstack(([left, 0.0], [right, 0.0], [right, ends[0]], working,
                                      [left, ends[1]])))
    check_plate(built, "demo-linear-roller", tmp_path, outline, [])
    assert "rectangular blank" in analysis.machining[0].stock


def test_groove_plate_centre_pass_and_both_walls(tmp_path: Path) -> None:
    """A groove plate with a 6 mm tool in its 16.1 mm groove: a pass down the middle, on the
    exact pitch curve; roughing out to the allowance off each wall; each wall finished, the
    tool touching it everywhere at the groove's floor and never nearer; the rim through the
    plate, the bore by a helix."""
    built = build("demo-groove-roller", "{tool_diameter: 6, feed: 600, compensation: path}")
    analysis = built.analysis
    design, geom, walls = analysis.design, analysis.geometry, analysis.groove
    settings = design.machining
    radius, allowance = settings.tool_radius, settings.finish_allowance
    tol = design.manufacturing.tolerance + ROUNDING["mm"]
    moves = run(built, "demo-groove-roller", tmp_path)
    theta = np.linspace(0.0, 2 * math.pi, 60_000, endpoint=False)
    pitch = geom.cam.pitch(theta, design.program.evaluate(theta))
    normal = np.stack((-pitch.tangent[:, 1], pitch.tangent[:, 0]), axis=-1)
    inner, outer = (pitch.xy - walls.radius * normal, pitch.xy + walls.radius * normal)
    if np.hypot(*inner.T).mean() > np.hypot(*outer.T).mean():
        inner, outer = outer, inner
    floor = -walls.depth
    middle = below(moves["the groove: its middle"])
    assert middle[:, 2].min() == pytest.approx(floor, abs=1e-6)
    deep = middle[np.abs(middle[:, 2] - floor) < 1e-6]
    # a lap along the pitch curve at the floor, all round
    miss = polyline_distance(pitch.xy, deep[:, :2], gap=3 * STEP)
    assert miss.max() <= tol, (miss.max(), pitch.xy[np.argmax(miss)])
    roughing = below(moves["the groove: roughing out to its walls"])
    for wall, name in ((inner, "the groove's inner wall"), (outer, "the groove's outer wall")):
        check_pass(roughing, wall, radius + allowance, tol, floor)
        check_pass(below(moves[f"{name}: finishing"]), wall, radius, tol, floor)
    every = below(moves[""])
    groove = every[np.hypot(*every[:, :2].T) < walls.outer_radius]
    assert groove[:, 2].min() >= floor - 1e-6 or np.all(
        np.hypot(*groove[groove[:, 2] < floor - 1e-6, :2].T) < design.cam.bore / 2)
    rim = below(moves["the outline: finishing"])
    assert rim[:, 2].min() == pytest.approx(-(walls.thickness + 0.5), abs=1e-6)
    check_pass(rim, circle_points(walls.outer_radius), radius, tol)
    check_pass(below(moves["the bore: finishing"]), circle_points(design.cam.bore / 2), radius,
               tol)


def test_tool_wider_than_a_hollow_is_refused_with_where(tmp_path: Path) -> None:
    """A knife with uniform-velocity rise and return has sharp hollows where they start and
    end (0° and 300°): no tool cuts them, and no program is written; the refusal says where."""
    text = """\
name: knife-hollow
cam: {type: disc, base_radius: 40, rotation: ccw, thickness: 8, bore: 12}
follower: {type: knife}
motion:
  - rise: {angle: 120, lift: 20, law: uniform-velocity}
  - dwell: {angle: 60}
  - return: {angle: 120, law: uniform-velocity}
  - dwell: {angle: 60}
machining: {tool_diameter: 6, feed: 600}
outputs: [gcode]
"""
    reason = refusal(render(analyse(design_from_text(text), advice=False)))
    angles = [float(a) for a in re.findall(r"(\d+(?:\.\d+)?)°", reason)]
    assert any(a < 1 or a > 359 for a in angles) and any(abs(a - 300) < 1 for a in angles)


def test_tool_wider_than_a_concave_stretch_is_refused_with_where() -> None:
    """Seed 10.4's profile is concave down to a radius of about 22 mm near the end of its
    return (255°–260°): a 60 mm tool does not fit there."""
    built = build("seed-10-4", "{tool_diameter: 60, cut_length: 60, feed: 600}",
                  ("  bore: 10", ""))
    reason = refusal(built)
    assert "concave" in reason
    angles = [float(a) for a in re.findall(r"(\d+(?:\.\d+)?)°", reason)]
    assert angles and all(250 < a < 262 for a in angles)


def refusal(artifacts) -> str:  # type: ignore[no-untyped-def]
    """Why no program was written (and none was)."""
    assert not any(name.endswith(".ngc") for name in artifacts.files)
    (reason,) = [n for n in artifacts.not_produced if n.startswith("gcode")]
    return reason


def test_a_tool_as_wide_as_the_bore_is_refused() -> None:
    """A tool as wide as the bore cannot cut it by helical interpolation: no program, and
    why."""
    reason = refusal(build("seed-10-4", "{tool_diameter: 10, cut_length: 40, feed: 600}"))
    assert "does not fit the bore" in reason
