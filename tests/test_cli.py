"""The command line as a user runs it: build, check, laws, new, --version, exit statuses."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from camfab.cli import STARTER_KINDS

from .conftest import DESIGN_FILES, DESIGNS, ROOT, run_cli

#: Example designs that build but fail a check on purpose (the seeds' worked examples were set
#: for their kinematics, not their pressure angle; demo-undercut shows an undercut report).
FAILING_DESIGNS = {
    "seed-10-4": {"pressure_angle"},
    "seed-c11-shm-ua": {"pressure_angle"},
    "demo-undercut": {"pressure_angle", "undercut"},
    "demo-drum-steep": {"pressure_angle", "groove"},
}


@pytest.mark.parametrize("path", DESIGN_FILES, ids=[p.stem for p in DESIGN_FILES])
def test_every_example_design_builds(tmp_path: Path, path: Path) -> None:
    result = run_cli("build", str(path), cwd=tmp_path)
    failing = FAILING_DESIGNS.get(path.stem, set())
    assert result.exit_code == (1 if failing else 0), result.output + result.stderr
    name = path.stem
    folder = tmp_path / "exports" / name
    assert (folder / f"{name}-report.json").is_file()
    assert (folder / f"{name}-motion.csv").is_file()
    report = json.loads((folder / f"{name}-report.json").read_text())
    assert report["name"] == name and report["status"]["exit_code"] == result.exit_code
    failed = {c["id"] for c in report["checks"] if c["ok"] is False and c["severity"] == "error"}
    assert failed == failing


def test_build_output_folder_option_and_summary(tmp_path: Path) -> None:
    result = run_cli("build", str(DESIGNS / "seed-10-4.yaml"), "-o", "out", cwd=tmp_path)
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == [
        "seed-10-4-motion.csv", "seed-10-4-report.html", "seed-10-4-report.json",
        "seed-10-4.dxf", "seed-10-4.stl",
        "seed-10-4.svg"]
    assert "seed-10-4: FAIL" in result.stdout and result.exit_code == 1
    assert "pressure angle reaches 56.2° at 221.7°" in result.stdout
    assert "acceleration steps at 0°, 120°, 180°, 260°" in result.stdout
    assert not (tmp_path / "exports").exists()


def test_velocity_step_fails_the_build_with_exit_1(tmp_path: Path) -> None:
    text = (DESIGNS / "seed-10-4.yaml").read_text().replace("law: harmonic", "law: linear")
    (tmp_path / "uv.yaml").write_text(text)
    result = run_cli("build", "uv.yaml", cwd=tmp_path)
    assert result.exit_code == 1
    assert "FAIL" in result.stdout and "velocity steps at 0°, 120°" in result.stdout
    report = json.loads((tmp_path / "exports/seed-10-4/seed-10-4-report.json").read_text())
    velocity = next(c for c in report["checks"] if c.get("quantity") == "velocity")
    assert velocity["ok"] is False and velocity["severity"] == "error"
    assert velocity["ranges_deg"] == [[0.0, 0.0], [120.0, 120.0]]
    assert report["segments"][0]["max_acceleration_m_s2"] is None  # infinite at the ends


def test_batch_build_in_parallel_reports_the_worst_status(tmp_path: Path) -> None:
    (tmp_path / "bad.yaml").write_text("name: x\n")
    args = ["build", "-j", "2", str(DESIGNS / "seed-10-4.yaml"), str(DESIGNS / "seed-poly-23.yaml"),
            "bad.yaml"]
    result = run_cli(*args, cwd=tmp_path)
    assert result.exit_code == 2
    assert (tmp_path / "exports/seed-10-4/seed-10-4-report.json").is_file()
    assert (tmp_path / "exports/seed-poly-23/seed-poly-23-report.json").is_file()
    assert result.stderr.startswith("bad.yaml:")


def test_check_prints_a_summary_and_writes_nothing(tmp_path: Path) -> None:
    result = run_cli("check", str(DESIGNS / "seed-10-4.yaml"), cwd=tmp_path)
    assert result.exit_code == 1  # the return's pressure angle is over the limit
    out = result.stdout
    for words in ("seed-10-4", "harmonic", "uniform-acceleration", "3.142", "493.5", "900",
                  "continuity", "pressure_angle", "FAIL"):
        assert words in out
    assert list(tmp_path.iterdir()) == []


def test_laws_lists_every_law_with_coefficients() -> None:
    from camfab.motion.laws import LAW_NAMES

    out = run_cli("laws").stdout
    for name in LAW_NAMES:
        assert name in out
    for value in ("1.571", "4.935", "6.283", "39.48", "5.774", "7.513", "4.888", "61.43",
                  "5.528", "69.47", "42.41"):
        assert value in out


@pytest.mark.parametrize("kind", STARTER_KINDS)
def test_new_prints_a_commented_starter_that_builds(tmp_path: Path, kind: str) -> None:
    result = run_cli("new", kind)
    assert result.exit_code == 0
    assert result.stdout.startswith("# camfab starter")
    (tmp_path / "design.yaml").write_text(result.stdout)
    built = run_cli("build", "design.yaml", cwd=tmp_path)
    assert built.exit_code == 0, built.stdout + built.stderr


def test_new_unknown_kind() -> None:
    result = run_cli("new", "disc-rollr")
    assert result.exit_code == 2
    assert "did you mean 'disc-roller'" in result.stderr


def test_bad_command_line_exits_2(tmp_path: Path) -> None:
    assert run_cli("build", cwd=tmp_path).exit_code == 2
    assert run_cli("build", "-j", "0", "x.yaml", cwd=tmp_path).exit_code == 2
    assert run_cli("frobnicate", cwd=tmp_path).exit_code == 2


@pytest.mark.parametrize(("args", "words"), [
    (("build",), "camfab build: Missing argument 'DESIGNS...'"),
    (("build", "d.yaml", "-o", "a-file"), "Directory 'a-file' is a file"),
    (("build", "d.yaml", "--frobnicate"), "No such option '--frobnicate'"),
    (("build", "d.yaml", "-j", "0"), "0 is not in the range 1<=x<=256"),
    (("frobnicate",), "camfab: No such command 'frobnicate'"),
    (("inspect", "x.dxf", "--type", "wheel"), "'wheel' is not one of"),
])
def test_a_bad_command_line_is_one_line(tmp_path: Path, args: tuple[str, ...],
                                        words: str) -> None:
    (tmp_path / "a-file").write_text("not a folder")
    run = subprocess.run([sys.executable, "-m", "camfab", *args], cwd=tmp_path,
                         capture_output=True, text=True, check=False)
    assert run.returncode == 2
    assert run.stdout == "" and run.stderr.count("\n") == 1, run.stderr
    assert words in run.stderr and "--help" in run.stderr, run.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a-file"]


@pytest.mark.parametrize("description", ["[/bold] x", "[link=http://example.com]y[/link]",
                                         "[red]not red[/red] :smile:"])
def test_check_prints_a_description_as_written(tmp_path: Path, description: str) -> None:
    text = (DESIGNS / "seed-poly-345.yaml").read_text()
    (tmp_path / "d.yaml").write_text(text + f"description: {json.dumps(description)}\n"
                                     if "description:" not in text else
                                     "\n".join(f"description: {json.dumps(description)}"
                                               if line.startswith("description:") else line
                                               for line in text.splitlines()) + "\n")
    result = run_cli("check", "d.yaml", cwd=tmp_path)
    assert result.exit_code == 0, result.output
    assert description in result.stdout.splitlines()
    assert "internal error" not in result.output


def test_version_does_not_import_numpy() -> None:
    code = (
        "import sys\n"
        "from camfab.cli import main\n"
        "try:\n    main(['--version'])\n"
        "except SystemExit:\n    pass\n"
        "print('numpy' in sys.modules, 'pydantic' in sys.modules)\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                            cwd=ROOT, check=True)
    lines = result.stdout.strip().splitlines()
    assert lines[0].startswith("camfab, version ")
    assert lines[-1] == "False False"


def test_module_entry_point_runs() -> None:
    result = subprocess.run([sys.executable, "-m", "camfab", "check",
                             str(DESIGNS / "seed-poly-23.yaml")],
                            capture_output=True, text=True, cwd=ROOT)
    assert result.returncode == 0, result.stderr
    assert "polynomial-23" in result.stdout


def test_numpy_warnings_stay_off_the_terminal() -> None:
    """An overflow deep in a computation on extreme values is numpy's RuntimeWarning on stderr
    unless camfab keeps it there: the user sees the one line of the outcome only. (In a process
    of its own: pytest would catch the warnings itself.)"""
    script = (
        "import numpy as np\n"
        "from camfab.batch import Outcome\n"
        "from camfab.cli import _guarded\n"
        "def work():\n"
        "    with np.errstate(all='warn'):\n"
        "        np.float64(1e308) * np.float64(10.0)\n"
        "        np.log(np.zeros(1))\n"
        "    return Outcome(0)\n"
        "assert _guarded('d.yaml', work).code == 0\n"
        "print('done')\n")
    env = {k: v for k, v in os.environ.items() if k != "CAMFAB_DEBUG"}
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         check=False, env=env)
    assert run.returncode == 0 and run.stdout == "done\n"
    assert run.stderr == "", run.stderr
