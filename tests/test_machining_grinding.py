"""Cam grinding: the table of the wheel centre's radius X against the cam angle C, and its C/X
program, against references built without camfab's wheel path.

The reference X(C) is the definition: the wheel coming in along its line at cam angle C stops
where it first touches the profile, at ``max over the profile of p·u + √(R² − (p·v)²)`` (u the
line's direction on the cam, v square to it, |p·v| ≤ R). It is taken by brute force over the
exact profile sampled densely (each motion segment's exact working curve, or a shaped cam's
exact outline of arcs), the best of 5,000 points refined among 200 around it. The programs are
run by LinuxCNC's rs274 and its moves, sampled between the program's points, are held to it.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from camfab.errors import DesignError
from camfab.machining.grinding import grind_files, grind_plates, plate_table
from camfab.pipeline import analyse, design_from_text

from . import rs274
from .conftest import DESIGNS, ROOT

STARTERS = ROOT / "camfab" / "starters"

Curve = Callable[[np.ndarray], np.ndarray]


def load(path: Path, wheel: float, **settings: float) -> object:
    """The analysis of the design at *path* with a machining section for a wheel *wheel* mm
    across (and *settings*, mm and mm/min)."""
    keys = {"tool_diameter": "'6 mm'", "feed": "'600 mm/min'", "wheel_diameter": f"'{wheel} mm'",
            **{key: f"'{value} mm'" if key != "feed" else f"'{value} mm/min'"
               for key, value in settings.items()}}
    text = path.read_text() + "\nmachining:\n" + "".join(f"  {k}: {v}\n"
                                                         for k, v in keys.items())
    return analyse(design_from_text(text, path.name, path.parent), advice=False)


def ray(c: np.ndarray, sigma: int) -> tuple[np.ndarray, np.ndarray]:
    """The wheel's line on the cam at cam angles *c* (rad): +Y turned back by σC, and the
    direction square to it."""
    u = np.stack((np.sin(sigma * c), np.cos(sigma * c)), axis=-1)
    return u, np.stack((u[:, 1], -u[:, 0]), axis=-1)


def reach(points: np.ndarray, c: np.ndarray, radius: float, sigma: int) -> np.ndarray:
    """(C, K): where along the line at each of *c* a wheel of *radius* touches each point
    (points (K, 2), or (C, K, 2) one set per angle); -inf where it passes beside it."""
    u, v = ray(c, sigma)
    if points.ndim == 2:
        along, across = u @ points.T, v @ points.T
    else:
        along = np.einsum("nkj,nj->nk", points, u)
        across = np.einsum("nkj,nj->nk", points, v)
    return np.where(np.abs(across) <= radius,
                    along + np.sqrt(np.maximum(radius**2 - across**2, 0.0)), -np.inf)


def brute_x(curve: Curve, c: np.ndarray, radius: float, sigma: int,
            count: int = 5_000, fine: int = 200) -> tuple[np.ndarray, np.ndarray]:
    """X(C) by brute force over the closed curve ``curve(t)``, 0 ≤ t < 1, and the point the
    wheel touches: the best of *count* points, refined among *fine* points around it."""
    t = np.arange(count) / count
    coarse = curve(t)
    x, touch = np.empty(len(c)), np.empty((len(c), 2))
    for lo in range(0, len(c), 400):
        cc = c[lo:lo + 400]
        best = reach(coarse, cc, radius, sigma).argmax(axis=1)
        around = (t[best][:, None] + np.linspace(-3.0, 3.0, fine)[None, :] / count) % 1.0
        points = curve(around.ravel()).reshape(len(cc), fine, 2)
        distance = reach(points, cc, radius, sigma)
        k = distance.argmax(axis=1)
        x[lo:lo + 400] = distance[np.arange(len(cc)), k]
        touch[lo:lo + 400] = points[np.arange(len(cc)), k]
    return x, touch


def polyline_curve(points: np.ndarray) -> Curve:
    """The closed chain *points* as a curve of its arc length (0 ≤ t < 1)."""
    closed = np.vstack((points, points[:1]))
    s = np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(closed, axis=0).T))))
    return lambda t: np.column_stack((np.interp(t * s[-1], s, closed[:, 0]),
                                      np.interp(t * s[-1], s, closed[:, 1])))


def exact_profile(analysis: object, plate: object) -> Curve:
    """The plate's exact profile in the frame of its drawing: a shaped cam's outline of arcs
    and lines, or each motion segment's exact working curve end to end — where the velocity
    steps, a flat face's straight edge or a knife's corner between them, or the arc a roller
    rolls about the pitch curve's corner —, cam b of a conjugate pair turned half a turn
    (mirrored, for arms) into the frame it is made in."""
    geom, program = plate.geometry, plate.program
    if geom.exact:
        return polyline_curve(geom.profile.points(1e-7))
    table, cam = program.table, geom.cam
    pieces = []
    for k in range(len(table.span)):
        t = np.linspace(0.0, table.span[k], 20_000)
        pieces.append(cam.working(table.start[k] + t,
                                  program.evaluate_local(np.full(t.size, k), t)).xy)
        ahead = np.array([(k + 1) % len(table.span)])
        motion = program.evaluate_local(ahead, np.zeros(1))
        corner = cam.pitch(table.start[ahead], motion).xy[0]
        start = pieces[-1][-1] - corner
        end = cam.working(table.start[ahead], motion).xy[0] - corner
        turn = math.atan2(start[0] * end[1] - start[1] * end[0], start @ end)
        if cam.follower.radius > 0.0 and not cam.follower.flat and abs(turn) > 1e-9:
            angle = math.atan2(start[1], start[0]) + turn * np.linspace(0.0, 1.0, 2_000)
            pieces.append(corner + cam.follower.radius * np.column_stack((np.cos(angle),
                                                                          np.sin(angle))))
    points = np.concatenate(pieces)
    if plate.start:
        points = (points * np.array([1.0, -1.0]) if analysis.design.follower.oscillating
                  else -points)
    return polyline_curve(points)


KNIFE_CORNER = """\
name: knife-corner
cam: {type: disc, rotation: cw, base_radius: 40}
follower: {type: knife, motion: translating, offset: 5}
motion:
  - rise: {angle: 150, lift: 15, law: cycloidal}
  - return: {angle: 150, law: polynomial, start: {velocity: -4},
             end: {velocity: 0, acceleration: 0}}
  - dwell: {angle: 60}
manufacturing: {tolerance: 0.002}
"""

#: Profiles with something between two segments where the velocity steps: a knife's corner
#: the wheel rolls round, a flat face's straight edge, a roller's hollow (the wheel smaller).
STEPPED = {
    "knife-corner": KNIFE_CORNER,
    "flat-edge": KNIFE_CORNER.replace("type: knife", "type: flat").replace("velocity: -4",
                                                                          "velocity: 4"),
    "roller-hollow": """\
name: roller-hollow
cam: {type: disc, rotation: ccw, base_radius: 40}
follower: {type: roller, motion: translating, offset: 5, roller_radius: 8}
motion:
  - dwell: {angle: 60}
  - rise: {angle: 150, lift: 15, law: polynomial, start: {velocity: 4},
           end: {velocity: 0, acceleration: 0}}
  - return: {angle: 150, law: cycloidal}
manufacturing: {tolerance: 0.002}
""",
}


@pytest.fixture(scope="module")
def stepped(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The folder of the :data:`STEPPED` designs."""
    folder = tmp_path_factory.mktemp("stepped")
    for name, text in STEPPED.items():
        (folder / f"{name}.yaml").write_text(text)
    return folder


@pytest.mark.parametrize(("design", "wheel"), [
    (STARTERS / "disc-roller.yaml", 80.0),
    (STARTERS / "oscillating-flat.yaml", 200.0),
    (DESIGNS / "demo-tangent-roller.yaml", 120.0),
    (DESIGNS / "demo-conjugate-oscillating.yaml", 60.0),
    ("knife-corner", 30.0),
    ("flat-edge", 50.0),
    ("roller-hollow", 12.0),
])
def test_the_table_agrees_with_the_brute_force_reference(design: Path | str, wheel: float,
                                                         stepped: Path) -> None:
    """At every row and between rows (X straight between them, as a control interpolates it)
    the table is within the tolerance of the brute-force X(C); each plate's CSV says the
    same."""
    path = stepped / f"{design}.yaml" if isinstance(design, str) else design
    analysis = load(path, wheel)
    tolerance = analysis.design.manufacturing.tolerance
    made = grind_files(analysis, analysis.design.machining)
    assert made.withheld is None
    plates = grind_plates(analysis)
    assert len(made.files) == 2 * len(plates)
    for plate in plates:
        rows = np.loadtxt(made.files[f"{plate.stem}-grind.csv"].decode().splitlines(),
                          delimiter=",", skiprows=1)
        c_deg, x = rows[:, 0], rows[:, 1]
        assert c_deg[0] == 0.0 and c_deg[-1] == 360.0 and np.all(np.diff(c_deg) > 0)
        share = np.array([0.0, 0.35, 0.7])
        c = np.radians(c_deg[:-1, None] + share * np.diff(c_deg)[:, None]).ravel()
        straight = (x[:-1, None] + share * np.diff(x)[:, None]).ravel()
        reference, _ = brute_x(exact_profile(analysis, plate), c, wheel / 2,
                               analysis.design.cam.sigma)
        assert np.max(np.abs(straight - reference)) <= tolerance


def test_a_radial_roller_as_large_as_the_wheel_is_its_pitch_radius() -> None:
    """With no offset and a roller the wheel's size, the wheel's centre is the roller's:
    X(C) = Rp + s(C) at every row."""
    text = (STARTERS / "disc-roller.yaml").read_text().replace("offset: 3 ", "offset: 0 ")
    path = Path("/nonexistent") / "radial.yaml"
    analysis = analyse(design_from_text(text + "\nmachining: {tool_diameter: 6, feed: 600, "
                                        "wheel_diameter: 16}\n", path.name, STARTERS),
                       advice=False)
    table = plate_table(grind_plates(analysis)[0], 8.0, analysis.design.manufacturing.tolerance)
    prime = analysis.design.cam.base_radius + 8.0
    assert np.max(np.abs(table.x - prime - analysis.program.evaluate(table.c)[0])) < 1e-9


def eccentric_x(c: np.ndarray, wheel_radius: float) -> np.ndarray:
    """X(C) of the eccentric circle of ``seed-jump-eccentric`` (radius 60 mm about a centre
    37.5 mm from the axis, on −Y at C = 0): e·cos(C − φ) + √((ρ + Rw)² − (e·sin(C − φ))²)
    with φ = 180°."""
    e, rho = 37.5, 60.0
    return (e * np.cos(c - math.pi)
            + np.sqrt((rho + wheel_radius) ** 2 - (e * np.sin(c - math.pi)) ** 2))


def test_an_eccentric_circle_gives_the_closed_form() -> None:
    """The full-cycle harmonic motion under a flat face makes an eccentric circle: its table
    is the closed form at every row and between rows."""
    analysis = load(DESIGNS / "seed-jump-eccentric.yaml", 300.0)
    table = plate_table(grind_plates(analysis)[0], 150.0,
                        analysis.design.manufacturing.tolerance)
    share = np.linspace(0.0, 1.0, 9)
    c = (table.c[:-1, None] + share * np.diff(table.c)[:, None]).ravel()
    straight = (table.x[:-1, None] + share * np.diff(table.x)[:, None]).ravel()
    assert np.max(np.abs(straight - eccentric_x(c, 150.0))) <= (
        analysis.design.manufacturing.tolerance)


def select(moves: rs274.Moves, keep: np.ndarray) -> rs274.Moves:
    """The moves of *moves* that *keep* marks."""
    return rs274.Moves(moves.kind[keep], moves.start[keep], moves.end[keep],
                       moves.centre[keep], moves.turn[keep], moves.feed_mode[keep],
                       moves.feed[keep], moves.messages, moves.canon)


def inverse_moves(moves: rs274.Moves) -> rs274.Moves:
    """The moves rs274 made in inverse-time feed mode."""
    return select(moves, (moves.kind != "traverse") & (moves.feed_mode == "inverse"))


def test_the_program_runs_in_rs274_and_its_moves_follow_the_closed_form(tmp_path: Path) -> None:
    """rs274 runs the eccentric cam's program without error; its C–X moves, sampled every
    0.05° between the program's points as the interpreter interpolates them, follow the exact
    X(C) within the tolerance (the first turn with the finishing allowance left); every C–X move
    is in inverse time, its F the feed over the distance the contact travels on the circle."""
    analysis = load(DESIGNS / "seed-jump-eccentric.yaml", 300.0, finish_allowance=0.3,
                    feed=900.0)
    settings = analysis.design.machining
    made = grind_files(analysis, settings)
    program = made.files["seed-jump-eccentric-grind.ngc"]
    text = program.decode()
    assert "G7" not in text and "\nG8\n" in text and "G93" in text
    moves = rs274.interpret(program, {1: 300.0}, tmp_path)
    ground = inverse_moves(moves)
    assert np.all(ground.start[:, 1:5] == 0.0) and np.all(ground.end[:, 1:5] == 0.0)
    assert ground.end[-1, 5] == pytest.approx(720.0)
    tolerance = analysis.design.manufacturing.tolerance
    finish = ground.end[:, 5] > 360.0 + 1e-9
    for turn, left in ((~finish, 0.3), (finish, 0.0)):
        sampled = select(ground, turn).sample(1e9, 0.05)
        exact = eccentric_x(np.radians(sampled[:, 5]), 150.0)
        assert np.max(np.abs(sampled[:, 0] - left - exact)) <= tolerance
    # the feed at the surface: each move's time 1/F against the contact's travel on the circle
    feeds = np.array([float(f) for f in re.findall(r"^G1 C\S+ X\S+ F(\S+)$", text, re.M)])
    assert len(feeds) == len(ground.kind)
    centre = np.array([0.0, -37.5])

    def contact(row: np.ndarray) -> np.ndarray:
        u, _ = ray(np.radians(row[:, 5]), 1)
        wheel = u * row[:, :1]
        towards = wheel - centre
        return centre + 60.0 * towards / np.hypot(*towards.T)[:, None]

    travel = np.hypot(*(contact(ground.end[finish]) - contact(ground.start[finish])).T)
    assert travel * feeds[finish] == pytest.approx(900.0, rel=2e-3)


def test_an_inch_design_writes_inches_and_its_moves_follow_the_reference(
        tmp_path: Path) -> None:
    """A design in inches: the CSV adds ``x_in``; the program is in inches (G20) and its moves,
    run by rs274 and sampled between points, follow the brute-force X(C) within the tolerance
    and the rounding of rs274's printout (four decimals of an inch: 1.27 µm either way)."""
    analysis = load(DESIGNS / "demo-inch-flat.yaml", 100.0, finish_allowance=0.0)
    made = grind_files(analysis, analysis.design.machining)
    csv = made.files["demo-inch-flat-grind.csv"].decode().splitlines()
    assert csv[0] == "c_deg,x_mm,x_in"
    rows = np.loadtxt(csv, delimiter=",", skiprows=1)
    assert np.allclose(rows[:, 2] * 25.4, rows[:, 1], rtol=1e-9)
    program = made.files["demo-inch-flat-grind.ngc"]
    assert "\nG20\n" in program.decode()
    moves = inverse_moves(rs274.interpret(program, {1: 100.0 / 25.4}, tmp_path, units="in"))
    sampled = moves.sample(1e9, 0.15)
    c = np.radians(sampled[:, 5])
    plate = grind_plates(analysis)[0]
    reference, _ = brute_x(exact_profile(analysis, plate), c, 50.0, analysis.design.cam.sigma)
    printed = 0.00005 * 25.4
    assert np.max(np.abs(sampled[:, 0] * 25.4 - reference)) <= (
        analysis.design.manufacturing.tolerance + printed)


def test_a_concave_part_tighter_than_the_wheel_is_refused_with_where() -> None:
    """A constant-diameter cam's concave flanks (radius down to about 21 mm) under a wheel of
    100 mm radius: no grinding files, and a reason naming the cam angles; the profile's
    tightest concave point lies in them and the wheel, wherever the table would put it, never
    reaches that point (the brute-force X(C) over a whole turn)."""
    analysis = load(DESIGNS / "demo-constant-diameter.yaml", 200.0)
    made = grind_files(analysis, analysis.design.machining)
    assert not made.files and made.withheld is not None
    assert "concave" in made.withheld
    spans = [(float(a), float(b)) for a, b in
             re.findall(r"(\d+(?:\.\d+)?)°–(\d+(?:\.\d+)?)°", made.withheld)]
    worst = analysis.numbers.profile_min_concave
    assert any(a <= worst.at_deg <= b for a, b in spans)
    plate = grind_plates(analysis)[0]
    theta = math.radians(worst.at_deg)
    point = plate.geometry.cam.working(np.array([theta]), analysis.program.evaluate(theta)).xy
    sigma = analysis.design.cam.sigma
    c = np.radians(np.arange(0.0, 360.0, 0.2))
    x, _ = brute_x(exact_profile(analysis, plate), c, 100.0, sigma)
    u, _ = ray(c, sigma)
    gap = np.hypot(*(u * x[:, None] - point).T) - 100.0
    assert gap.min() > 10 * analysis.design.manufacturing.tolerance


def test_a_sharp_hollow_is_refused_with_where(tmp_path: Path) -> None:
    """A knife's velocity stepping up at the start of a uniform-velocity rise makes a sharp
    hollow no wheel enters: refused at its cam angle."""
    path = tmp_path / "hollow.yaml"
    path.write_text(KNIFE_CORNER.replace("law: cycloidal", "law: uniform-velocity"))
    analysis = load(path, 20.0)
    made = grind_files(analysis, analysis.design.machining)
    assert not made.files and made.withheld is not None
    assert "hollow" in made.withheld and "0°" in made.withheld


@pytest.mark.parametrize(("design", "words"), [("demo-groove-roller", "groove"),
                                               ("demo-linear-knife", "slides")])
def test_cams_that_are_not_ground_say_why(design: str, words: str) -> None:
    analysis = load(DESIGNS / f"{design}.yaml", 100.0)
    made = grind_files(analysis, analysis.design.machining)
    assert not made.files and made.withheld is not None and words in made.withheld


def test_a_wheel_on_grbl_is_a_located_error() -> None:
    """Grbl has no C axis: ``wheel_diameter`` with ``dialect: grbl`` is refused on its line."""
    text = ((STARTERS / "disc-roller.yaml").read_text()
            + "\nmachining:\n  tool_diameter: 6\n  feed: 600\n  dialect: grbl\n"
              "  wheel_diameter: 80\n")
    with pytest.raises(DesignError) as refused:
        design_from_text(text, "grbl.yaml")
    line = text.splitlines().index("  wheel_diameter: 80") + 1
    assert f"grbl.yaml:{line}: machining.wheel_diameter:" in str(refused.value)


def test_a_build_with_a_wheel_writes_the_grinding_files_beside_the_milling_program() -> None:
    """``wheel_diameter`` given: the build writes the plate's milling program, its grinding
    table and its C/X program, each with its setup sheet; a wheel that cannot grind the plate
    leaves the milling program and fails the ``grinding`` check with where."""
    from dataclasses import replace

    from camfab.pipeline import render

    def gcode(analysis):  # type: ignore[no-untyped-def]
        return replace(analysis, design=analysis.design.model_copy(update={"outputs": ("gcode",)}))

    analysis = gcode(load(DESIGNS / "seed-10-4.yaml", 40.0))
    artifacts = render(analysis)
    name = analysis.design.name
    assert {f"{name}.ngc", f"{name}-grind.csv", f"{name}-grind.ngc"} <= set(artifacts.files)
    assert artifacts.analysis is not None
    assert [s.file for s in artifacts.analysis.machining] == [f"{name}.ngc", f"{name}-grind.ngc"]
    assert "grinding" not in {f.id for f in artifacts.analysis.findings}

    refused = render(gcode(load(DESIGNS / "demo-constant-diameter.yaml", 200.0)))
    names = set(refused.files)
    assert any(n.endswith(".ngc") for n in names) and not any("-grind" in n for n in names)
    assert refused.analysis is not None
    (grinding,) = [f for f in refused.analysis.findings if f.id == "grinding"]
    assert not grinding.ok and "concave" in grinding.message and "°" in grinding.message
