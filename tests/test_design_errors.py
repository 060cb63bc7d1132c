"""Bad input: one line naming the file, line and field, exit status 2, no traceback, nothing
written. Each case is a distinct mistake a designer makes."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st

from camfab.errors import CamfabError
from camfab.pipeline import analyse, design_from_mapping, design_from_text, render

from .conftest import DESIGNS, run_cli

BASE = """\
name: bad-design
units: mm
cam:
  type: disc
  rotation: ccw
  speed_rpm: 1000
  base_radius: 20
  thickness: 10
  bore: 10
follower:
  type: roller
  motion: translating
  offset: 10
  roller_radius: 7
motion:
  - rise:   {angle: 120, lift: 40, law: harmonic}
  - dwell:  {angle: 60}
  - return: {angle: 80, law: uniform-acceleration}
  - dwell:  {angle: 100}
"""

# (id, old text, new text, line, field, words the message must contain)
CASES = [
    ("unknown-top-key", "units: mm", "unit: mm", 2, "unit", "did you mean 'units'"),
    ("unknown-cam-key", "  bore: 10", "  boar: 10", 9, "cam.boar", "did you mean 'bore'"),
    ("unknown-follower-key", "  roller_radius: 7", "  roller_radis: 7", 14,
     "follower.roller_radis", "did you mean 'roller_radius'"),
    ("unknown-law", "law: harmonic", "law: cycloid", 16, "motion[0].law", "'cycloidal'"),
    ("unknown-segment", "  - dwell:  {angle: 60}", "  - dwel:  {angle: 60}", 17, "motion[1]",
     "did you mean 'dwell'"),
    ("negative-angle", "{angle: 60}", "{angle: -30}", 17, "motion[1].angle", "must be > 0"),
    ("angles-not-360", "{angle: 100}", "{angle: 90}", 15, "motion", "sum to 350"),
    ("negative-lift", "lift: 40", "lift: -40", 16, "motion[0].lift", "must be > 0"),
    ("lift-not-a-number", "lift: 40", "lift: forty", 16, "motion[0].lift", "must be a length"),
    ("wrong-unit-kind", "base_radius: 20", "base_radius: '20 kg'", 7, "cam.base_radius",
     "must be a length"),
    ("unknown-unit", "base_radius: 20", "base_radius: '20 furlongz'", 7, "cam.base_radius",
     "unknown unit"),
    ("speed-in-mm", "speed_rpm: 1000", "speed_rpm: '1000 mm'", 6, "cam.speed_rpm",
     "rotational speed"),
    ("bool-as-number", "base_radius: 20", "base_radius: yes", 7, "cam.base_radius",
     "must be a length"),
    ("nan", "base_radius: 20", "base_radius: .nan", 7, "cam.base_radius", "finite"),
    ("bad-rotation", "rotation: ccw", "rotation: clockwise", 5, "cam.rotation", "allowed: ccw, cw"),
    ("bad-follower-type", "type: roller", "type: rollr", 11, "follower.type",
     "did you mean 'roller'"),
    ("missing-roller-radius", "  roller_radius: 7\n", "", 10, "follower.roller_radius",
     "required"),
    ("offset-beyond-prime", "offset: 10", "offset: 30", 13, "follower.offset",
     "prime circle radius 27"),
    ("return-below-zero", "law: uniform-acceleration}", "law: uniform-acceleration, lift: 50}",
     18, "motion[2].lift", "below zero"),
    ("not-periodic", "law: uniform-acceleration}", "law: uniform-acceleration, lift: 30}", 15,
     "motion", "periodic"),
    ("dwell-with-law", "{angle: 60}", "{angle: 60, law: harmonic}", 17, "motion[1].law",
     "only an angle"),
    ("param-of-other-law", "law: harmonic}", "law: harmonic, blend: 0.2}", 16, "motion[0].blend",
     "modified-uniform-velocity"),
    ("blend-out-of-range", "law: harmonic}", "law: modified-uniform-velocity, blend: 0.7}", 16,
     "motion[0].blend", "≤ 0.5"),
    ("rise-without-law", "lift: 40, law: harmonic}", "lift: 40}", 16, "motion[0].law",
     "required"),
    ("rise-without-lift", "{angle: 120, lift: 40, law: harmonic}", "{angle: 120, law: harmonic}",
     16, "motion[0].lift", "required"),
    ("bad-name", "name: bad-design", "name: Bad Design", 1, "name", "a-z"),
    ("missing-name", "name: bad-design\n", "", None, "name", "required"),
    ("yaml-syntax", "  - dwell:  {angle: 60}", "  - dwell:  {angle: 60", 18, "", "invalid YAML"),
    ("tab-indent", "  bore: 10", "\tbore: 10", 9, "", "invalid YAML"),
    ("duplicate-key", "  bore: 10", "  bore: 10\n  bore: 12", 10, "cam.bore", "duplicate"),
    ("bore-too-big", "bore: 10", "bore: 40", 9, "cam.bore", "material"),
    ("unknown-cam", "type: disc", "type: grove", 4, "cam.type", "groove"),
    ("keyway-without-bore", "  bore: 10", "  keyway: {width: 3, depth: 1}", 9, "cam.keyway",
     "needs a bore"),
    ("motion-not-list", "  - rise:   {angle: 120, lift: 40, law: harmonic}\n", "", None,
     "motion", None),
    ("preload-and-compression", "  - dwell:  {angle: 100}\n",
     "  - dwell:  {angle: 100}\nspring: {rate: 10, preload: 5, initial_compression: 2}\n", 20,
     "spring.initial_compression", "not both"),
    ("oscillating-unreachable", "  motion: translating\n  offset: 10\n",
     "  motion: oscillating\n  pivot_distance: 200\n  arm_length: 20\n", 14,
     "follower.arm_length", "cannot reach"),
    ("pressure-limit-90", "  - dwell:  {angle: 100}\n",
     "  - dwell:  {angle: 100}\nlimits: {pressure_angle: 95}\n", 20, "limits.pressure_angle",
     "below 90"),
    ("table-step", "  - dwell:  {angle: 100}\n", "  - dwell:  {angle: 100}\ntable_step: 7\n", 20,
     "table_step", "divide 360"),
    ("pivot-inside-cam", "  motion: translating\n  offset: 10\n",
     "  motion: oscillating\n  pivot_distance: 35\n  arm_length: 25\n", 13,
     "follower.pivot_distance", "pivot must lie outside the cam"),
    ("face-swings-faster-than-cam", "  type: roller\n  motion: translating\n  offset: 10\n"
     "  roller_radius: 7\n", "  type: flat\n  motion: oscillating\n  pivot_distance: 60\n"
     "  arm_length: 40\n", 18, "motion[2]", "swing slower than the cam"),  # 40° back in 80°
    ("kerf-wider-than-bore", "  - dwell:  {angle: 100}\n",
     "  - dwell:  {angle: 100}\nmanufacturing: {kerf: 12}\n", 20, "manufacturing.kerf",
     "smaller than the bore"),
    ("kerf-wider-than-keyway", "  bore: 10\n",
     "  bore: 10\n  keyway: {width: 2, depth: 1}\n", None, "manufacturing.kerf", "keyway"),
    ("negative-cutter", "  - dwell:  {angle: 100}\n",
     "  - dwell:  {angle: 100}\nmanufacturing: {cutter_radius: -2}\n", 20,
     "manufacturing.cutter_radius", None),
    # a unit must have the field's dimension, and name nothing but units
    ("angle-squared", "{angle: 120,", "{angle: '120 degree*degree',", 16, "motion[0].angle",
     "must be an angle"),
    ("turns-per-turn", "base_radius: 20", "base_radius: '20 turn/revolution'", 7,
     "cam.base_radius", "cancels out"),
    ("unit-to-the-zero", "base_radius: 20", "base_radius: '20 mm**0'", 7, "cam.base_radius",
     "cancels out"),
    ("percent", "base_radius: 20", "base_radius: '20 percent'", 7, "cam.base_radius",
     "'percent' is a pure number"),
    ("ppm", "offset: 10", "offset: '10 ppm'", 13, "follower.offset", "'ppm' is a pure number"),
    ("pi-times", "roller_radius: 7", "roller_radius: '2 pi*mm'", 14, "follower.roller_radius",
     "'pi' is a pure number"),
    ("speed-per-turn", "speed_rpm: 1000", "speed_rpm: '1000 rpm*turn'", 6, "cam.speed_rpm",
     "rotational speed"),
    ("mass-in-percent", "  roller_radius: 7\n", "  roller_radius: 7\n  mass: '5 percent'\n", 15,
     "follower.mass", "pure number"),
    # every number that sets how finely camfab samples has a lower bound on its line
    ("table-step-tiny", "  - dwell:  {angle: 100}\n",
     "  - dwell:  {angle: 100}\ntable_step: 0.000001\n", 20, "table_step", "at least 0.01°"),
    ("blend-tiny", "law: harmonic}", "law: modified-uniform-velocity, blend: 1.0e-8}", 16,
     "motion[0].blend", "≥ 0.001"),
    # the name places the files: it cannot climb out of exports/ or hide them
    ("name-dot-dot", "name: bad-design", "name: '..'", 1, "name", "start with a letter"),
    ("name-dot", "name: bad-design", "name: '.'", 1, "name", "start with a letter"),
    ("name-hidden", "name: bad-design", "name: .cam", 1, "name", "start with a letter"),
    # a path no file system takes: a NUL character ("\\0" in YAML's double quotes)
    ("table-csv-nul", "law: harmonic}", 'law: table, csv: "lift\\0.csv"}', 16, "motion[0].csv",
     "a path holds no NUL character (got 'lift\\x00.csv')"),
]


@pytest.mark.parametrize(("case", "old", "new", "line", "field", "words"), CASES,
                         ids=[c[0] for c in CASES])
def test_bad_design_gives_one_located_line_and_exit_2(
    tmp_path: Path, case: str, old: str, new: str, line: int | None, field: str,
    words: str | None,
) -> None:
    assert old in BASE, case
    text = BASE.replace(old, new, 1)
    if case == "kerf-wider-than-keyway":
        text += "manufacturing: {kerf: 2.5}\n"
        line = text.count("\n")
    if case == "motion-not-list":
        text = text.replace("motion:\n", "motion: 12\n").split("  - dwell")[0]
    design = tmp_path / "design.yaml"
    design.write_text(text)
    result = run_cli("build", "design.yaml", cwd=tmp_path)
    assert result.exit_code == 2, result.output
    message = result.stderr.strip()
    assert "\n" not in message and "Traceback" not in message
    head = f"design.yaml:{line}: " if line is not None else "design.yaml:"
    assert message.startswith(head), message
    if field:
        assert f": {field}: " in message, message
    if words:
        assert words in message, message
    assert not (tmp_path / "exports").exists()  # nothing written


@pytest.mark.parametrize("command", ["check", "build", "size"])
@pytest.mark.parametrize("name", ["lift.csv", "data/lift.csv"])
def test_a_table_csv_that_is_a_symbolic_link_loop_is_one_located_line(
        tmp_path: Path, command: str, name: str) -> None:
    """A table law's CSV whose path loops through symbolic links (the file itself, or a folder
    on its way) is refused on its line as every other unreadable CSV is, not an internal
    error."""
    text = BASE.replace("law: harmonic}", f"law: table, csv: {name}}}", 1)
    (tmp_path / "design.yaml").write_text(text)
    first = tmp_path / name.split("/")[0]
    first.symlink_to("loop")
    (tmp_path / "loop").symlink_to(first.name)
    before = sorted(p.name for p in tmp_path.iterdir())
    result = run_cli(command, "design.yaml", cwd=tmp_path)
    assert result.exit_code == 2, result.output
    message = result.stderr.strip()
    assert "\n" not in message and "internal error" not in message, message
    assert message.startswith(f"design.yaml:16: motion[0].csv: cannot read the table: {name} "
                              "cannot be read ("), message
    assert sorted(p.name for p in tmp_path.iterdir()) == before  # nothing written


def test_missing_file(tmp_path: Path) -> None:
    result = run_cli("build", "nope.yaml", cwd=tmp_path)
    assert result.exit_code == 2
    assert result.stderr.strip() == "nope.yaml: no such design file"


def test_binary_garbage_and_empty_file(tmp_path: Path) -> None:
    (tmp_path / "bin.yaml").write_bytes(bytes(range(256)) * 4)
    (tmp_path / "empty.yaml").write_text("")
    for name in ("bin.yaml", "empty.yaml"):
        result = run_cli("check", name, cwd=tmp_path)
        assert result.exit_code == 2
        assert re.match(rf"{name}:\d+: \S", result.stderr), result.stderr
        assert "Traceback" not in result.stderr


def test_failed_build_leaves_earlier_outputs_intact(tmp_path: Path) -> None:
    good = (DESIGNS / "seed-10-4.yaml").read_text()
    (tmp_path / "d.yaml").write_text(good)
    assert run_cli("build", "d.yaml", cwd=tmp_path).exit_code == 1  # built, with a finding
    report = tmp_path / "exports" / "seed-10-4" / "seed-10-4-report.json"
    before = report.read_bytes()
    (tmp_path / "d.yaml").write_text(good.replace("lift: 40", "lift: -40"))
    assert run_cli("build", "d.yaml", cwd=tmp_path).exit_code == 2
    assert report.read_bytes() == before
    assert sorted(p.name for p in report.parent.iterdir()) == [
        "seed-10-4-motion.csv", "seed-10-4-report.html", "seed-10-4-report.json",
        "seed-10-4.dxf", "seed-10-4.stl", "seed-10-4.svg"]  # no temporary files left


# ---- property-based: mutated designs end in a design or one clean message -------------------

EXAMPLES = [(DESIGNS / f"{n}.yaml").read_text() for n in
            ("seed-10-4", "demo-table", "seed-poly-345", "demo-inch-flat", "demo-cylindrical")]
NOISE = [*":{}[],-#'\"\n\t &*!|>%@`0123456789.e+ abcxyz", "\x00", "é", "\ufeff"]


@st.composite
def mutated_texts(draw) -> str:
    text = list(draw(st.sampled_from(EXAMPLES)))
    for _ in range(draw(st.integers(1, 4))):
        i = draw(st.integers(0, len(text) - 1))
        op = draw(st.sampled_from(["replace", "delete", "insert"]))
        if op == "replace":
            text[i] = draw(st.sampled_from(NOISE))
        elif op == "delete":
            del text[i]
        else:
            text.insert(i, draw(st.sampled_from(NOISE)))
    return "".join(text)


@given(mutated_texts())
@settings(max_examples=300, deadline=None)
def test_mutated_text_builds_or_fails_with_one_line(text: str) -> None:
    try:
        analysis = analyse(design_from_text(text, "d.yaml"))
        render(analysis)
    except CamfabError as exc:
        assert "\n" not in str(exc) and str(exc).startswith("d.yaml")


VALUES = st.one_of(st.none(), st.booleans(), st.integers(-10**6, 10**6),
                   st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=12),
                   st.lists(st.integers(), max_size=3),
                   st.dictionaries(st.text(max_size=5), st.integers(), max_size=2))


@given(st.data())
@settings(max_examples=300, deadline=None)
def test_mutated_values_build_or_fail_cleanly(data) -> None:
    design = yaml.safe_load(EXAMPLES[0])
    for _ in range(data.draw(st.integers(1, 3))):
        node = design
        path = data.draw(st.sampled_from([("name",), ("units",), ("cam", "type"),
                                          ("cam", "base_radius"), ("cam", "speed_rpm"),
                                          ("follower", "type"), ("follower", "offset"),
                                          ("follower", "motion"), ("motion", 0), ("motion", 1),
                                          ("motion",), ("cam",), ("follower",)]))
        try:
            for key in path[:-1]:
                node = node[key]
            node[path[-1]] = data.draw(VALUES)
        except (TypeError, KeyError, IndexError):
            continue  # an earlier draw replaced a parent of this path
    try:
        render(analyse(design_from_mapping(design)))
    except CamfabError as exc:
        assert "\n" not in str(exc)


def test_a_linear_cam_refuses_a_flat_face_and_says_why(tmp_path: Path) -> None:
    (tmp_path / "ca.yaml").write_text(
        "name: ca\ncam:\n  type: linear\n  stroke: 300\n  base_height: 5\n"
        "follower: {type: flat}\nmotion:\n  - dwell: {travel: 300}\n")
    result = run_cli("check", "ca.yaml", cwd=tmp_path)
    assert result.exit_code == 2
    assert result.stderr.startswith("ca.yaml:6: follower.type: a linear cam takes a roller or "
                                    "knife follower")
    assert "rests on the highest point" in result.stderr


@pytest.mark.parametrize("top_deg", [89.0, 91.0])
def test_an_oscillating_flat_face_that_would_swing_past_90_degrees_is_refused(
        tmp_path: Path, top_deg: float) -> None:
    """The face line lies a·sin Ψ − f from the cam centre: past Ψ = 90° that distance falls as
    the face swings out, the contact passes behind the pivot and no cam drives the face there
    (built, such a cam read back 9 mm off its motion). The demo's 15° swing is made to end at
    *top_deg* from the line of centres through its base radius: sin ψ₀ = (Rb + f)/a."""
    a, f, swing = 95.0, 8.0, 15.0
    rb = a * math.sin(math.radians(top_deg - swing)) - f
    text = (DESIGNS / "demo-oscillating-flat.yaml").read_text()
    assert "base_radius: 50\n" in text and "pivot_distance: 95\n" in text
    (tmp_path / "d.yaml").write_text(text.replace("base_radius: 50", f"base_radius: {rb!r}"))
    result = run_cli("check", "d.yaml", cwd=tmp_path)
    if top_deg < 90.0:
        assert result.exit_code in (0, 1), result.output
        return
    assert result.exit_code == 2, result.output
    line = text.splitlines().index("  pivot_distance: 95") + 1
    message = result.stderr.strip()
    assert "\n" not in message and "Traceback" not in message
    assert message.startswith(f"d.yaml:{line}: follower.pivot_distance: "), message
    assert "past 90°" in message
    assert run_cli("build", "d.yaml", cwd=tmp_path).exit_code == 2
    assert not (tmp_path / "exports").exists()


def test_an_oscillating_flat_face_that_cannot_touch_the_base_circle_is_refused(
        tmp_path: Path) -> None:
    """(Rb + f)/a = 1.037: no arm angle puts the face line on the base circle."""
    text = (DESIGNS / "demo-oscillating-flat.yaml").read_text()
    (tmp_path / "d.yaml").write_text(text.replace("base_radius: 50", "base_radius: 90.5"))
    result = run_cli("build", "d.yaml", cwd=tmp_path)
    assert result.exit_code == 2, result.output
    assert re.fullmatch(r"d\.yaml:\d+: follower\.face_offset: .*= 1\.037 must lie in \(0, 1\).*",
                        result.stderr.strip()), result.stderr
    assert not (tmp_path / "exports").exists()
