"""``camfab inspect SCAN --design``: what is refused, in one line with nothing written, and
what a scan of the exact part gives (camfab's own STL of it: its surface within the mesh's
tolerance, so the motion it gives is the design's)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from tests.conftest import DESIGNS, run_cli

DRUM = DESIGNS / "demo-cylindrical.yaml"
GLOBOID = DESIGNS / "demo-globoidal-convex.yaml"
DISC = DESIGNS / "seed-poly-345.yaml"


def _points_csv(path: Path, points: np.ndarray) -> Path:
    np.savetxt(path, points, delimiter=",", header="x,y,z", comments="", fmt="%.6f")
    return path


@pytest.fixture(scope="module")
def drum_stl(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("drum")
    result = run_cli("build", str(DRUM), "-o", str(out))
    assert result.exit_code == 0, result.stderr
    return out / f"{DRUM.stem}.stl"


def _refused(tmp_path: Path, *args: str) -> str:
    result = run_cli("inspect", *args, "-o", str(tmp_path / "out"))
    assert result.exit_code == 2, result.stdout
    assert len(result.stderr.strip().splitlines()) == 1, result.stderr
    assert not (tmp_path / "out").exists()
    return result.stderr


def test_a_scan_needs_its_design(tmp_path: Path) -> None:
    scan = _points_csv(tmp_path / "scan.ply.csv", np.random.default_rng(0).random((200, 3)))
    err = _refused(tmp_path, str(scan), "--scan")
    assert "scan.ply.csv: a 3-D scan is inspected against its design" in err


@pytest.mark.parametrize("option", [("--centre", "1,2"), ("--kerf", "0.2"), ("--align",),
                                    ("--roller-radius", "5")])
def test_an_outline_s_options_are_refused_with_a_scan(tmp_path: Path, drum_stl: Path,
                                                      option: tuple[str, ...]) -> None:
    err = _refused(tmp_path, str(drum_stl), "--design", str(DRUM), *option)
    assert err.startswith(f"{option[0]}: applies to an outline, not to a 3-D scan"), err


@pytest.mark.parametrize("option,value,words", [("--fit", "30", "--fit: must be from 0.05 to 20"),
                                                ("--gate", "0", "--gate: must be from 0.01 to 20"),
                                                ("--tolerance", "-1", "--tolerance")])
def test_bad_values_are_refused_naming_the_option(tmp_path: Path, drum_stl: Path, option: str,
                                                  value: str, words: str) -> None:
    err = _refused(tmp_path, str(drum_stl), "--design", str(DRUM), option, value)
    assert words in err


def test_a_scan_of_another_part_is_refused(tmp_path: Path) -> None:
    """Points on no flank of the design's part (a block far off): refused, saying so."""
    block = np.random.default_rng(1).random((2000, 3)) * 10.0 + 500.0
    scan = _points_csv(tmp_path / "block.csv", block)
    err = _refused(tmp_path, str(scan), "--design", str(DRUM))
    assert "block.csv: no point of the scan lies on the cam's lower wall or upper wall" in err


def test_a_plate_without_a_thickness_is_refused(tmp_path: Path) -> None:
    """camfab makes no part of a plate without a thickness: there is nothing to hold a scan
    to (the design names the cause)."""
    text = (DESIGNS / "demo-linear-roller.yaml").read_text().replace("  thickness: 8\n", "")
    design = tmp_path / "thin.yaml"
    design.write_text(text)
    scan = _points_csv(tmp_path / "scan.csv", np.random.default_rng(2).random((200, 3)))
    err = _refused(tmp_path, str(scan), "--design", str(design))
    assert "cam.thickness is not given" in err


def test_the_drum_s_own_stl_gives_its_design_s_motion(tmp_path: Path, drum_stl: Path) -> None:
    """The STL is the exact groove to the build's tolerance: the motion through it departs
    from the design's by a fraction of the tolerance on both walls, all round; the play is the
    design's clearance; the placement needs no turn and leaves micrometres."""
    result = run_cli("inspect", str(drum_stl), "--design", str(DRUM), "-o", str(tmp_path / "o"))
    assert result.exit_code == 0, result.stdout + result.stderr
    report = json.loads((tmp_path / "o" / f"{DRUM.stem}-inspection.json").read_text())
    motion = report["motion"]
    assert motion["max_error_mm"] < 0.005
    assert [f["measured_share"] for f in motion["flanks"]] == [1.0, 1.0]
    assert motion["backlash"]["min_mm"] == pytest.approx(0.1, abs=0.005)
    assert motion["backlash"]["max_mm"] == pytest.approx(0.1, abs=0.005)
    assert report["alignment"]["residual_rms_mm"] < 0.005
    assert report["status"]["exit_code"] == 0
    table = (tmp_path / "o" / f"{DRUM.stem}-lift.csv").read_text().splitlines()
    assert table[0] == ("cam_angle_deg,design_lift_mm,lift_mm,lift_error_mm,lower_wall_error_mm,"
                        "upper_wall_error_mm,backlash_mm,pressure_angle_deg")
    assert len(table) == 361
    page = (tmp_path / "o" / f"{DRUM.stem}-inspection.html").read_text()
    for section in ('id="findings"', 'id="maps"', 'id="surface"', 'id="diagrams"',
                    'id="alignment"'):
        assert section in page
    assert page.count('href="data:image/png;base64,') == 3  # two walls and the colour scale


def test_a_disc_cam_s_csv_is_an_outline_unless_scan_is_given(tmp_path: Path) -> None:
    """Without --scan a disc cam's CSV is read as an outline of x, y points (today's
    inspection), so three columns are refused as the outline's; with it, as a scan."""
    points = np.random.default_rng(3).random((300, 3))
    scan = _points_csv(tmp_path / "pts.csv", points)
    result = run_cli("inspect", str(scan), "--design", str(DISC), "-o", str(tmp_path / "a"))
    assert "no point of the scan" not in result.stderr
    err = _refused(tmp_path, str(scan), "--design", str(DISC), "--scan")
    assert "no point of the scan lies on the cam's profile" in err


def test_a_pair_s_two_drawings_are_judged_together(tmp_path: Path) -> None:
    """camfab's two drawings of a conjugate pair, plate a's with --plate-b plate b's: both
    plates' outlines run together give the design's motion, the pair's play nil within the
    drawings' tolerance; plate a's alone stays an outline inspected against cam a."""
    design = DESIGNS / "demo-conjugate.yaml"
    out = tmp_path / "built"
    assert run_cli("build", str(design), "-o", str(out)).exit_code == 0
    a, b = out / "demo-conjugate-a.dxf", out / "demo-conjugate-b.dxf"
    result = run_cli("inspect", str(a), "--plate-b", str(b), "--design", str(design), "-o",
                     str(tmp_path / "o"))
    assert result.exit_code == 0, result.stdout + result.stderr
    report = json.loads((tmp_path / "o" / "demo-conjugate-a-inspection.json").read_text())
    assert [f["flank"] for f in report["motion"]["flanks"]] == ["plate a", "plate b"]
    assert all(f["measured_share"] == 1.0 for f in report["motion"]["flanks"])
    assert abs(report["motion"]["max_error_mm"]) < 0.005
    assert abs(report["motion"]["backlash"]["min_mm"]) < 0.005
    assert abs(report["motion"]["backlash"]["max_mm"]) < 0.005
    alone = run_cli("inspect", str(a), "--design", str(design), "-o", str(tmp_path / "a"))
    assert alone.exit_code == 0 and "deviation from demo-conjugate" in alone.stdout
    err = _refused(tmp_path, str(b), "--plate-b", str(a), "--design", str(DRUM))
    assert err.startswith("--plate-b: applies to a conjugate pair's drawings")
