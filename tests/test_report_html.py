"""The HTML report's content, read back from the page: every check, the drawing and the
diagrams inline, dynamics when the design has them, and nothing fetched from a network; the
headings as a quantity and its unit, the inputs the design file takes for the kind, and no
column of a globoid's motion table empty at every row."""

from __future__ import annotations

import html
import json
import re

import pytest

from camfab.pipeline import analyse, design_from_text, load_design, render

from .conftest import DESIGNS


@pytest.mark.parametrize("name", ["seed-jump-eccentric", "demo-undercut", "demo-cylindrical",
                                  "demo-oscillating-flat"])
def test_report_holds_every_check_and_its_figures(name: str) -> None:
    artifacts = render(analyse(load_design(DESIGNS / f"{name}.yaml")))
    analysis = artifacts.analysis
    assert analysis is not None
    page = artifacts.files[f"{name}-report.html"].decode()
    assert page.startswith("<!DOCTYPE html>")
    assert re.search(r"<span class=\"verdict (ok|fail)\">(PASS|FAIL)</span>", page)
    assert ("PASS" if analysis.exit_code == 0 else "FAIL") in page
    # one table row per check, with its id
    rows = re.findall(r'<tr class="(fail|warn|)"><td class="mark', page)
    assert len(rows) == len(analysis.findings)
    for finding in analysis.findings:
        label = finding.id if finding.quantity is None else f"{finding.id} ({finding.quantity})"
        assert f"<td>{label}</td>" in page
    assert len(re.findall(r"<svg[ >]", page)) >= 2  # the drawing and the diagrams
    dyn = analysis.dynamics
    assert ('id="dynamics"' in page) == (dyn is not None and dyn.force_N is not None)
    assert "<metadata>" not in page
    # the verification's numbers are on the page
    assert "max lift error (mm)" in page


def test_undercut_is_marked_on_the_drawing() -> None:
    page = render(analyse(load_design(DESIGNS / "demo-undercut.yaml"))).files[
        "demo-undercut-report.html"].decode()
    assert "undercut" in page and "pressure angle over the limit" in page


def _section(page: str, name: str) -> str:
    found = re.search(rf'<section id="{name}">(.*?)</section>', page, flags=re.S)
    assert found is not None, name
    return found.group(1)


@pytest.mark.parametrize("name", ["demo-globoidal-concave", "seed-10-3-oscillating",
                                  "seed-10-4", "demo-valve-at-speed"])
def test_every_heading_reads_as_a_quantity_and_its_unit(name: str) -> None:
    """The motion table's headings and the key numbers' labels: words, then the unit in
    brackets: an arm's swing per radian of cam angle is "max velocity (rad/rad)", not
    "max velocity rad (/rad)"."""
    design = load_design(DESIGNS / f"{name}.yaml")
    page = render(analyse(design)).files[f"{name}-report.html"].decode()
    heads = [html.unescape(h) for h in re.findall(r"<th>(.*?)</th>", _section(page, "motion"))]
    labels = [html.unescape(h) for h in re.findall(r"<tr><td>(.*?)</td>",
                                                   _section(page, "numbers"))]
    assert heads and labels
    for label in heads + labels:
        assert re.fullmatch(r"[A-Za-z][\w ]*( \([^()/ ][^()]*\))?", label), label
    if design.follower.oscillating:
        for unit in ("velocity (rad/rad)", "acceleration (rad/rad²)", "jerk (rad/rad³)"):
            assert f"max {unit}" in heads, heads


@pytest.mark.parametrize("name", ["demo-cylindrical", "demo-globoidal-concave",
                                  "seed-10-3-oscillating", "demo-oscillating-flat",
                                  "demo-linear-roller", "seed-10-4"])
def test_the_inputs_table_lists_only_the_keys_the_design_file_takes_for_the_kind(
        name: str) -> None:
    """The cam and follower rows of the inputs table are keys the design file takes for the
    design's cam type and follower (the loader refuses any other): no pivot_side or
    face_offset on a drum, no offset on an arm, no arm on a translating follower."""
    from camfab.design.cam_types import CAM_TYPES
    from camfab.design.loader import follower_keys

    design = load_design(DESIGNS / f"{name}.yaml")
    page = render(analyse(design)).files[f"{name}-report.html"].decode()
    keys = re.findall(r"<tr><td>([^<]+)</td>", _section(page, "inputs"))
    fol = design.follower
    spec = CAM_TYPES[design.cam.type]
    accepted = {"cam": spec.cam_keys,
                "follower": follower_keys(spec, {"type": fol.type, "motion": fol.motion})}
    shown = {section: [key.split(".")[1] for key in keys if key.startswith(f"{section}.")]
             for section in accepted}
    for section, names in shown.items():
        assert names and set(names) <= set(accepted[section]), (section, names)
    assert "type" in shown["cam"] and "motion" in shown["follower"]
    if design.cam.type == "cylindrical":
        assert "pivot_side" not in shown["follower"] and "face_offset" not in shown["follower"]
    if fol.oscillating:
        assert "offset" not in shown["follower"] and "arm_length" in shown["follower"]
    else:
        assert "pivot_side" not in shown["follower"] and "arm_length" not in shown["follower"]
    if fol.type != "flat":
        assert "face_offset" not in shown["follower"]


def test_a_globoid_s_motion_table_has_no_column_that_is_always_empty() -> None:
    """A globoid's flanks are surfaces: no pitch or profile radius of curvature (columns that
    were empty at every row); its table, the CSV and the page's readout, gives the undercut
    limit at each angle instead, whose least is the report's undercut_roller_radius_mm. The
    CSV keeps the pitch radius column SPEC §5 names for every table, empty; the readout shows
    no column that is empty at every row."""
    name = "demo-globoidal-concave"
    files = render(analyse(load_design(DESIGNS / f"{name}.yaml"))).files
    lines = files[f"{name}-motion.csv"].decode().strip().splitlines()
    header = lines[0].split(",")
    rows = [line.split(",") for line in lines[1:]]
    for k, column in enumerate(header):
        assert any(row[k] for row in rows) == (column != "pitch_radius_of_curvature_mm"), column
    assert [c for c in header if "curvature" in c] == ["pitch_radius_of_curvature_mm"]
    limit = [float(row[header.index("undercut_roller_radius_mm")]) for row in rows]
    report = json.loads(files[f"{name}-report.json"])
    least = report["geometry"]["undercut_roller_radius_mm"]
    assert min(limit) == pytest.approx(least, rel=2e-3)  # the table's 1° rows, the least
    assert min(limit) >= least - 1e-9                    # found on the 0.05° grid
    page = files[f"{name}-report.html"].decode()
    readout = [html.unescape(h) for h in re.findall(r"<th>(.*?)</th>", _section(page, "drawing"))]
    assert "undercut roller radius (mm)" in readout
    assert not [label for label in readout if "curvature" in label]


def _check_rows(page: str) -> dict[str, list[str]]:
    """The check table's cells by check label: mark, label, severity, value, limit, where."""
    rows = {}
    for row in re.findall(r'<tr class="(?:fail|warn|na|)">(.*?)</tr>', _section(page, "findings"),
                          flags=re.S):
        cells = [html.unescape(re.sub(r"<[^>]+>", "", cell)).strip()
                 for cell in re.findall(r"<td[^>]*>(.*?)</td>", row, flags=re.S)]
        rows[cells[1]] = cells
    return rows


def test_the_check_table_shows_real_limits_and_where_each_value_is() -> None:
    """A jerk step passes whatever its size: no limit (not "limit 0 m/s³" beside a passing
    416373.9 m/s³); a passing pressure angle says where it is largest, as its message does;
    the inputs carry their units (mass kg, stiffness N/mm, load rating N, …), in the page and
    in the JSON's ``design_units``."""
    text = (DESIGNS / "demo-valve-at-speed.yaml").read_text().replace("polynomial-4567",
                                                                       "cycloidal")
    files = render(analyse(design_from_text(text))).files
    page = files["demo-valve-at-speed-report.html"].decode()
    report = json.loads(files["demo-valve-at-speed-report.json"])
    checks = {(c["id"], c.get("quantity")): c for c in report["checks"]}
    jerk = checks[("continuity", "jerk")]
    assert jerk["ok"] and jerk["value"] > 0 and jerk["limit"] is None
    rows = _check_rows(page)
    assert rows["continuity (jerk)"][4] == ""
    # the steps' places, the joints of the cycloidal rise and return with the dwells
    assert rows["continuity (jerk)"][5] == "0, 110, 130, 240"
    pressure = checks[("pressure_angle", None)]
    assert pressure["ok"] and pressure["ranges_deg"] == []
    at = re.search(r"largest pressure angle [\d.]+° at ([\d.]+)°", pressure["message"])
    assert at is not None
    assert pressure["value_at_deg"] == pytest.approx(float(at.group(1)), abs=5e-3)
    assert rows["pressure_angle"][5] == at.group(1)
    # a velocity step must be none: its limit 0 stays, and means it
    assert checks[("continuity", "velocity")]["limit"] == 0.0
    units = report["design_units"]
    inputs = dict(re.findall(r"<tr><td>([^<]+)</td><td[^>]*>([^<]*)</td>",
                             _section(page, "inputs")))
    for key, value, unit in (("follower.mass", "0.35", "kg"), ("follower.stiffness", "600",
                             "N/mm"), ("follower.roller_load_rating", "6200", "N"),
                             ("spring.rate", "25", "N/mm"), ("spring.preload", "250", "N"),
                             ("cam.speed_rpm", "1500", "rpm"), ("cam.base_radius", "30", "mm"),
                             ("limits.contact_stress", "1200", "MPa"),
                             ("limits.roller_life", "10000.0", "h")):
        assert units[key] == unit, key
        assert html.unescape(inputs[key]) == f"{value} {unit}", key
    assert html.unescape(inputs["motion[0].angle"]) == "110°"
    assert "follower.damping_ratio" not in units and inputs["follower.damping_ratio"] == "0.06"
