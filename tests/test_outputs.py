"""The files a build writes: report JSON keys (SPEC §5) and the motion table."""

from __future__ import annotations

import csv
import io
import json
import math
from pathlib import Path

import numpy as np
import pytest

from camfab.export.motion_csv import render_motion_csv
from camfab.export.report_json import render_report_json
from camfab.pipeline import analyse, design_from_text, load_design

from .conftest import DESIGNS


def report_of(path: Path) -> dict:
    return json.loads(render_report_json(analyse(load_design(path))))


def table_of(design) -> list[dict[str, str]]:
    return list(csv.DictReader(io.StringIO(render_motion_csv(analyse(design)).decode())))


def test_report_has_the_contract_keys() -> None:
    report = report_of(DESIGNS / "seed-10-4.yaml")
    for key in ("camfab_version", "name", "cam_type", "follower", "geometry", "segments",
                "checks", "dynamics", "verification"):
        assert key in report
    assert {k: report["follower"][k] for k in ("type", "motion")} == {"type": "roller",
                                                                    "motion": "translating"}
    assert report["follower"]["roller_radius_mm"] == 7.0
    geometry = report["geometry"]
    for key in ("base_radius_mm", "prime_radius_mm", "max_radius_mm",
                "pitch_min_radius_of_curvature_mm", "profile_min_radius_of_curvature_mm",
                "profile_min_concave_radius_mm", "face_width_required_mm"):
        assert key in geometry
    assert geometry["base_radius_mm"] == 20.0 and geometry["prime_radius_mm"] == 27.0
    segment = report["segments"][0]
    for key in ("kind", "law", "start_deg", "end_deg", "lift_mm", "max_velocity_m_s",
                "max_acceleration_m_s2", "max_jerk_m_s3", "max_pressure_angle_deg"):
        assert key in segment
    assert segment["start_deg"] == 0.0 and segment["end_deg"] == 120.0
    for check in report["checks"]:
        assert set(check) >= {"id", "ok", "severity", "message", "value", "limit", "ranges_deg"}
        assert check["severity"] in ("error", "warning")
    assert set(report["dynamics"]) >= {"jump_speed_rpm", "min_contact_force_N",
                                       "required_preload_N"}
    assert "max_lift_error_mm" in report["verification"]


def test_oscillating_report_uses_angular_keys() -> None:
    report = report_of(DESIGNS / "seed-10-3-oscillating.yaml")
    segment = report["segments"][0]
    assert segment["lift_deg"] == pytest.approx(28.0)
    assert "max_angular_velocity_rad_s" in segment and "max_angular_jerk_rad_s3" in segment
    assert segment["max_angular_velocity_rad_s"] is None  # no speed given
    assert segment["max_velocity_rad_per_rad"] == pytest.approx(
        math.radians(28) * (math.pi / 2) / math.radians(80))


def test_motion_table_rows_columns_and_right_limits() -> None:
    rows = table_of(load_design(DESIGNS / "seed-10-4.yaml"))
    assert len(rows) == 360
    assert list(rows[0]) == ["cam_angle_deg", "displacement_mm", "velocity_m_s",
                             "acceleration_m_s2", "jerk_m_s3", "pressure_angle_deg",
                             "pitch_radius_of_curvature_mm", "profile_radius_of_curvature_mm"]
    assert float(rows[0]["cam_angle_deg"]) == 0 and float(rows[-1]["cam_angle_deg"]) == 359
    # SHM rise: s = 20(1 - cos(1.5 θ)), a at 0 is the value after the step
    for row in rows[:120:7]:
        theta = math.radians(float(row["cam_angle_deg"]))
        assert float(row["displacement_mm"]) == pytest.approx(
            20 * (1 - math.cos(1.5 * theta)), abs=1e-8)
    assert float(rows[0]["acceleration_m_s2"]) == pytest.approx(493.48, rel=1e-4)
    assert float(rows[120]["acceleration_m_s2"]) == 0.0  # the dwell, just after the step
    assert float(rows[180]["acceleration_m_s2"]) == pytest.approx(-900.0, rel=1e-9)
    # the seed's formula tan φ = (s′ − e)/(√(Rp² − e²) + s) with e = 10, Rp = 27 (ccw)
    for row in rows[::11]:
        theta = math.radians(float(row["cam_angle_deg"]))
        s = float(row["displacement_mm"])
        v = float(row["velocity_m_s"]) * 1000 / (1000 * math.pi / 30)
        phi = math.degrees(math.atan((v - 10) / (math.sqrt(27**2 - 10**2) + s)))
        assert float(row["pressure_angle_deg"]) == pytest.approx(phi, abs=1e-6)
    # on the base-circle dwell the pitch curve is the prime circle, the profile the base circle
    assert float(rows[300]["pitch_radius_of_curvature_mm"]) == pytest.approx(27.0, abs=1e-9)
    assert float(rows[300]["profile_radius_of_curvature_mm"]) == pytest.approx(20.0, abs=1e-9)


def test_motion_table_without_speed_and_oscillating() -> None:
    rows = table_of(load_design(DESIGNS / "seed-10-3-oscillating.yaml"))
    assert list(rows[0]) == ["cam_angle_deg", "displacement_deg", "pressure_angle_deg",
                             "pitch_radius_of_curvature_mm", "profile_radius_of_curvature_mm"]
    assert max(float(r["displacement_deg"]) for r in rows) == pytest.approx(28.0)


def test_table_step() -> None:
    text = (DESIGNS / "seed-10-4.yaml").read_text() + "table_step: 2.5\n"
    rows = table_of(design_from_text(text))
    assert len(rows) == 144 and float(rows[1]["cam_angle_deg"]) == 2.5


def test_inch_design_is_converted_once_to_mm() -> None:
    design = load_design(DESIGNS / "demo-inch-flat.yaml")
    assert design.cam.base_radius == pytest.approx(31.75)
    assert design.cam.keyway.width == pytest.approx(3.175)
    assert design.cam.keyway.depth == pytest.approx(1.6)
    assert design.cam.speed_rpm == pytest.approx(900)
    report = json.loads(render_report_json(analyse(design)))
    assert report["units"] == "in"
    assert report["segments"][0]["lift_mm"] == pytest.approx(12.7)


@pytest.mark.parametrize(("text", "mm"), [("'1.5 in'", 38.1), ("'38.1 mm'", 38.1),
                                          ("'3.81 cm'", 38.1), ("38.1", 38.1)])
def test_units_on_values(text: str, mm: float) -> None:
    design_text = (DESIGNS / "seed-10-4.yaml").read_text().replace(
        "base_radius: 20 ", f"base_radius: {text} ")
    assert design_from_text(design_text).cam.base_radius == pytest.approx(mm)


def test_unit_strings_for_speed_rate_and_angles() -> None:
    text = (DESIGNS / "seed-jump-eccentric.yaml").read_text()
    text = text.replace("speed_rpm: 1500", "speed_rpm: '157.07963 rad/s'")
    text = text.replace("angle: 180, lift: 75", "angle: '0.5 turn', lift: '7.5 cm'")
    text = text.replace('rate: "24 N/mm"', 'rate: "24000 N/m"')
    design = design_from_text(text)
    assert design.cam.speed_rpm == pytest.approx(1500, rel=1e-6)
    assert design.spring.rate == pytest.approx(24.0)
    assert design.motion[0].angle == pytest.approx(math.pi)
    assert design.motion[0].lift == pytest.approx(75.0)


def test_table_law_from_csv_file(tmp_path: Path) -> None:
    (tmp_path / "rise.csv").write_text("angle,displacement\n0,0\n30,2\n60,9\n90,10\n")
    text = (DESIGNS / "seed-10-4.yaml").read_text().replace(
        "  - rise:   {angle: 120, lift: 40, law: harmonic}\n  - dwell:  {angle: 60}\n",
        "  - rise:   {angle: 90, law: table, csv: rise.csv}\n  - dwell:  {angle: 90}\n")
    (tmp_path / "d.yaml").write_text(text)
    design = load_design(tmp_path / "d.yaml")
    program = analyse(design).program
    s = program.evaluate(np.radians([0, 30, 60, 90]))[0]
    np.testing.assert_allclose(s, [0, 2, 9, 10], atol=1e-9)


def test_reports_are_deterministic() -> None:
    design = load_design(DESIGNS / "demo-table.yaml")
    assert render_report_json(analyse(design)) == render_report_json(analyse(design))
    assert render_motion_csv(analyse(design)) == render_motion_csv(analyse(design))
