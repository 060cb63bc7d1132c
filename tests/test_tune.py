"""``camfab tune``: the least peak acceleration of a polynomial law against a linear programme
set up independently here; the tuned residual vibration of a spring-held valve train below the
best standard law's, both measured by an integration of the train written here; the tuned
design building, differing from the design only in the law values, comments kept; the same
bytes twice; a blend tuned to its known optimum; no candidate meeting the limits (exit 1,
the report alone); Ctrl-C writing the best so far (130); bad options refused (exit 2, nothing
written).

The searches are kept small (one start, one speed) and each test's processor time is bounded
(a guard against runaway work, not a measure of speed)."""

from __future__ import annotations

import difflib
import math
import re
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import pytest
import yaml
from click.testing import Result

from camfab.pipeline import analyse, load_design

from .conftest import DESIGNS, run_cli

VALVE = DESIGNS / "demo-valve-at-speed.yaml"
#: The valve train's rise as a polynomial of degree 9 (velocity, acceleration and jerk zero
#: at both ends) through two points whose lifts are free.
POLY_RISE = """\
  - rise:                      # a polynomial through two points, their lifts free
      angle: 110
      lift: 9
      law: polynomial
      start: {velocity: 0, acceleration: 0, jerk: 0}
      end: {velocity: 0, acceleration: 0, jerk: 0}
      points: [[36.6667, 3], [73.3333, 6]]   # the lifts the tuner sets
"""
#: A plate cam whose rise is a polynomial of degree 7 through two free points (the convex
#: sub-problem), its return a standard law.
ACCELERATION = """\
# a polynomial rise with two free points
name: acc
cam: {type: disc, speed_rpm: 300, base_radius: 40, thickness: 8}
follower: {type: roller, roller_radius: 8}
motion:
  - rise:
      angle: 120
      lift: 10
      law: polynomial
      start: {velocity: 0, acceleration: 0}
      end: {velocity: 0, acceleration: 0}
      points: [[40, 2], [80, 8]]    # the lifts are free
  - dwell: {angle: 60}
  - return: {angle: 120, law: cycloidal}
  - dwell: {angle: 60}
"""
#: The most processor seconds one test's tuning may take (a backstop, far above its need).
CPU_BOUND = 120.0


@contextmanager
def cpu_bounded(seconds: float = CPU_BOUND) -> Iterator[None]:
    start = time.process_time()
    yield
    assert time.process_time() - start < seconds, "the tuning ran away"


def tune(design: Path, text: str, *args: str) -> Result:
    """``camfab tune DESIGN ARGS`` of *text* written as *design* (its processor time
    bounded)."""
    design.write_text(text, encoding="utf-8")
    with cpu_bounded():
        return run_cli("tune", str(design), *args)


def poly_valve(folder: Path) -> Path:
    """The valve train of ``demo-valve-at-speed`` with :data:`POLY_RISE` for its rise."""
    text = VALVE.read_text(encoding="utf-8")
    rise = next(line for line in text.splitlines() if line.startswith("  - rise:"))
    path = folder / "valve-poly.yaml"
    path.write_text(text.replace(rise + "\n", POLY_RISE), encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def tuned_valve(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path, str]:
    """The polynomial valve train tuned for its residual vibration at its design speed, 1500
    rpm: the design, the tuned design and the command's output."""
    folder = tmp_path_factory.mktemp("valve")
    design = poly_valve(folder)
    with cpu_bounded():
        result = run_cli("tune", str(design), "--speeds", "1500", "--starts", "1")
    assert result.exit_code == 0, result.output
    return design, folder / "valve-poly-tuned.yaml", result.output


# --- the convex sub-problem ----------------------------------------------------------------------


def independent_least_peak(span: float, lift: float, points: list[float]) -> float:
    """The least peak |s″| (mm/rad²) of a rise of *lift* (mm) over *span* (rad) by a
    polynomial of degree 7 with zero velocity and acceleration at both ends through points at
    the shares *points* of the span, each point's lift free between 0 and the lift: a linear
    programme over the polynomial's eight coefficients (not the points' lifts) and the bound
    t, |f″(u)| ≤ t on 20,001 points of u, solved by HiGHS."""
    from scipy.optimize import linprog

    degree = 8

    def row(u: float, order: int) -> np.ndarray:
        return np.array([math.perm(k, order) * u ** (k - order) if k >= order else 0.0
                         for k in range(degree)])

    equal = np.array([row(0, 0), row(1, 0), row(0, 1), row(0, 2), row(1, 1), row(1, 2)])
    u = np.linspace(0.0, 1.0, 20001)
    second = np.array([row(x, 2) for x in u])
    column = np.ones((u.size, 1))
    bounds_rows = np.array([sign * row(p, 0) for p in points for sign in (1.0, -1.0)])
    a_ub = np.vstack([np.hstack([second, -column]), np.hstack([-second, -column]),
                      np.hstack([bounds_rows, np.zeros((len(bounds_rows), 1))])])
    b_ub = np.concatenate([np.zeros(2 * u.size), [1.0, 0.0] * len(points)])
    cost = np.zeros(degree + 1)
    cost[-1] = 1.0
    result = linprog(cost, A_ub=a_ub, b_ub=b_ub,
                     A_eq=np.hstack([equal, np.zeros((len(equal), 1))]),
                     b_eq=[0, 1, 0, 0, 0, 0], bounds=[(None, None)] * degree + [(0, None)],
                     method="highs")
    assert result.status == 0, result.message
    return float(result.x[-1]) * lift / span**2


def test_the_least_peak_acceleration_of_a_polynomial_is_the_global_optimum(
        tmp_path: Path) -> None:
    design = tmp_path / "acc.yaml"
    result = tune(design, ACCELERATION, "--objective", "acceleration", "--segment", "0")
    assert result.exit_code == 0, result.output
    assert "global optimum" in result.output
    tuned = load_design(tmp_path / "acc-tuned.yaml")
    rise = tuned.program.segments[0]
    expected = independent_least_peak(math.radians(120), 10.0, [40 / 120, 80 / 120])
    assert rise.peak(2) == pytest.approx(expected, rel=1e-6)
    before = load_design(design).program.segments[0].peak(2)
    assert rise.peak(2) < 0.95 * before


# --- the residual vibration ----------------------------------------------------------------------


def integrated_residual(design_path: Path, rpm: float = 1500.0, turns: int = 6) -> float:
    """The residual vibration (mm, the largest peak-to-peak swing of x − s over a dwell) of
    the design's spring-held follower train, integrated in time over *turns* turns of the cam
    from rest to its steady state (the last turn measured):

        m x″ + c (x′ − s′) + k_f (x − s) + c_s x′ + k_s x + P = 0,

    c = 2ζ√(m(k_f + k_s)), with s(t) the design's lift at θ = ωt (a cubic Hermite spline of
    its program's s and s′ on a 0.01° grid)."""
    from scipy.integrate import solve_ivp
    from scipy.interpolate import CubicHermiteSpline

    design = load_design(design_path)
    program = design.program
    theta = np.linspace(0.0, 2.0 * math.pi, 36001)
    s, ds = program.evaluate(theta)[:2] * 1e-3  # m, m/rad
    lift = CubicHermiteSpline(theta, s, ds)
    slope = lift.derivative()
    fol, spring = design.follower, design.spring
    assert fol.mass and fol.stiffness and spring is not None and spring.preload is not None
    m, kf, ks = fol.mass, fol.stiffness * 1e3, spring.rate * 1e3
    c = 2.0 * fol.train_damping_ratio * math.sqrt(m * (kf + ks))
    cs, load = spring.damping, spring.preload
    omega = rpm * math.pi / 30.0

    def motion(t: float, y: np.ndarray) -> list[float]:
        x, v = y
        angle = (omega * t) % (2.0 * math.pi)
        return [v, -(c * (v - slope(angle) * omega) + kf * (x - lift(angle)) + cs * v + ks * x
                     + load) / m]

    period = 2.0 * math.pi / omega
    start = (kf * s[0] - load) / (kf + ks)
    solved = solve_ivp(motion, (0.0, turns * period), [start, 0.0], method="DOP853",
                       rtol=1e-8, atol=1e-12, dense_output=True)
    assert solved.success
    swings = []
    for seg in program.segments:
        if seg.kind == "dwell":  # its own samples, 0.01° apart, both ends included
            angle = np.linspace(seg.start, seg.end, max(2, round(math.degrees(seg.span) * 100)))
            t = (turns - 1) * period + angle / omega
            swings.append(np.ptp(solved.sol(t)[0] - lift(angle)))
    return 1000.0 * max(swings)


def test_the_integration_agrees_with_camfab_s_train() -> None:
    """The test's own measure against the at-speed analysis's, on the valve train as given."""
    residual = analyse(load_design(VALVE)).at_speed.vibration.residual_m * 1000.0
    assert integrated_residual(VALVE) == pytest.approx(residual, rel=1e-4)


def test_the_tuned_residual_is_below_the_best_standard_law_s(
        tuned_valve: tuple[Path, Path, str], tmp_path: Path) -> None:
    _, tuned, _ = tuned_valve
    tuned_residual = integrated_residual(tuned)
    data = yaml.safe_load(VALVE.read_text(encoding="utf-8"))
    returned = yaml.safe_load(tuned.read_text(encoding="utf-8"))["motion"][2]["return"]["law"]
    standard = {}
    # the standard laws whose acceleration is continuous at the dwells, as the design's is
    for law in ("cycloidal", "polynomial-345", "polynomial-4567", "polynomial-56789",
                "modified-trapezoid", "modified-sine"):
        data["motion"][0]["rise"]["law"] = law
        data["motion"][2]["return"]["law"] = returned
        path = tmp_path / f"{law}.yaml"
        path.write_text(yaml.safe_dump(data), encoding="utf-8")
        standard[law] = integrated_residual(path)
    assert tuned_residual < min(standard.values()), (tuned_residual, standard)


def test_the_gain_it_prints_over_the_best_standard_law_is_the_integration_s(
        tuned_valve: tuple[Path, Path, str], tmp_path: Path) -> None:
    """The tuned laws' gain over the best standard law in their place (the same law in every
    tuned segment), as the command prints it, is the gain the integration measures."""
    _, tuned, output = tuned_valve
    found = re.search(r"the best standard law in their place, ([a-z0-9-]+): ([0-9.e-]+) mm, "
                      r"([0-9.]+) times the tuned laws'", output)
    assert found, output
    law, factor = found.group(1), float(found.group(3))
    data = yaml.safe_load(VALVE.read_text(encoding="utf-8"))
    data["motion"][0]["rise"] = {"angle": data["motion"][0]["rise"]["angle"],
                                 "lift": data["motion"][0]["rise"]["lift"], "law": law}
    data["motion"][2]["return"]["law"] = law
    path = tmp_path / "standard.yaml"
    path.write_text(yaml.safe_dump(data), encoding="utf-8")
    assert factor > 1.0
    assert factor == pytest.approx(integrated_residual(path) / integrated_residual(tuned),
                                   rel=1e-3)


def test_the_tuned_design_builds(tuned_valve: tuple[Path, Path, str],
                                 tmp_path: Path) -> None:
    _, tuned, _ = tuned_valve
    result = run_cli("build", str(tuned), "-o", str(tmp_path / "out"))
    assert result.exit_code == 0, result.output


def test_only_the_law_values_change(tuned_valve: tuple[Path, Path, str]) -> None:
    design, tuned, output = tuned_valve
    old = design.read_text(encoding="utf-8").splitlines()
    new = tuned.read_text(encoding="utf-8").splitlines()
    assert len(old) == len(new)
    changed = [(a, b) for a, b in zip(old, new, strict=True) if a != b]
    assert changed, output
    for a, b in changed:  # a point's lifts, or a law's name, on its own line
        assert ("points:" in a and "points:" in b) or ("law:" in a and "law:" in b), (a, b)
        # the comment after the value kept
        assert a.partition("#")[2] == b.partition("#")[2]
    assert [line for line in old if "#" in line] != []
    kept = [line for line in old if line.lstrip().startswith("#")]
    assert kept == [line for line in new if line.lstrip().startswith("#")]
    # the data: the law values only
    before, after = yaml.safe_load("\n".join(old)), yaml.safe_load("\n".join(new))
    after["motion"][0]["rise"]["points"] = before["motion"][0]["rise"]["points"]
    after["motion"][2]["return"]["law"] = before["motion"][2]["return"]["law"]
    assert after == before
    assert f"wrote {tuned}" in output
    report = tuned.with_name("valve-poly-tuning.html").read_text(encoding="utf-8")
    assert "The motion, before and after" in report and "<svg" in report


# --- the families and the command -----------------------------------------------------------------


def test_the_same_design_gives_the_same_bytes(tmp_path: Path) -> None:
    files = []
    for _ in range(2):
        result = tune(tmp_path / "acc.yaml", ACCELERATION, "--objective", "jerk")
        assert result.exit_code == 0, result.output
        files.append([(tmp_path / name).read_bytes()
                      for name in ("acc-tuned.yaml", "acc-tuning.html")])
    assert files[0] == files[1]


def test_a_blend_goes_to_its_least_acceleration(tmp_path: Path) -> None:
    """The peak acceleration of modified uniform velocity, Δ/β² · 1/(r(1 − r)), is least at
    r = ½."""
    text = VALVE.read_text(encoding="utf-8").replace(
        "law: polynomial-4567}", "law: modified-uniform-velocity, blend: 0.2}")
    result = tune(tmp_path / "muv.yaml", text, "--objective", "acceleration", "--starts", "1")
    assert result.exit_code == 0, result.output
    tuned = yaml.safe_load((tmp_path / "muv-tuned.yaml").read_text(encoding="utf-8"))
    assert tuned["motion"][0]["rise"]["blend"] == 0.5
    assert tuned["motion"][2]["return"]["blend"] == 0.5


def test_the_laws_that_step_the_acceleration_at_a_dwell_are_not_chosen(
        tmp_path: Path) -> None:
    """A 4-5-6-7 rise between dwells keeps a law continuous in its acceleration there: the
    least peak acceleration of those is the modified trapezoid's (Ca 4.888), not the
    uniform acceleration's (4, with steps)."""
    result = tune(tmp_path / "valve.yaml", VALVE.read_text(encoding="utf-8"), "--objective",
                  "acceleration")
    assert result.exit_code == 0, result.output
    tuned = yaml.safe_load((tmp_path / "valve-tuned.yaml").read_text(encoding="utf-8"))
    assert tuned["motion"][0]["rise"]["law"] == "modified-trapezoid"
    page = (tmp_path / "valve-tuning.html").read_text(encoding="utf-8")
    assert "the acceleration steps at the start of motion[0]" in page


def test_no_candidate_meeting_the_limits_writes_the_report_alone(tmp_path: Path) -> None:
    text = ACCELERATION.replace("follower:", "limits: {pressure_angle: 2}\nfollower:")
    result = tune(tmp_path / "acc.yaml", text, "--objective", "acceleration", "--starts", "1")
    assert result.exit_code == 1, result.output
    assert "no candidate meets every limit" in result.output
    assert "pressure angle" in result.output
    assert not (tmp_path / "acc-tuned.yaml").exists()
    assert "no tuned design is written" in (tmp_path / "acc-tuning.html").read_text()


@pytest.mark.parametrize(("args", "words"), [
    (["--objective", "nope"], "--objective"),
    (["--segment", "1"], "motion[1] is a dwell"),
    (["--segment", "9"], "no [9]"),
    (["--segment", "x"], "is not a segment's number"),
    (["--speeds", "0:100"], "must be a speed > 0"),
    (["--speeds", "abc"], "is not a number"),
    (["--speeds", "2000:1000"], "below its low one"),
    (["--starts", "0"], "--starts"),
    (["-o", "out.txt"], "NAME.yaml"),
])
def test_a_bad_option_is_refused(tmp_path: Path, args: list[str], words: str) -> None:
    design = tmp_path / "acc.yaml"
    design.write_text(ACCELERATION, encoding="utf-8")
    result = run_cli("tune", str(design), *args, cwd=tmp_path)
    assert result.exit_code == 2, result.output
    assert words in result.output
    assert len(result.output.strip().splitlines()) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["acc.yaml"]


def test_an_objective_the_design_has_no_value_of_is_refused(tmp_path: Path) -> None:
    design = tmp_path / "acc.yaml"
    design.write_text(ACCELERATION, encoding="utf-8")
    for objective, words in (("residual", "follower.mass"), ("stress", "not computed"),
                             ("torque", "follower.mass")):
        result = run_cli("tune", str(design), "--objective", objective, cwd=tmp_path)
        assert result.exit_code == 2, result.output
        assert words in result.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["acc.yaml"]


def test_the_residual_is_the_analysis_s(tmp_path: Path) -> None:
    from camfab.tune.objectives import residuals

    design = load_design(VALVE)
    residual = analyse(design).at_speed.vibration.residual_m * 1000.0
    assert residuals(design, np.array([1500.0]))[0] == pytest.approx(residual, rel=1e-12)


def test_ctrl_c_writes_the_best_so_far(tmp_path: Path) -> None:
    design = poly_valve(tmp_path)
    process = subprocess.Popen(
        [sys.executable, "-m", "camfab", "tune", str(design), "--starts", "64", "--speeds",
         "1000:2000:41", "--progress"],
        cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert process.stderr is not None
    # the progress line says the search is under way (a backstop, not a measure of speed)
    deadline = time.monotonic() + 900
    seen = ""
    while time.monotonic() < deadline and process.poll() is None:
        seen += process.stderr.read(1)
        if "candidates" in seen:
            break
    assert "candidates" in seen, seen
    process.send_signal(signal.SIGINT)
    out, err = process.communicate(timeout=300)
    assert process.returncode == 130, out + seen + err
    assert "stopped: the best found so far" in out
    assert "camfab: interrupted" in err
    assert (tmp_path / "valve-poly-tuning.html").exists()
    assert "Stopped before the end" in (tmp_path / "valve-poly-tuning.html").read_text()
    if "OK —" in out:
        assert load_design(tmp_path / "valve-poly-tuned.yaml").program is not None
    assert not list(tmp_path.glob(".*.tmp"))


def test_the_report_says_what_changed(tuned_valve: tuple[Path, Path, str]) -> None:
    design, tuned, output = tuned_valve
    report = tuned.with_name("valve-poly-tuning.html").read_text(encoding="utf-8")
    diff = [line for line in difflib.unified_diff(
        design.read_text().splitlines(), tuned.read_text().splitlines(), lineterm="")
        if line.startswith("+") and not line.startswith("+++")]
    assert diff
    assert "motion[0].rise.points[0][1]" in report
    assert "Every limit, before and after" in report
    for label in ("pressure angle", "contact stress", "jump speed (elastic train)"):
        assert label in report and label in output


def test_a_spline_s_control_values_are_tuned_to_their_least_peak(tmp_path: Path) -> None:
    """A spline's free control values (given as a list) are tuned; its least peak acceleration
    is a linear programme's, below the smooth rise's of the same order (the 5-6-7-8-9
    polynomial's); a count of controls is not rewritten, the message says what to write."""
    text = VALVE.read_text(encoding="utf-8").replace(
        "  - rise:   {angle: 110, lift: 9, law: polynomial-4567}",
        "  - rise:   {angle: 110, lift: 9, law: spline, controls: [0.1, 0.4, 0.6, 0.9]}")
    result = tune(tmp_path / "spline.yaml", text, "--objective", "acceleration", "--segment",
                  "0")
    assert result.exit_code == 0, result.output
    assert "global optimum" in result.output
    tuned = load_design(tmp_path / "spline-tuned.yaml")
    assert len(tuned.motion[0].controls) == 4
    counted = tmp_path / "counted.yaml"
    counted.write_text(text.replace("controls: [0.1, 0.4, 0.6, 0.9]", "controls: 4"),
                       encoding="utf-8")
    smooth = load_design(counted).program.segments[0].peak(2)
    assert tuned.program.segments[0].peak(2) < 0.95 * smooth
    result = run_cli("tune", str(counted), "--objective", "acceleration", "--segment", "0")
    assert result.exit_code == 2, result.output
    assert "write them as a list to free them (controls: [" in result.output


def test_a_polydyne_cam_s_laws_the_rules_refuse_are_out(tmp_path: Path) -> None:
    """A polydyne cam's segments take the laws with polynomial pieces and four continuous
    derivatives: the others are out of the search (its program refuses them), not its end
    (nor a stop that writes the best so far)."""
    text = (DESIGNS / "demo-polydyne.yaml").read_text(encoding="utf-8")
    result = tune(tmp_path / "polydyne.yaml", text, "--objective", "acceleration",
                  "--segment", "0")
    assert result.exit_code == 0, result.output
    assert "stopped" not in result.output and "internal error" not in result.output
    page = (tmp_path / "polydyne-tuning.html").read_text(encoding="utf-8")
    assert "uniform-velocity</td><td>–</td><td>out:" in page


def test_the_command_offers_every_objective() -> None:
    from camfab.cli import TUNE_OBJECTIVES
    from camfab.tune.objectives import NAMES

    assert TUNE_OBJECTIVES == NAMES
