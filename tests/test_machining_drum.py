"""A drum cam's machining program, run by LinuxCNC's interpreter and measured against the
exact groove.

The reference is the roller's envelope computed here from the motion program alone: at radius
r and polar angle ϕ of the cam frame the groove holds the roller at every cam angle θ, whose
axis is the radial line at polar angle −σθ and axial position start + s(θ) (THEORY §C), so the
groove's upper wall there is the largest of z_c(θ) + √(R² − r² sin²(ϕ + σθ)) over θ and its lower
wall the least of z_c(θ) − √(…). The walls cut are the same sum over the tool's positions rs274
moved through (sampled between the program's points as the interpreter interpolates them): the
tool's axis at polar angle −A, axial position X, its flat end at Z from the drum's axis, so a
point there at height r cos(ϕ + A) below the tip is not reached.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np
import pytest

from camfab.design.loader import design_from_text
from camfab.machining import Machined, machine
from camfab.pipeline import analyse

from . import rs274

ROOT = Path(__file__).resolve().parents[1]

SMALL = """\
name: small-drum
cam:
  type: cylindrical
  rotation: cw
  speed_rpm: 100
  radius: 20
  length: 36
  groove_depth: 5
follower:
  type: roller
  roller_radius: 4
motion:
  - rise:   {angle: 140, lift: 10, law: cycloidal}
  - dwell:  {angle: 40}
  - return: {angle: 140, law: cycloidal}
  - dwell:  {angle: 40}
manufacturing:
  tolerance: 0.005
"""

#: Polar angles (rad) and radii at which the walls are compared: every 0.5° round the drum,
#: at the floor, the surface and between.
PHI_STEP = math.radians(0.5)
ROWS = 5


def _built(text: str, machining: str) -> tuple[object, Machined]:
    from camfab.kinds import kind_of

    design = design_from_text(text + "machining:\n" + machining, "design.yaml")
    analysis = analyse(design, advice=False)
    part = kind_of(design.cam.type).part(analysis)
    return analysis, machine(analysis, part)


def _demo() -> str:
    return (ROOT / "designs" / "demo-cylindrical.yaml").read_text()


def _envelope(centre: np.ndarray, axis: np.ndarray, reach: float, base: np.ndarray | float,
              r: np.ndarray, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The lowest and highest axial positions (mm) that cylinders of radius *reach* round the
    radial lines at polar angles *axis* (rad) and axial positions *centre* (mm), each from
    *base* (mm from the drum's axis) out, hold at each radius *r* and polar angle *phi*."""
    order = np.argsort(np.mod(axis, 2 * np.pi))
    axis, centre = np.mod(axis, 2 * np.pi)[order], centre[order]
    base = np.broadcast_to(np.asarray(base, dtype=float), order.shape)[order]
    extended = np.concatenate((axis - 2 * np.pi, axis, axis + 2 * np.pi))
    n = axis.size
    low, high = np.full(r.size, np.inf), np.full(r.size, -np.inf)
    half = math.asin(min(1.0, reach / float(r.min())))
    first = np.searchsorted(extended, phi - half)
    last = np.searchsorted(extended, phi + half, side="right")
    width = int((last - first).max())
    for start in range(0, r.size, max(1, 3_000_000 // width)):
        rows = slice(start, start + max(1, 3_000_000 // width))
        index = first[rows, None] + np.arange(width)
        inside = index < last[rows, None]
        index = np.minimum(index, extended.size - 1)
        delta = phi[rows, None] - extended[index]
        across = r[rows, None] * np.sin(delta)
        held = inside & (np.abs(across) <= reach) & (r[rows, None] * np.cos(delta)
                                                     >= base[index % n] - 1e-9)
        half_chord = np.sqrt(np.maximum(reach * reach - across * across, 0.0))
        z = centre[index % n]
        high[rows] = np.where(held, z + half_chord, -np.inf).max(axis=1)
        low[rows] = np.where(held, z - half_chord, np.inf).min(axis=1)
    return low, high


def _points(radius: float, root: float) -> tuple[np.ndarray, np.ndarray]:
    phi = np.arange(0.0, 2 * np.pi, PHI_STEP)
    rows = np.linspace(root, radius, ROWS)
    return (np.repeat(rows, phi.size), np.tile(phi, rows.size))


def _exact(analysis: object, r: np.ndarray, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The exact walls at (*r*, *phi*): the roller's envelope, every 0.01° of cam angle."""
    design = analysis.design  # type: ignore[attr-defined]
    cam, fol = design.cam, design.follower
    roller = fol.roller_radius + fol.groove_clearance / 2
    start = cam.groove_start if cam.groove_start is not None else (
        (cam.length - design.program.max_lift) / 2)
    theta = np.arange(0.0, 2 * np.pi, math.radians(0.01))
    lift = design.program.evaluate(theta)[0]
    return _envelope(start + lift, -cam.sigma * theta, roller, -np.inf, r, phi)


def _cut(moves: rs274.Moves, tool: float, r: np.ndarray,
         phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The walls the tool of diameter *tool* cuts along rs274's feed moves, sampled every
    0.02 mm and 0.02°."""
    sampled = moves.cutting().sample(0.02, 0.02)
    return _envelope(sampled[:, 0], -np.radians(sampled[:, 3]), tool / 2, sampled[:, 2], r, phi)


def _run(made: Machined, tool: float, tmp_path: Path) -> rs274.Moves:
    [(name, program)] = made.files.items()
    assert name.endswith(".ngc")
    return rs274.interpret(program, {1: tool}, tmp_path)


@pytest.mark.parametrize("source, tool", [("small", 8.0), ("demo", 12.1)])
def test_a_tool_the_groove_s_width_cuts_the_exact_walls(source: str, tool: float,
                                                        tmp_path: Path) -> None:
    """The roller-sized tool (the groove's width: the demo's roller with its clearance) follows
    the roller's axis: rs274's moves sweep walls within the tolerance of the exact ones, from
    the floor to the surface, both walls, all round (a clockwise drum and a counterclockwise
    one: A's sign), and the wall_error finding says so."""
    rs274.need_rs274()
    cpu = time.process_time()
    text = SMALL if source == "small" else _demo()
    analysis, made = _built(text, f"  tool_diameter: {tool}\n  feed: 500\n")
    design = analysis.design  # type: ignore[attr-defined]
    tolerance = design.manufacturing.tolerance
    [finding] = made.findings
    assert finding.id == "wall_error" and finding.ok and finding.value <= tolerance
    moves = _run(made, tool, tmp_path)
    cam = design.cam
    r, phi = _points(cam.radius, cam.radius - cam.groove_depth)
    low, high = _exact(analysis, r, phi)
    cut_low, cut_high = _cut(moves, tool, r, phi)
    assert np.all(np.isfinite(cut_low)) and np.all(np.isfinite(cut_high))
    assert np.max(np.abs(cut_high - high)) <= tolerance
    assert np.max(np.abs(cut_low - low)) <= tolerance
    assert time.process_time() - cpu < 60


def test_a_narrower_tool_leaves_the_wall_error_it_reports(tmp_path: Path) -> None:
    """A 5 mm tool in the 8 mm groove roughs it and finishes each wall: its walls stray from
    the exact ones by no more than the wall error it reports (measured across the wall: the
    difference along the drum's axis times the wall's slope), and by about that much (the
    error is no mere bound); they never pass them by more than the tolerance; the error is
    over the tolerance, and the smallest tool it names meets it."""
    rs274.need_rs274()
    analysis, made = _built(SMALL, "  tool_diameter: 5\n  feed: 500\n")
    design = analysis.design  # type: ignore[attr-defined]
    tolerance = design.manufacturing.tolerance
    [finding] = made.findings
    assert finding.id == "wall_error" and not finding.ok and finding.severity == "error"
    error = finding.value
    moves = _run(made, 5.0, tmp_path)
    cam = design.cam
    r, phi = _points(cam.radius, cam.radius - cam.groove_depth)
    low, high = _exact(analysis, r, phi)
    cut_low, cut_high = _cut(moves, 5.0, r, phi)
    left = []
    for exact, cut, sign in ((high, cut_high, 1.0), (low, cut_low, -1.0)):
        grid = exact.reshape(ROWS, -1)
        radius = r.reshape(ROWS, -1)[:, :1]
        slope = (np.roll(grid, -1, axis=1) - np.roll(grid, 1, axis=1)) / (2 * PHI_STEP * radius)
        across = 1.0 / np.hypot(1.0, slope).ravel()
        gap = sign * (exact - cut) * across
        assert gap.min() >= -tolerance
        left.append(gap.max())
    assert max(left) <= error * 1.05 + 1e-3
    assert max(left) >= error * 0.8
    smallest = float(finding.message.split("a tool of at least ")[1].split(" mm")[0])
    assert 5.0 < smallest < 8.0
    _, better = _built(SMALL, f"  tool_diameter: {smallest}\n  feed: 500\n")
    assert better.findings[0].ok and better.findings[0].value <= tolerance


def test_moves_that_turn_a_run_in_inverse_time_at_the_feed(tmp_path: Path) -> None:
    """Every move that turns A is in inverse time (rs274 reports it as a rate over the move's
    XYZ length, or its angle where it has none), and the time it takes runs the tool over the
    work at the asked feed at the top of the layer it cuts: the helix the move makes on the
    cylinder of that radius (the drum's surface for the first layer, the layer above for the
    others); plunges and steps along X are in units per minute."""
    rs274.need_rs274()
    analysis, made = _built(SMALL, "  tool_diameter: 5\n  feed: 500\n  plunge_feed: 150\n")
    cam = analysis.design.cam  # type: ignore[attr-defined]
    moves = _run(made, 5.0, tmp_path).cutting()
    turning = np.abs(moves.end[:, 3] - moves.start[:, 3]) > 0
    assert turning.sum() > 100
    assert np.all(moves.feed_mode[turning] == "inverse")
    assert np.all(moves.feed_mode[~turning] == "units")
    straight = moves.end[~turning, :3] - moves.start[~turning, :3]
    plunges = np.abs(straight[:, 2]) > 0
    assert np.allclose(moves.feed[~turning][plunges], 150)
    assert np.allclose(moves.feed[~turning][~plunges], 500)
    start, end = moves.start[turning], moves.end[turning]
    assert np.all(start[:, 2] == end[:, 2])  # at one depth
    levels = np.unique(end[:, 2])[::-1]
    tops = dict(zip(levels, np.concatenate(([cam.radius], levels[:-1])), strict=True))
    top = np.array([tops[z] for z in end[:, 2]])
    xyz = np.linalg.norm(end[:, :3] - start[:, :3], axis=1)
    turn = np.abs(end[:, 3] - start[:, 3])
    inverse = moves.feed[turning] / np.where(xyz > 0, xyz, turn)
    helix = np.hypot(end[:, 0] - start[:, 0], top * np.radians(turn))
    assert np.allclose(inverse * helix, 500, rtol=2e-3)


def test_the_setup_sheet_states_the_drum_and_its_toolpath() -> None:
    """The setup sheet: the drum blank, the work zero and A's sign, XZA, the tool, each
    operation with its passes and minutes (the feed moves' lengths over their feeds), the
    unrolled toolpath, and the wall error in the notes."""
    _, made = _built(SMALL, "  tool_diameter: 8\n  feed: 500\n")
    [setup] = made.setups
    assert setup.axes == "XZA" and setup.file == "small-drum.ngc"
    assert "⌀40 mm" in setup.stock and "36 mm" in setup.stock
    assert "A = −θ" in setup.work_zero
    assert setup.tools[0].diameter_mm == 8.0
    [operation] = setup.operations
    assert operation.passes == 2 and operation.minutes > 0
    path = setup.toolpath
    assert path is not None and path.y_label.startswith("A")
    drawn = path.cutting[np.isfinite(path.cutting[:, 0])]
    assert drawn[:, 1].min() == 0.0 and drawn[:, 1].max() == 360.0
    assert any("Wall error" in note for note in setup.notes)
    # two laps of 2π × 20 mm round the drum at 500 mm/min, at least
    assert operation.minutes > 2 * 2 * math.pi * 15 / 500


def test_the_program_is_the_same_each_time() -> None:
    _, first = _built(SMALL, "  tool_diameter: 8\n  feed: 500\n")
    _, second = _built(SMALL, "  tool_diameter: 8\n  feed: 500\n")
    assert first.files == second.files
