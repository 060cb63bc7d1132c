"""Synthetic scans with known errors (:mod:`tests.scan_synth`) inspected with ``camfab inspect``
as a user runs it: each error comes back where and as large as it was put in, within what the
scanner's noise allows, and a part without errors passes.

What the noise allows. The follower is run through each flank as the scan shows it: every node
moved by the mean deviation of the points in a box of ``--fit`` (1 mm) about it. A scan of noise
σ along the normal with n points in a box gives each node an error of σ/√n; the follower rests
on the highest node of the line it touches (some thirty of them across a flank), so the lift
error of a part without errors is a few σ/√n, toward the follower (on both flanks: the play
between them is less by twice that). Here σ = 5 µm and 200,000 points, 60 % on the
flanks (some 20 to 60 points a box): the lift error of the error-free part is asserted under
15 µm (3σ), the tolerance 25 µm.

The bump's lift error by hand: a flank moved out by h along its normal where the pressure
angle is φ pushes the follower by h / cos φ along its motion; the box average lowers the top of
a bump of radius R by about (π/R)²·fit²/24 of its height (its second-order term over a square
box). For the drum (cycloidal rise of 25 mm over 150°), at 90°: s′ = (25/β)(1 − cos(2π·90/150))
with β = 150° in radians, and at radius r = floor + across, tan φ = s′/r (THEORY §C).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from tests.conftest import DESIGNS, run_cli
from tests.scan_synth import synthetic_scan

NOISE_MM = 0.005
POINTS = 200_000

#: A rigid misplacement of the whole cloud: turned 2°, −1.5°, 37° about X, Y, Z and moved
#: (3, −2, 1.5) mm.
MISPLACE = (2.0, -1.5, 37.0, 3.0, -2.0, 1.5)

#: Largest lift error (mm) of a part without errors, under the noise (see the module).
CLEAN_MM = 3 * NOISE_MM

#: How far (mm) the play between two flanks may come out from the part's: each flank's run
#: leans toward the other by its noise's extreme (see the module), so the play is less by up to
#: twice that.
PLAY_MM = 2.5 * NOISE_MM


@dataclass(frozen=True)
class Run:
    code: int
    report: dict
    table: list[dict[str, str]]
    out: str


def _inspect(tmp: Path, name: str, *args: str, **errors: object) -> Run:
    """Make the scan of *name* with *errors*, write it as PLY, inspect it."""
    design = DESIGNS / f"{name}.yaml"
    scan = synthetic_scan(design, points=POINTS, noise_mm=NOISE_MM, seed=5, **errors)
    path = scan.write(tmp / f"{name}.ply")
    result = run_cli("inspect", str(path), "--design", str(design), *args, "-o", str(tmp / "o"))
    assert result.exit_code in (0, 1), result.stdout + result.stderr
    report = json.loads((tmp / "o" / f"{name}-inspection.json").read_text())
    lines = (tmp / "o" / f"{name}-lift.csv").read_text().splitlines()
    head = lines[0].split(",")
    table = [dict(zip(head, line.split(","), strict=True)) for line in lines[1:]]
    return Run(result.exit_code, report, table, result.stdout)


def _column(run: Run, name: str) -> np.ndarray:
    return np.array([float(r[name]) if r[name] else math.nan for r in run.table])


def _away(run: Run, centre_deg: float, half_deg: float) -> np.ndarray:
    """Rows of the lift table farther than *half_deg* from *centre_deg*."""
    angle = _column(run, "cam_angle_deg")
    return np.abs((angle - centre_deg + 180.0) % 360.0 - 180.0) > half_deg


def _flank(run: Run, name: str) -> dict:
    return next(f for f in run.report["motion"]["flanks"] if f["flank"] == name)


# -- a drum: a bump on a wall, the scan misplaced -----------------------------------------------

BUMP_DEG, BUMP_ACROSS, BUMP_MM, BUMP_RADIUS = 90.0, 4.0, 0.1, 5.0


@pytest.fixture(scope="module")
def drum_bump(tmp_path_factory: pytest.TempPathFactory) -> Run:
    return _inspect(tmp_path_factory.mktemp("drum"), "demo-cylindrical",
                    bump=(BUMP_DEG, BUMP_ACROSS, BUMP_MM, BUMP_RADIUS, 0), misplace=MISPLACE)


def test_a_bump_on_a_drum_s_wall_gives_the_lift_error_the_geometry_predicts(
        drum_bump: Run) -> None:
    beta = math.radians(150.0)
    ds = 25.0 / beta * (1.0 - math.cos(2.0 * math.pi * BUMP_DEG / 150.0))
    r = 50.0 - 8.0 + BUMP_ACROSS
    predicted = BUMP_MM * math.hypot(1.0, ds / r)  # h / cos φ
    predicted *= 1.0 - (math.pi / BUMP_RADIUS) ** 2 / 24.0  # the 1 mm box's average at the top
    motion = drum_bump.report["motion"]
    assert drum_bump.code == 1
    assert motion["max_error_flank"] == "lower wall"
    assert motion["max_error_at_deg"] == pytest.approx(BUMP_DEG, abs=1.0)
    assert motion["max_error_mm"] == pytest.approx(predicted, rel=0.04)
    lower = _column(drum_bump, "lower_wall_error_mm")
    upper = _column(drum_bump, "upper_wall_error_mm")
    away = _away(drum_bump, BUMP_DEG, 8.0)
    assert np.nanmax(np.abs(lower[away])) < CLEAN_MM
    assert np.nanmax(np.abs(upper)) < CLEAN_MM
    # the bump takes the play: 0.1 mm less where it stands
    play = _column(drum_bump, "backlash_mm")
    assert np.nanmin(play) == pytest.approx(0.1 - predicted, abs=0.015)
    assert np.nanmedian(play) == pytest.approx(0.1, abs=PLAY_MM)


def test_the_drum_s_surface_shows_the_bump_and_the_noise(drum_bump: Run) -> None:
    lower, upper = drum_bump.report["surface"]
    assert lower["max_mm"] == pytest.approx(BUMP_MM, abs=4 * NOISE_MM)
    assert upper["std_mm"] == pytest.approx(NOISE_MM, rel=0.15)
    assert drum_bump.report["alignment"]["residual_rms_mm"] == pytest.approx(NOISE_MM, rel=0.25)
    assert drum_bump.out.startswith("demo-cylindrical: FAIL") and "(on the lower wall, at " \
        in drum_bump.out


# -- a drum's groove cut oversize, on a fixture turned 7° --------------------------------------

def test_an_oversize_groove_shows_as_play_and_a_fixtured_scan_s_phase_comes_back(
        tmp_path: Path) -> None:
    """A groove cut 0.06 mm wide (each wall 0.03 mm back): the play is the clearance plus
    0.06 mm all round, each wall's lift error 0.03/cos φ toward the other; the part on its
    fixture turned 7°: found and reported."""
    run = _inspect(tmp_path, "demo-cylindrical", "--fixtured", oversize_mm=0.06,
                   whole_phase_deg=7.0)
    play = _column(run, "backlash_mm")
    # the roller rests where the wall moved least along the axis: at the drum's surface (r = 50)
    steepest = 2.0 * 25.0 / math.radians(150.0)  # s′ at mid-rise
    assert np.nanmedian(play) == pytest.approx(0.16, abs=PLAY_MM)
    assert np.nanmax(play) == pytest.approx(0.1 + 0.06 * math.hypot(1.0, steepest / 50.0),
                                            abs=PLAY_MM)
    assert run.report["alignment"]["phase_deg"] == pytest.approx(-7.0, abs=0.01)
    assert run.report["alignment"]["mode"] == "fixtured"
    lower, upper = run.report["surface"]
    assert lower["mean_mm"] == pytest.approx(-0.03, abs=0.003)
    assert upper["mean_mm"] == pytest.approx(-0.03, abs=0.003)
    assert run.code == 1  # 0.03/cos φ on each wall is over the tolerance of 0.025


# -- a globoid: a bump, misplaced --------------------------------------------------------------

def test_a_bump_on_a_globoid_s_flank_comes_back_where_it_was_put(tmp_path: Path) -> None:
    from tests.scan_synth import part_of

    design = DESIGNS / "demo-globoidal-convex.yaml"
    flank = part_of(str(design)).model.flanks[1]
    across = float(0.5 * (flank.across[0] + flank.across[-1]))
    run = _inspect(tmp_path, "demo-globoidal-convex", bump=(60.0, across, 0.08, 4.0, 1),
                   misplace=MISPLACE)
    motion = run.report["motion"]
    assert run.code == 1
    assert motion["max_error_flank"] == flank.name
    assert motion["max_error_at_deg"] == pytest.approx(60.0, abs=1.5)
    assert 0.07 < abs(motion["max_error_mm"]) < 0.1
    errors = _column(run, f"{flank.name.replace(' ', '_')}_error_mm")
    assert np.nanmax(np.abs(errors[_away(run, 60.0, 10.0)])) < CLEAN_MM
    assert run.report["surface"][1]["max_mm"] == pytest.approx(0.08, abs=4 * NOISE_MM)


# -- a groove plate: a taper; a conjugate pair and a disc cam without errors --------------------

def test_a_tapered_groove_plate_s_walls_lean_as_made(tmp_path: Path) -> None:
    """Walls cut 0.04 mm back at the top, nothing at the floor: each wall's mean deviation is
    −0.02 mm, its points range over the taper; the follower, touching the whole depth, rests
    on the floor's end: its lift error stays within the noise."""
    run = _inspect(tmp_path, "demo-groove-roller", taper_mm=0.04, misplace=MISPLACE)
    for wall in run.report["surface"]:
        assert wall["mean_mm"] == pytest.approx(-0.02, abs=0.003)
        assert wall["p01_mm"] == pytest.approx(-0.04, abs=4 * NOISE_MM)
    assert run.report["motion"]["max_error_mm"] is not None
    assert abs(run.report["motion"]["max_error_mm"]) < CLEAN_MM
    assert run.code == 0


@pytest.mark.parametrize("name", ["demo-conjugate", "seed-poly-345", "demo-linear-roller"])
def test_a_part_without_errors_passes_wherever_it_was_scanned(tmp_path: Path, name: str) -> None:
    run = _inspect(tmp_path, name, misplace=MISPLACE)
    assert run.code == 0, run.out
    assert abs(run.report["motion"]["max_error_mm"]) < CLEAN_MM
    assert all(f["measured_share"] == 1.0 for f in run.report["motion"]["flanks"])
    assert run.report["alignment"]["residual_rms_mm"] == pytest.approx(NOISE_MM, rel=0.25)
    assert run.report["alignment"]["tilt_deg"] == pytest.approx(2.5, abs=0.1)


# -- a scan that misses part of the groove; a scan in inches ------------------------------------

def test_where_the_scan_misses_the_groove_the_motion_is_not_judged(tmp_path: Path) -> None:
    """The drum scanned but for its flanks from 100° to 200° of cam angle, written in inches:
    the motion there is not judged (the follower would fall into what was not scanned, as if
    there were no material): the coverage warning names the gap, the rest passes."""
    from dataclasses import replace

    design = DESIGNS / "demo-cylindrical.yaml"
    scan = synthetic_scan(design, points=POINTS, noise_mm=NOISE_MM, seed=9, misplace=MISPLACE)
    angle = np.degrees(np.nan_to_num(scan.cam_angle, nan=-1.0))
    keep = ~((scan.flank >= 0) & (angle >= 100.0) & (angle < 200.0))
    inches = replace(scan, points=scan.points[keep] / 25.4, normals=None)
    path = inches.write(tmp_path / "gap.csv")
    result = run_cli("inspect", str(path), "--design", str(design), "--units", "in", "-o",
                     str(tmp_path / "o"))
    assert result.exit_code == 0, result.stdout + result.stderr
    report = json.loads((tmp_path / "o" / "gap-inspection.json").read_text())
    assert report["scan"]["units"] == "in (--units)"
    coverage = next(c for c in report["checks"] if c["id"] == "coverage")
    assert not coverage["ok"]
    for flank in report["motion"]["flanks"]:
        assert flank["measured_share"] == pytest.approx(260 / 360, abs=0.02)
    assert abs(report["motion"]["max_error_mm"]) < CLEAN_MM
    lines = (tmp_path / "o" / "gap-lift.csv").read_text().splitlines()
    head = lines[0].split(",")
    rows = [dict(zip(head, line.split(","), strict=True)) for line in lines[1:]]
    missing = [float(r["cam_angle_deg"]) for r in rows if not r["lower_wall_error_mm"]]
    assert min(missing) >= 100.0 and max(missing) < 200.0 and len(missing) >= 95
