"""The cam at its speed as a user meets it: the design file's keys and their refusals (one located
line, exit 2, nothing written), the roller bearing's life against a hand computation, the
checks, the report's and the motion table's numbers, sweeps, starters and the sizing that learns
the contact stress."""

from __future__ import annotations

import csv
import html
import io
import json
import math
import re
from pathlib import Path

import numpy as np
import pytest
import yaml

from camfab.design.loader import unsized_design
from camfab.pipeline import analyse, design_from_text, load_design, render, size_design
from camfab.speed.contact import Contact, ContactSide, roller_life

from .conftest import DESIGNS, run_cli

VALVE = DESIGNS / "demo-valve-at-speed.yaml"

ROLLER = """\
name: life
cam: {type: disc, base_radius: 30, speed_rpm: 600, thickness: 10}
follower: {type: roller, roller_radius: 10, mass: 0.5, roller_load_rating: 8.5 kN%s}
motion:
  - rise:   {angle: 120, lift: 18, law: cycloidal}
  - dwell:  {angle: 60}
  - return: {angle: 120, law: cycloidal}
  - dwell:  {angle: 60}
spring: {rate: 5, preload: 100}
"""


def _grid(pieces: list[tuple[float, float]]) -> tuple[np.ndarray, np.ndarray]:
    """A turn split into arcs of the given shares, each holding its value: angles (rad, each
    arc's ends both on the grid, as the analysis grid holds a joint twice) and the values."""
    theta, value, start = [], [], 0.0
    total = sum(share for share, _ in pieces)
    for share, level in pieces:
        span = 2 * math.pi * share / total
        theta.append(np.linspace(start, start + span, 50))
        value.append(np.full(50, level))
        start += span
    return np.concatenate(theta), np.concatenate(value)


def test_roller_life_of_a_constant_load_by_hand() -> None:
    """500 N all the turn on a roller of 10 mm rolling 40 mm a radian: 4 revolutions a turn;
    L10 = (8500/500)^(10/3)·10⁶ revolutions, at 600 rpm (needle: 10/3) or cubed (ball)."""
    for bearing, exponent in (("", 10 / 3), (", roller_bearing: ball", 3.0)):
        design = design_from_text(ROLLER % bearing)
        theta, force = _grid([(1.0, 500.0)])
        side = ContactSide("the profile", 1, np.zeros(theta.size), np.ones(theta.size),
                           np.full(theta.size, 40.0))
        life = roller_life(design, Contact(theta, "line", 0.1, 10.0, (side,), 10.0), force)
        assert life is not None
        assert life.revolutions[0] == pytest.approx(4.0, rel=1e-12)
        assert life.load_N[0] == pytest.approx(500.0, rel=1e-12)
        hours = (8500 / 500) ** exponent * 1e6 / (4.0 * 600 * 60)
        assert life.hours[0] == pytest.approx(hours, rel=1e-12)


def test_roller_life_of_a_varying_load_is_the_cubic_mean() -> None:
    """Mott, *Machine Elements in Mechanical Design* (4th ed.), Example 14-6: 650 lb for 30
    min, 750 lb for 10 min, 250 lb for 20 min at a steady speed, a ball bearing: the mean
    load 597 lb. On a cam the shares of the roller's revolutions take the minutes' place."""
    design = design_from_text(ROLLER % ", roller_bearing: ball")
    lbf = 4.4482216152605
    theta, force = _grid([(30.0, 650 * lbf), (10.0, 750 * lbf), (20.0, 250 * lbf)])
    side = ContactSide("the profile", 1, np.zeros(theta.size), np.ones(theta.size),
                       np.full(theta.size, 40.0))
    life = roller_life(design, Contact(theta, "line", 0.1, 10.0, (side,), 10.0), force)
    assert life is not None
    assert life.load_N[0] / lbf == pytest.approx(597.0, abs=0.5)


def test_a_conjugate_pairs_rollers_roll_over_their_whole_cams() -> None:
    """Each roller rides its cam loaded or not: a turn is its cam's perimeter over the roller's
    circumference (the outline's chain measured here), whichever roller carries."""
    text = (DESIGNS / "demo-conjugate.yaml").read_text()
    text = text.replace("roller_radius:", "roller_load_rating: 6 kN\n  roller_radius:", 1)
    analysis = analyse(design_from_text(text, folder=DESIGNS))
    life = analysis.at_speed.life  # type: ignore[union-attr]
    assert life is not None and life.names == ("roller a", "roller b")
    radius = analysis.design.follower.roller_radius
    for k, geom in enumerate((analysis.geometry, analysis.partner.geometry)):
        ring = geom.outline_points()
        perimeter = float(np.sum(np.hypot(*(np.roll(ring, -1, axis=0) - ring).T)))
        assert life.revolutions[k] == pytest.approx(perimeter / (2 * math.pi * radius),
                                                    rel=1e-4)


def test_the_valve_example_passes_at_speed_and_reports_every_number() -> None:
    analysis = analyse(load_design(VALVE))
    assert analysis.exit_code == 0
    files = render(analysis).files
    dynamics = json.loads(files["demo-valve-at-speed-report.json"])["dynamics"]
    for key in ("contact_stress_max_MPa", "contact_stress_max_at_deg", "natural_frequency_Hz",
                "dynamic_error_max_mm", "residual_vibration_mm", "dynamic_min_contact_force_N",
                "dynamic_jump_speed_rpm", "roller_life_h"):
        assert isinstance(dynamics[key], float), key
    # f_n = √((k_f + k_s)/m)/2π
    assert dynamics["natural_frequency_Hz"] == pytest.approx(
        math.sqrt(625e3 / 0.35) / (2 * math.pi), rel=1e-12)
    dwells = dynamics["residual_vibration_by_dwell"]
    assert [(d["start_deg"], d["end_deg"]) for d in dwells] == [(110.0, 130.0), (240.0, 360.0)]
    assert dynamics["residual_vibration_mm"] == max(d["peak_to_peak_mm"] for d in dwells)
    checks = {c["id"]: c for c in json.loads(files["demo-valve-at-speed-report.json"])["checks"]}
    for key in ("contact_stress", "dynamic_jump", "roller_life"):
        assert checks[key]["ok"] is True
    assert checks["contact_stress"]["value"] == pytest.approx(dynamics["contact_stress_max_MPa"])
    # the motion table's new columns, at the report's angles
    table = list(csv.DictReader(io.StringIO(files["demo-valve-at-speed-motion.csv"].decode())))
    assert {"contact_stress_MPa", "dynamic_displacement_mm", "dynamic_contact_force_N"} <= set(
        table[0])
    stress = np.array([float(row["contact_stress_MPa"]) for row in table])
    assert stress.max() <= dynamics["contact_stress_max_MPa"] + 1e-9
    assert stress.max() == pytest.approx(dynamics["contact_stress_max_MPa"], rel=0.02)
    page = files["demo-valve-at-speed-report.html"].decode()
    for section in ('id="contact-stress"', 'id="follower-train"', "Residual vibration"):
        assert section in page
    assert page.count("data-cursor=") == 3  # the diagrams, the stress, the vibration


def test_without_the_numbers_each_key_is_null_and_says_why() -> None:
    files = render(analyse(load_design(DESIGNS / "seed-10-4.yaml"))).files
    dynamics = json.loads(files["seed-10-4-report.json"])["dynamics"]
    assert dynamics["contact_stress_max_MPa"] is None
    assert "mass" in dynamics["contact_stress_note"]
    assert dynamics["natural_frequency_Hz"] is None and dynamics["roller_life_h"] is None
    assert "stiffness" in dynamics["vibration_note"]
    assert "contact_stress_MPa" not in files["seed-10-4-motion.csv"].decode().splitlines()[0]


def test_a_knife_edge_has_no_stress() -> None:
    """Its contact has no area: no stress is computed, and a limit on it is refused."""
    text = (DESIGNS / "demo-oscillating-knife.yaml").read_text()
    text = text.replace("  type: knife", "  type: knife\n  mass: 0.3", 1)
    text += "\nspring: {rate: 5, preload: 50}\n"
    if "speed_rpm" not in text:
        text = text.replace("  type: disc", "  type: disc\n  speed_rpm: 300", 1)
    speed = analyse(design_from_text(text)).at_speed
    assert speed is not None and speed.force_N is not None and speed.stress is None
    assert "knife" in (speed.stress_note or "")
    with pytest.raises(Exception, match=r"limits.contact_stress: a knife edge's contact has no"):
        design_from_text(text + "limits: {contact_stress: 900 MPa}\n")


@pytest.mark.parametrize(("change", "words"), [
    ("  thickness: 14\n", "needs the contact's length: give cam.thickness or "
                          "follower.roller_length"),
    ("spring:\n  rate: 25                     # N/mm\n  preload: 250                 # N at "
     "zero lift\n", "give the spring that holds it on the cam"),
])
def test_a_limit_at_speed_that_cannot_be_checked_is_refused(change: str, words: str) -> None:
    text = VALVE.read_text().replace("  roller_length: 12            # the line of contact: "
                                     "the shorter of this and the thickness\n", "")
    assert change in text
    with pytest.raises(Exception, match=f"limits.contact_stress: .*{re.escape(words)}"):
        design_from_text(text.replace(change, ""))


def test_the_contact_stress_fails_over_its_limit_with_where_and_the_size_that_passes() -> None:
    text = VALVE.read_text().replace("contact_stress: 1200 MPa", "contact_stress: 420 MPa")
    text = text.replace("base_radius: 30", "base_radius: 24")
    analysis = analyse(design_from_text(text))
    finding = next(f for f in analysis.findings if f.id == "contact_stress")
    assert not finding.ok and analysis.exit_code == 1
    assert finding.ranges_deg and finding.value > 420
    assert "where the cam is convex, of radius of curvature" in finding.message
    assert "base radius of" in finding.message  # the sizing's advice


def test_camfab_size_learns_the_contact_stress(tmp_path: Path) -> None:
    """Held to 430 MPa, the valve's cam is sized by its stress: at the size found the build's
    own check passes, a hundredth of a millimetre smaller it fails."""
    text = VALVE.read_text().replace("contact_stress: 1200 MPa", "contact_stress: 430 MPa")
    design = design_from_text(text)
    sizing = size_design(design, frozenset({"cam.base_radius"}))
    assert sizing.size is not None and sizing.found.governing is not None
    assert sizing.found.governing.id == "contact_stress"
    assert sizing.found.governing.unit == "MPa"

    def check(base: float) -> bool:
        at = design_from_text(text.replace("base_radius: 30", f"base_radius: {base!r}"))
        return next(f for f in analyse(at, advice=False).findings
                    if f.id == "contact_stress").ok

    assert check(sizing.size)
    assert not check(sizing.size - 0.01)
    path = tmp_path / "valve.yaml"
    path.write_text(text.replace("base_radius: 30", "base_radius: auto"))
    result = run_cli("check", str(path))
    assert "governed by the contact stress" in result.output


@pytest.mark.parametrize(("old", "new", "where", "words"), [
    ("stiffness: 600 ", "stiffness: -5 ", "follower.stiffness", "must be > 0"),
    ("stiffness: 600 ", "stiffness: 600 mm ", "follower.stiffness", "must be a spring rate"),
    ("damping_ratio: 0.06", "damping_ratio: 1.5", "follower.damping_ratio", "must be below 1"),
    ("roller_load_rating: 6.2 kN", "roller_load_rating: 0 kN", "follower.roller_load_rating",
     "must be > 0"),
    ("cam: steel", "cam: stel", "materials.cam", "did you mean 'steel'"),
    ("cam: steel", "cam: {E: 5 mm, poisson: 0.3}", "materials.cam.E", "must be a stress"),
    ("contact_stress: 1200 MPa", "contact_stress: 1200 mm", "limits.contact_stress",
     "must be a stress"),
    ("roller_life: 10000 h", "roller_life: 10000 N", "limits.roller_life",
     "must be a duration"),
    ("  mass: 0.35", "  # mass: 0.35", "follower.stiffness", "needs the follower's mass"),
    ("  roller_load_rating: 6.2 kN", "  # roller_load_rating", "follower.roller_bearing",
     "only with follower.roller_load_rating"),
])
def test_bad_keys_are_one_located_line(tmp_path: Path, old: str, new: str, where: str,
                                       words: str) -> None:
    text = VALVE.read_text()
    assert old in text
    path = tmp_path / "bad.yaml"
    path.write_text(text.replace(old, new, 1))
    out = tmp_path / "out"
    result = run_cli("build", str(path), "-o", str(out))
    assert result.exit_code == 2
    [line] = result.output.strip().splitlines()
    _, number, field, problem = line.split(":", 3)
    assert field.strip() == where and words in problem
    written = path.read_text().splitlines()[int(number) - 1]
    assert where.split(".")[1] in written
    assert not out.exists()


def test_a_roller_life_limit_needs_a_rating_and_a_roller() -> None:
    text = re.sub(r"\n  roller_(load_rating|bearing): .*", "", VALVE.read_text())
    with pytest.raises(Exception, match=r"limits.roller_life: needs follower.roller_load_rating"):
        design_from_text(text)


def test_a_damping_ratio_needs_a_stiffness() -> None:
    text = VALVE.read_text().replace("  stiffness: 600 ", "  # stiffness: 600 ")
    with pytest.raises(Exception, match=r"follower.damping_ratio: only an elastic"):
        design_from_text(text)


def test_sweep_rows_carry_the_stress_the_vibration_and_the_life(tmp_path: Path) -> None:
    result = run_cli("sweep", str(VALVE), "--vary", "follower.stiffness=200,600,2000",
                     "--format", "csv", "-o", str(tmp_path), "-j", "1")
    assert result.exit_code == 0, result.output
    rows = list(csv.DictReader((tmp_path / "demo-valve-at-speed-sweep.csv").open()))
    assert [row["follower.stiffness"] for row in rows] == ["200", "600", "2000"]
    residual = [float(row["residual_vibration_mm"]) for row in rows]
    assert residual[0] > residual[1] > residual[2]  # a stiffer train rings less
    for row in rows:
        assert float(row["contact_stress_max_MPa"]) > 0 and float(row["roller_life_h"]) > 0


def test_every_starter_builds_with_its_commented_keys_given() -> None:
    """The starters show the keys commented; given (uncommented), each starter still builds
    and the numbers they ask for are computed."""
    from camfab.cli import STARTER_KINDS

    for kind in STARTER_KINDS:
        text = run_cli("new", kind).output
        assert "# stiffness:" in text
        lines = []
        for line in text.splitlines():
            match = re.match(r"^(\s*)# ((?:mass|stiffness|damping_ratio|roller_length|"
                             r"roller_load_rating|roller_bearing|contact_stress|roller_life|"
                             r"limits|materials|spring)\b.*)$", line)
            nested = re.match(r"^#   ((?:cam|follower|contact_stress|roller_life|rate|"
                              r"preload): .*)$", line)
            lines.append(match.group(1) + match.group(2) if match else
                         "  " + nested.group(1) if nested else line)
        analysis = analyse(design_from_text("\n".join(lines) + "\n", folder=DESIGNS))
        speed = analysis.at_speed
        assert speed is not None and speed.force_N is not None, kind
        if analysis.design.follower.type != "knife":
            assert speed.stress is not None, kind
        if analysis.design.follower.type == "roller":
            assert speed.life is not None, kind


@pytest.mark.parametrize("given", ["stiffness", "stiffness, no spring", "rigid"])
def test_a_jerk_step_says_where_its_ringing_is_seen(tmp_path: Path, given: str) -> None:
    """A jerk step sets an elastic follower ringing: with a stiffness the train's residual
    vibration says how much (or what it lacks), never "give follower.stiffness" — in the
    terminal, the report's page and its JSON alike."""
    text = VALVE.read_text().replace("polynomial-4567", "cycloidal")  # jerk steps at the dwells
    if given == "rigid":
        text = re.sub(r"\n  (stiffness|damping_ratio): .*", "", text)
    if given == "stiffness, no spring":
        text = re.sub(r"\nspring:\n  rate: .*\n  preload: .*", "", text)
        text = text.replace("limits:\n  contact_stress: 1200 MPa     # a through-hardened steel "
                            "cam\n  roller_life: 10000 h\n", "")
    path = tmp_path / "valve.yaml"
    path.write_text(text)
    result = run_cli("build", str(path), "-o", str(tmp_path / "out"))
    assert result.exit_code in (0, 1), result.output
    json_path = tmp_path / "out" / "demo-valve-at-speed-report.json"
    report = json.loads(json_path.read_text())
    [jerk] = [c for c in report["checks"]
              if c["id"] == "continuity" and c["message"].startswith("jerk steps")]
    page = html.unescape((tmp_path / "out" / "demo-valve-at-speed-report.html").read_text())
    terminal = run_cli("check", str(path)).output
    for shown in (jerk["message"], page, " ".join(terminal.split())):
        if given == "rigid":
            assert "give follower.stiffness to see how much" in shown
            continue
        assert "give follower.stiffness" not in shown
        if given == "stiffness":
            assert "the elastic follower train's residual vibration in the dwells says how " \
                   "much" in shown
        else:
            assert "would say how much, but no spring holds the follower" in shown
    if given == "stiffness":
        assert isinstance(report["dynamics"]["residual_vibration_mm"], float)


def _with_life(name: str, limits: dict[str, object], **cam: object) -> str:
    """Design *name* from designs/ with a roller bearing of C = 2 kN, a follower mass where it
    has none, *limits* for its own and the cam's keys *cam* changed."""
    data = yaml.safe_load((DESIGNS / f"{name}.yaml").read_text())
    data["follower"].setdefault("mass", 0.5)
    data["follower"]["roller_load_rating"] = "2 kN"
    data["limits"] = limits
    data["cam"].update(cam)
    return yaml.safe_dump(data)


def _life(text: str) -> float:
    """The build's roller life (h, its least roller's) for the design *text*."""
    speed = analyse(design_from_text(text), advice=False).at_speed
    assert speed is not None and speed.life is not None
    return speed.life.hours_min


def test_camfab_size_holds_the_roller_life_and_its_answer_passes_the_build(
        tmp_path: Path) -> None:
    """A conjugate pair's roller b lasts longer on a larger cam up to some size (its pressure
    angle falls faster than its turns grow): held to 2.2e5 h, the pair's least size is set by
    the life. At it the build's every check passes, its roller_life included; 0.01 mm less the
    life fails."""
    text = _with_life("demo-conjugate", {"roller_life": "220000 h"}, base_radius="auto")
    path = tmp_path / "pair.yaml"
    path.write_text(text)
    result = run_cli("size", str(path))
    assert result.exit_code == 0, result.output
    assert "governed by the roller's bearing life" in result.output
    sizing = size_design(*unsized_design(path, frozenset({"cam.base_radius"})))
    assert sizing.size is not None
    at = text.replace("base_radius: auto", f"base_radius: {sizing.size!r}")
    (tmp_path / "at.yaml").write_text(at)
    assert run_cli("check", str(tmp_path / "at.yaml")).exit_code == 0
    assert _life(at) >= 220000.0
    less = text.replace("base_radius: auto", f"base_radius: {sizing.size - 0.01!r}")
    assert _life(less) < 220000.0
    checked = run_cli("check", str(path))  # auto: sized, then checked as built
    assert checked.exit_code == 0, checked.output


@pytest.mark.parametrize(("name", "key"), [("demo-valve-at-speed", "base_radius"),
                                           ("demo-cylindrical", "radius")])
def test_a_roller_life_no_size_reaches_is_refused_naming_it(tmp_path: Path, name: str,
                                                           key: str) -> None:
    """A roller's life falls as the cam grows (the roller turns more often a turn): held to
    a pressure angle that needs a cam larger than the life allows, no size meets both.
    `camfab size` says so naming the life (exit 1); a build of `auto` refuses the design on
    the key's line (exit 2, nothing written)."""
    pressure = 12 if key == "base_radius" else 20
    smallest = design_from_text(_with_life(name, {"pressure_angle": pressure}))
    sized = size_design(smallest, frozenset({f"cam.{key}"}))
    assert sized.size is not None
    # the life on the least cam the pressure angle allows, and on one a tenth smaller
    at_least = _life(_with_life(name, {"pressure_angle": pressure}, **{key: sized.size}))
    smaller = _life(_with_life(name, {"pressure_angle": 89}, **{key: 0.9 * sized.size}))
    assert smaller > at_least  # life falls as the cam grows
    limit = 0.5 * (smaller + at_least)  # met by the smaller cam, not by any large enough
    text = _with_life(name, {"pressure_angle": pressure, "roller_life": f"{limit!r} h"},
                      **{key: "auto"})
    path = tmp_path / "d.yaml"
    path.write_text(text)
    result = run_cli("size", str(path))
    assert result.exit_code == 1, result.output
    words = " ".join(result.output.split())
    size_name = "base radius" if key == "base_radius" else "drum radius"
    assert re.search(rf"no {size_name} up to [\d.]+ mm meets the limits: the "
                     r"roller's bearing life is [\d.e+]+ h at a", words), words
    assert "fails at every larger" in words
    assert re.search(r"where it holds, pressure angle[^;]* is", words), words
    built = run_cli("build", str(path), "-o", str(tmp_path / "out"))
    assert built.exit_code == 2
    line = text.splitlines().index(f"  {key}: auto") + 1
    assert re.fullmatch(rf"{re.escape(str(path))}:{line}: cam\.{key}: auto: no .* the roller's "
                        r"bearing life .*", built.stderr.strip()), built.stderr
    assert not (tmp_path / "out").exists()
