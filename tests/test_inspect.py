"""``camfab inspect``: a made or scanned cam's outline against its design.

References are independent of the inspection code: the design's motion table (written by the
build), closed forms of an eccentric (circular) cam, and the base circle on which a bump's contact
angle follows from the follower's position.
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest

from camfab.pipeline import analyse, load_design, render

from .conftest import DESIGN_FILES, DESIGNS, run_cli

SEED = DESIGNS / "seed-10-4.yaml"
ECCENTRIC = DESIGNS / "seed-jump-eccentric.yaml"


def _eligible(path: Path) -> dict[str, float] | None:
    """What the tests need of a design whose analysis has a disc outline that is not undercut
    (an undercut cam's outline differs from its design on purpose), else None."""
    design = load_design(path)
    if design.cam.type in ("cylindrical", "groove"):  # a groove cam's CUT is its plate's circle
        return None
    geom = analyse(design).geometry
    if geom is None or geom.undercut:
        return None
    fol = design.follower
    return {"tolerance": design.manufacturing.tolerance,
            "arm": fol.arm_length if fol.oscillating else 0.0}


#: Every example design with a disc outline that should match its design, and what the tests
#: need of it (drum cams have no plate outline, a groove cam's outline is a circle with the cam
#: in a pocket; an undercut cam's differs on purpose).
ELIGIBLE = {p.stem: f for p in DESIGN_FILES if (f := _eligible(p)) is not None}


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict[str, dict[str, float]]]:
    """Every eligible example design built once (DXF and motion table), each into its own
    folder ``NAME/`` of one folder, as a batch build writes them."""
    folder = tmp_path_factory.mktemp("built")
    facts = ELIGIBLE
    paths = [str(DESIGNS / f"{name}.yaml") for name in facts]
    result = run_cli("build", "-j", "4", *paths, "-o", str(folder))
    assert result.exit_code in (0, 1), result.output + result.stderr
    return folder, facts


def _own(folder: Path, name: str) -> Path:
    """The plate outline of the example design *name* in the batch build's *folder*."""
    return folder / name / f"{name}.dxf"


def _read_csv(path: Path) -> dict[str, np.ndarray]:
    with path.open() as stream:
        rows = list(csv.DictReader(stream))
    return {key: np.array([float(r[key]) if r[key] else np.nan for r in rows])
            for key in rows[0]}


def _inspect(tmp_path: Path, profile: Path, *args: str) -> tuple[int, dict, dict, str]:
    """Run ``camfab inspect``; the exit code, the JSON report, the lift table and stderr."""
    out = tmp_path / "out"
    result = run_cli("inspect", str(profile), *args, "-o", str(out))
    stem = profile.stem
    report, table = {}, {}
    if result.exit_code in (0, 1):
        report = json.loads((out / f"{stem}-inspection.json").read_text())
        table = _read_csv(out / f"{stem}-lift.csv")
        assert (out / f"{stem}-inspection.html").is_file()
    return result.exit_code, report, table, result.stderr


@pytest.mark.parametrize("name", sorted(ELIGIBLE))
def test_own_dxf_reproduces_the_design_lift(built, tmp_path: Path, name: str) -> None:
    folder, facts = built
    path = DESIGNS / f"{name}.yaml"
    tolerance, arm = facts[name]["tolerance"], facts[name]["arm"]
    dxf = folder / name / f"{name}.dxf"
    if not dxf.exists():  # a conjugate pair: cam a is the design's own cam
        dxf = folder / name / f"{name}-a.dxf"
    code, report, table, err = _inspect(tmp_path, dxf, "--design", str(path))
    assert code == 0, err
    assert report["deviation"]["max_mm"] <= tolerance
    assert report["deviation"]["within_tolerance"] is True
    # the measured lift against the design's own motion table, row by row
    motion = _read_csv(folder / name / f"{name}-motion.csv")
    if arm:
        error = np.radians(table["lift_deg"] - motion["displacement_deg"]) * arm
    else:
        error = table["lift_mm"] - motion["displacement_mm"]
    assert np.array_equal(table["cam_angle_deg"], motion["cam_angle_deg"])
    assert np.max(np.abs(error)) <= tolerance


def test_laser_file_kerf_is_taken_off_from_the_drawing_note(built, tmp_path: Path) -> None:
    folder, _ = built
    design = DESIGNS / "demo-laser-kerf.yaml"
    code, report, _, _ = _inspect(tmp_path, _own(folder, "demo-laser-kerf"), "--design",
                                  str(design))
    assert code == 0
    assert report["profile"]["kerf_mm"] == pytest.approx(0.2)
    # the beam's path itself is the part grown by kerf/2: on the base-circle dwell the roller
    # (radius 8 mm, offset 4 mm, base radius 30 mm) rides kerf/2 along its radius, so
    # 0.1 mm / cos φ higher along its line of motion, cos φ = √(38² − 4²)/38
    code, report, table, _ = _inspect(tmp_path, _own(folder, "demo-laser-kerf"), "--design",
                                      str(design), "--kerf", "0")
    assert code == 1
    dwell = (table["cam_angle_deg"] > 300) & (table["cam_angle_deg"] < 355)
    expected = 0.1 * 38.0 / math.sqrt(38.0**2 - 4.0**2)
    assert np.allclose(table["deviation_mm"][dwell], expected, atol=0.001)


def _seed_points() -> tuple[np.ndarray, float, float, float]:
    """seed-10-4's exact working curve (closed form, every 0.05° of cam angle) and its base
    radius, roller radius and offset."""
    design = load_design(SEED)
    geom = analyse(design).geometry
    assert geom is not None
    fol = design.follower
    assert design.cam.base_radius and fol.roller_radius
    return geom.dense.working.xy, design.cam.base_radius, fol.roller_radius, fol.offset


def _write_points(path: Path, xy: np.ndarray, header: str = "x,y") -> Path:
    lines = [f"# {len(xy)} points", header] + [f"{x:.9f},{y:.9f}" for x, y in xy]
    path.write_text("\n".join(lines) + "\n")
    return path


def _bump(xy: np.ndarray, centre_deg: float, half_width_deg: float, height: float) -> np.ndarray:
    """*xy* pushed radially outward by a cos² bump of *height* (mm) centred on the polar angle
    *centre_deg*."""
    polar = np.degrees(np.arctan2(xy[:, 1], xy[:, 0]))
    off = (polar - centre_deg + 180.0) % 360.0 - 180.0
    rise = np.where(np.abs(off) < half_width_deg,
                    height * np.cos(0.5 * math.pi * off / half_width_deg) ** 2, 0.0)
    radius = np.hypot(xy[:, 0], xy[:, 1])
    return xy * ((radius + rise) / radius)[:, None]


def test_bump_on_the_base_circle_is_found_where_the_roller_meets_it(tmp_path: Path) -> None:
    xy, base, roller, offset = _seed_points()
    # on the dwell the roller's centre is at (e, y0) and touches the base circle on the line
    # to the cam centre: at the polar angle atan2(y0, e) − θ in the cam (ccw). A bump δ along
    # that line lifts the roller δ/cos φ along its line of motion, cos φ = y0/(Rb + r).
    y0 = math.sqrt((base + roller) ** 2 - offset**2)
    lift = 0.05 * (base + roller) / y0
    theta = 310.0
    polar = math.degrees(math.atan2(y0, offset)) - theta
    bumped = _write_points(tmp_path / "bumped.csv", _bump(xy, polar, 6.0, 0.05))
    code, report, table, _ = _inspect(tmp_path, bumped, "--design", str(SEED),
                                      "--tolerance", "0.01")
    assert code == 1
    dev = report["deviation"]
    assert dev["max_signed_mm"] == pytest.approx(lift, abs=0.001)
    assert dev["max_at_deg"] == pytest.approx(theta, abs=0.5)
    (excursion,) = dev["excursions"]
    assert excursion["start_deg"] < theta < excursion["end_deg"]
    # where on the part: the bump's top
    x, y = dev["max_at_xy_mm"]
    off = (math.degrees(math.atan2(y, x)) - polar + 180.0) % 360.0 - 180.0
    assert off == pytest.approx(0.0, abs=0.5)
    assert math.hypot(x, y) == pytest.approx(base + 0.05, abs=0.01)
    # away from the bump the points hold the design
    far = np.abs(table["cam_angle_deg"] - theta) > 30.0
    assert np.max(np.abs(table["deviation_mm"][far])) < 0.001


def test_bump_on_the_rise_is_found_at_its_contact_angle(tmp_path: Path) -> None:
    design = load_design(SEED)
    geom = analyse(design).geometry
    assert geom is not None
    dense = geom.dense
    # the contact point at θ = 60° (closed form of the working curve), its polar angle, and how
    # far a radial bump there moves the roller along its path: δ·(r̂·n̂)/cos φ
    k = int(np.argmin(np.abs(dense.theta - math.radians(60.0))))
    point = dense.working.xy[k]
    polar = math.degrees(math.atan2(point[1], point[0]))
    tangent = dense.working.tangent[k]
    normal = np.array([tangent[1], -tangent[0]])
    radial = point / np.hypot(*point)
    expected = 0.05 * abs(float(radial @ normal)) / math.cos(dense.pressure_angle[k])
    bumped = _write_points(tmp_path / "rise.csv", _bump(dense.working.xy, polar, 4.0, 0.05))
    code, report, _, _ = _inspect(tmp_path, bumped, "--design", str(SEED), "--tolerance", "0.01")
    assert code == 1
    assert report["deviation"]["max_signed_mm"] == pytest.approx(expected, rel=0.1)
    assert report["deviation"]["max_at_deg"] == pytest.approx(60.0, abs=1.5)


def _eccentric_points(count: int = 2000) -> np.ndarray:
    """seed-jump-eccentric's cam: a circle of radius 60 mm about (0, −37.5) at θ = 0."""
    angle = np.linspace(0.0, 2.0 * math.pi, count, endpoint=False)
    return np.column_stack((60.0 * np.cos(angle), -37.5 + 60.0 * np.sin(angle)))


def _roller_on_eccentric(theta_deg: np.ndarray, roller: float) -> np.ndarray:
    """Closed form: a radial roller's lift on the eccentric turning ccw."""
    t = np.radians(theta_deg)
    cx, cy = 37.5 * np.sin(t), -37.5 * np.cos(t)
    return cy + np.sqrt((60.0 + roller) ** 2 - cx**2) - (22.5 + roller)


def test_a_clean_scan_with_a_gauges_noise_passes_the_inspection_tolerance(
        tmp_path: Path) -> None:
    """A scan of a true part carries its instrument's noise (2 µm here): held to the export
    tolerance (1 µm: how closely the files follow the exact curve) it would fail; the
    inspection tolerance is its own, ±0.025 mm by default, and a design can set it; the
    report's lift table gives the inspector that band."""
    rng = np.random.default_rng(7)
    xy = _eccentric_points()
    radius = np.hypot(xy[:, 0], xy[:, 1] + 37.5)
    noisy = xy + (rng.uniform(-0.002, 0.002, len(xy)) / radius)[:, None] * np.column_stack(
        (xy[:, 0], xy[:, 1] + 37.5))
    scan = _write_points(tmp_path / "scan.csv", noisy)
    code, report, _, err = _inspect(tmp_path, scan, "--design", str(ECCENTRIC))
    assert code == 0, err
    assert report["design"]["tolerance_mm"] == 0.025
    assert 0.001 < report["deviation"]["max_mm"] < 0.025
    tight = tmp_path / "tight.yaml"
    tight.write_text(ECCENTRIC.read_text() + "inspection: {tolerance: 0.001}\n")
    code, report, _, err = _inspect(tmp_path, scan, "--design", str(tight))
    assert code == 1 and report["design"]["tolerance_mm"] == 0.001
    # the build's lift table: the band is the inspection tolerance over cos φ (a flat face: 0)
    files = render(analyse(load_design(ECCENTRIC))).files
    table = json.loads(files["seed-jump-eccentric-report.json"])["lift_table"]
    assert table["inspection_tolerance_mm"] == 0.025
    assert {row[2] for row in table["rows"]} == {0.025}
    assert "the inspection tolerance, ±0.025 mm" in files[
        "seed-jump-eccentric-report.html"].decode()


def test_csv_of_points_and_another_inspection_roller(tmp_path: Path) -> None:
    points = _write_points(tmp_path / "scan.csv", _eccentric_points(), header="X;Y")
    points.write_text(points.read_text().replace(",", ";"))
    code, report, table, err = _inspect(tmp_path, points, "--design", str(ECCENTRIC))
    assert code == 0, err
    # a chord polygon of 2000 points lies within 60·(1 − cos(π/2000)) = 0.07 µm of the circle
    assert report["deviation"]["max_mm"] < 1e-4
    # a dial indicator's roller of 5 mm instead of the design's flat face
    code, report, table, err = _inspect(tmp_path, points, "--design", str(ECCENTRIC),
                                        "--type", "roller", "--roller-radius", "5")
    assert code == 0, err
    assert report["follower"] == {"type": "roller", "motion": "translating", "radius_mm": 5.0,
                                  "offset_mm": 0.0, "pivot_distance_mm": None,
                                  "arm_length_mm": None, "pivot_side": None}
    exact = _roller_on_eccentric(table["cam_angle_deg"], 5.0)
    assert np.max(np.abs(table["lift_mm"] - exact)) < 1e-4
    assert np.max(np.abs(table["design_lift_mm"] - exact)) < 1e-4
    # velocity from the lift's derivative: exact v = ω·ds/dθ
    t = np.radians(table["cam_angle_deg"])
    omega = 1500 * math.pi / 30
    cx = 37.5 * np.sin(t)
    ds = 37.5 * np.sin(t) - cx * 37.5 * np.cos(t) / np.sqrt(65.0**2 - cx**2)
    assert np.max(np.abs(table["velocity_m_s"] - omega * ds / 1000)) < 1e-3 * omega * 37.5 / 1000


def test_own_dxf_with_another_roller_against_the_closed_form(built, tmp_path: Path) -> None:
    folder, _ = built
    code, report, table, err = _inspect(tmp_path, _own(folder, "seed-jump-eccentric"),
                                        "--design", str(ECCENTRIC), "--type", "roller",
                                        "--roller-radius", "12.5")
    assert code == 0, err
    exact = _roller_on_eccentric(table["cam_angle_deg"], 12.5)
    assert np.max(np.abs(table["lift_mm"] - exact)) < 1e-3
    assert "run over" in report["design"]["reference"]


def test_without_a_design_the_follower_comes_from_a_file(built, tmp_path: Path) -> None:
    folder, _ = built
    (tmp_path / "dial.yaml").write_text("units: mm\nrotation: ccw\nspeed_rpm: 1000\n"
                                        "follower: {type: roller, offset: 10, roller_radius: 7}\n")
    code, report, table, err = _inspect(tmp_path, _own(folder, "seed-10-4"),
                                        "--follower", str(tmp_path / "dial.yaml"))
    assert code == 0, err
    assert report["deviation"] is None and report["design"] is None
    assert "design_lift_mm" not in table
    assert report["motion"]["max_lift_mm"] == pytest.approx(40.0, abs=0.002)
    assert report["profile"]["min_radius_mm"] == pytest.approx(20.0, abs=0.001)
    # SHM rise of 40 mm over 120° at 1000 rpm: v_max = (π/2)·h·ω/β
    v_max = math.pi / 2 * 40 * (1000 * math.pi / 30) / math.radians(120) / 1000
    assert np.max(table["velocity_m_s"]) == pytest.approx(v_max, rel=0.01)
    # the command line gives the same follower
    code, report2, _, _ = _inspect(tmp_path, _own(folder, "seed-10-4"), "--type", "roller",
                                   "--roller-radius", "7", "--offset", "10")
    assert code == 0 and report2["motion"]["max_lift_mm"] == report["motion"]["max_lift_mm"]


def test_align_finds_the_phase_of_a_turned_scan(tmp_path: Path) -> None:
    xy, _, _, _ = _seed_points()
    turn = math.radians(-7.0)  # turned against the rotation: its motion runs 7° late
    c, s = math.cos(turn), math.sin(turn)
    turned = _write_points(tmp_path / "turned.csv", xy @ np.array([[c, s], [-s, c]]))
    code, report, _, _ = _inspect(tmp_path, turned, "--design", str(SEED), "--tolerance", "0.01")
    assert code == 1 and report["deviation"]["max_mm"] > 1.0
    code, report, _, err = _inspect(tmp_path, turned, "--design", str(SEED), "--tolerance", "0.01",
                                    "--align")
    assert code == 0, err
    assert report["deviation"]["align_deg"] == pytest.approx(7.0, abs=0.01)
    assert report["deviation"]["max_mm"] < 0.002


def test_foreign_dxf_polyline_with_bulges_off_centre(tmp_path: Path) -> None:
    import ezdxf

    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = 4
    msp = doc.modelspace()
    # the eccentric drawn with its shaft at (100, 50): two half circles as bulges, a bore circle
    # and a frame on another layer
    cx, cy = 100.0, 50.0 - 37.5
    msp.add_lwpolyline([(cx + 60, cy, 1.0), (cx - 60, cy, 1.0)], format="xyb", close=True,
                       dxfattribs={"layer": "PART"})
    msp.add_circle((100.0, 50.0), 10.0, dxfattribs={"layer": "PART"})
    msp.add_lwpolyline([(0, -100), (300, -100), (300, 200), (0, 200)], close=True,
                       dxfattribs={"layer": "FRAME"})
    path = tmp_path / "foreign.dxf"
    doc.saveas(path)
    code, report, _, err = _inspect(tmp_path, path, "--design", str(ECCENTRIC), "--layer", "PART",
                                    "--centre", "100,50")
    assert code == 0, err
    assert report["deviation"]["max_mm"] < 1e-9
    assert report["profile"]["units"].startswith("mm")


def _nothing_written(tmp_path: Path) -> bool:
    return not (tmp_path / "out").exists()


@pytest.mark.parametrize("case", ["missing", "no-contour", "bad-row", "centre", "no-follower",
                                  "align-without-design", "drum-outline", "drum-drawing"])
def test_bad_input_exits_2_with_one_line_and_writes_nothing(tmp_path: Path, case: str) -> None:
    args: list[str] = ["--design", str(SEED)]
    if case == "missing":
        profile = tmp_path / "nothing.dxf"
        expect = "nothing.dxf: no such file"
    elif case == "no-contour":
        import ezdxf

        doc = ezdxf.new("R2010")
        doc.modelspace().add_line((0, 0), (10, 0))
        profile = tmp_path / "open.dxf"
        doc.saveas(profile)
        expect = "open.dxf: has no closed contour"
    elif case == "bad-row":
        profile = tmp_path / "scan.csv"
        profile.write_text("x,y\n1,2\n3,four\n5,6\n")
        expect = "scan.csv:3: not a pair of numbers"
    elif case == "centre":
        profile = _write_points(tmp_path / "scan.csv", _eccentric_points())
        args = ["--design", str(ECCENTRIC), "--centre", "500,500"]
        expect = "lies outside the outline"
    elif case == "no-follower":
        profile = _write_points(tmp_path / "scan.csv", _eccentric_points())
        args = []
        expect = "scan.csv: no follower to run over the outline"
    elif case == "align-without-design":
        profile = _write_points(tmp_path / "scan.csv", _eccentric_points())
        args = ["--type", "knife", "--align"]
        expect = "--align: needs --design"
    elif case == "drum-outline":  # a drum's CSV is a scan: x, y points are not one
        profile = _write_points(tmp_path / "scan.csv", _eccentric_points())
        args = ["--design", str(DESIGNS / "demo-cylindrical.yaml")]
        expect = "does not name the columns x, y, z"
    else:  # a drum's drawing is no outline to inspect: the refusal says what is
        import ezdxf

        doc = ezdxf.new("R2010")
        doc.modelspace().add_circle((0, 0), 30)
        profile = tmp_path / "drum.dxf"
        doc.saveas(profile)
        args = ["--design", str(DESIGNS / "demo-cylindrical.yaml")]
        expect = "demo-cylindrical.yaml: is a drum (cylindrical) cam: its groove is inspected " \
                 "from a 3-D scan"
    code, _, _, err = _inspect(tmp_path, profile, *args)
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and expect in err, err
    assert _nothing_written(tmp_path)


def test_oscillating_follower_from_the_command_line(built, tmp_path: Path) -> None:
    folder, _ = built
    code, report, table, err = _inspect(tmp_path, _own(folder, "seed-10-3-oscillating"),
                                        "--type", "roller", "--roller-radius", "10",
                                        "--pivot-distance", "55", "--arm-length", "45")
    assert code == 0, err
    assert report["follower"]["motion"] == "oscillating"
    # the published swing of seed 10.3: 28°
    assert np.max(table["lift_deg"]) == pytest.approx(28.0, abs=0.01)


@pytest.mark.parametrize(("text", "said"), [
    # an alias bomb: a billion values from a few lines
    ("a: &a [1,1,1,1,1,1,1,1,1,1]\n" + "".join(
        f"{n}: &{n} [{','.join(['*' + p] * 10)}]\n"
        for p, n in zip("abcdefgh", "bcdefghi", strict=True)),
     "expand to more than 100,000 values"),
    ("[" * 100_000, "nested too deeply"),
    ("type: [roller\n", "invalid YAML"),
    ("type: roller\nroller_radius: 5\nroller_radius: 6\n", "roller_radius"),
])
def test_a_follower_file_is_read_within_the_design_limits(built, tmp_path: Path, text: str,
                                                         said: str) -> None:
    """A follower file is refused, quickly and on its line, where a design would be."""
    folder, _ = built
    (tmp_path / "dial.yaml").write_text(text)
    code, _, _, err = _inspect(tmp_path, _own(folder, "seed-10-4"),
                               "--follower", str(tmp_path / "dial.yaml"))
    assert code == 2 and said in err and "dial.yaml" in err and len(err.splitlines()) == 1
    assert not (tmp_path / "out").exists()
