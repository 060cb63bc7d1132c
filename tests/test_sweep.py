"""``camfab sweep``: the --vary specs, one clear line and exit 2 for a bad one, each row against
the variant's design file written out and analysed on its own, the same table bytes from one
process, a local pool and a Dask cluster of separate processes, Ctrl-C keeping the rows done,
the variants of a CSV file, the best variants built, and the summary page."""

from __future__ import annotations

import csv
import io
import json
import math
import re
import signal
import subprocess
import sys
import time
from importlib.util import find_spec
from pathlib import Path

import pytest

from camfab.pipeline import analyse, design_from_text
from camfab.sweep.vary import SweepError, parse_spec, parse_vary, with_values

from .conftest import DESIGNS, REQUIRED, run_cli

SEED = DESIGNS / "seed-10-4.yaml"
#: A small sweep with OK, FAIL and INVALID rows (a base radius of 0 is no design).
VARY = ("--vary", "cam.base_radius=0:100:20", "--vary", "follower.offset=0,10",
        "--vary", "motion[0].law=harmonic,cycloidal")


def table(path: Path) -> list[dict[str, str]]:
    return list(csv.DictReader(io.StringIO(path.read_text(encoding="utf-8"))))


def swept(tmp_path: Path, *args: str, folder: str = "out") -> list[dict[str, str]]:
    """The rows of a sweep of the seed with *args* (in one process, as CSV)."""
    result = run_cli("sweep", str(SEED), *args, "-o", folder, "-j", "1", "--format", "csv",
                     cwd=tmp_path)
    assert result.exit_code == 0, result.output
    return table(tmp_path / folder / "seed-10-4-sweep.csv")


@pytest.mark.parametrize(("spec", "values"), [
    ("20:40:5", (20.0, 25.0, 30.0, 35.0, 40.0)),
    ("0:0.3:0.1", (0.0, 0.1, 0.2, 0.3)),  # the stop reached, as written
    ("40:20:-10", (40.0, 30.0, 20.0)),
    ("20:22:5", (20.0,)),
    ("log:1:100:3", (1.0, 10.0, 100.0)),
    ("harmonic, cycloidal", ("harmonic", "cycloidal")),
    ("20,25.5,1 in", (20, 25.5, "1 in")),
])
def test_specs_give_their_values(spec: str, values: tuple) -> None:
    assert parse_spec(spec, "--vary x") == values


@pytest.mark.parametrize(("spec", "problem"), [
    ("40:20:5", "the range is empty"),
    ("20:40:0", "the step must not be 0"),
    ("20:40", "START:STOP:STEP"),
    ("a:40:5", "the start 'a' is not a number"),
    ("log:0:10:3", "must be > 0"),
    ("log:1:10:2.5", "whole number"),
    ("1,,2", "empty item"),
    ("0:1e9:1e-3", "values; at most"),
])
def test_a_bad_spec_is_one_clear_problem(spec: str, problem: str) -> None:
    with pytest.raises(SweepError, match=problem):
        parse_spec(spec, "--vary x")


def test_a_path_reaches_a_segment_whatever_its_kind() -> None:
    data = {"motion": [{"rise": {"angle": 120, "law": "harmonic"}}, {"dwell": {"angle": 60}}]}
    changed = with_values(data, [parse_vary("motion[0].law=cycloidal").keys], ["cycloidal"])
    assert changed["motion"][0] == {"rise": {"angle": 120, "law": "cycloidal"}}
    assert data["motion"][0]["rise"]["law"] == "harmonic"  # the base untouched
    with pytest.raises(LookupError, match="no \\[5\\]"):
        with_values(data, [parse_vary("motion[5].angle=1").keys], [1])


@pytest.mark.parametrize(("vary", "words"), [
    ("cam.base_radiu=20,30", ("--vary cam.base_radiu", "unknown key", "base_radius")),
    ("cam.base_radius=40:20:5", ("--vary cam.base_radius=40:20:5", "the range is empty")),
    ("cam.base_radius=big,small", ("--vary cam.base_radius", "'big'", "must be a length")),
    ("motion[0].law=cycloidl", ("--vary motion[0].law", "unknown motion law",
                                "did you mean 'cycloidal'")),
    ("motion[7].angle=10,20", ("--vary motion[7].angle", "motion has 4 entries")),
    ("cam..base=1", ("is not a key of the design",)),
    ("cam.base_radius", ("give PATH=SPEC",)),
])
def test_bad_vary_input_is_one_line_and_exit_2_with_nothing_written(
        vary: str, words: tuple[str, ...], tmp_path: Path) -> None:
    start = time.process_time()
    result = run_cli("sweep", str(SEED), "--vary", vary, "-o", "out", "-j", "1", cwd=tmp_path)
    assert time.process_time() - start < 5.0
    assert result.exit_code == 2, result.output
    lines = result.output.strip().splitlines()
    assert len(lines) == 1, lines
    for word in words:
        assert word in lines[0], lines[0]
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("args", [
    (),
    ("--vary", "cam.base_radius=20,30", "--build-best", "2"),
    ("--vary", "cam.base_radius=20,30", "--minimize", "status"),
    ("--vary", "cam.base_radius=20,30", "--vary", "cam.base_radius=40"),
    ("--vary", "cam.base_radius=1:1000:0.01", "--vary", "follower.offset=0:100:0.1"),  # 1e9
])
def test_bad_sweep_options_are_one_line_and_exit_2(args: tuple[str, ...],
                                                   tmp_path: Path) -> None:
    result = run_cli("sweep", str(SEED), *args, "-o", "out", "-j", "1", cwd=tmp_path)
    assert result.exit_code == 2, result.output
    assert len(result.output.strip().splitlines()) == 1, result.output
    assert not (tmp_path / "out").exists()


def test_each_row_is_the_variants_design_analysed_on_its_own(tmp_path: Path) -> None:
    rows = swept(tmp_path, *VARY)
    assert [int(r["variant"]) for r in rows] == list(range(6 * 2 * 2))
    assert {r["status"] for r in rows} == {"OK", "FAIL", "INVALID"}
    text = SEED.read_text()
    for r in rows[::3]:
        # the variant written as a design file by hand, from the seed's text
        radius, offset, law = float(r["cam.base_radius"]), float(r["follower.offset"]), \
            r["motion[0].law"]
        assert f"law: {law}" in text.replace("harmonic", law)
        variant = (text.replace("base_radius: 20 ", f"base_radius: {radius} ")
                   .replace("offset: 10 ", f"offset: {offset} ")
                   .replace("law: harmonic", f"law: {law}"))
        try:
            analysis = analyse(design_from_text(variant, "variant.yaml"), advice=False)
        except Exception as exc:  # an invalid design: the row says so, in the same words
            assert r["status"] == "INVALID"
            assert str(exc).split(": ", 1)[1] in r["message"], (exc, r["message"])
            continue
        failed = {f.id for f in analysis.findings if not f.ok and f.severity == "error"}
        assert r["status"] == ("FAIL" if failed else "OK")
        from camfab.export.report_json import render_report_json

        report = json.loads(render_report_json(analysis))
        geometry = report["geometry"]
        # the report's numbers, to the 12 digits both carry: 20, not 19.999999999999996
        assert float(r["pressure_angle_max_deg"]) == geometry["pressure_angle_max_deg"]
        assert float(r["profile_min_radius_of_curvature_mm"]) == geometry[
            "profile_min_radius_of_curvature_mm"]
        assert (r["undercut"] == "true") == geometry["undercut"]
        peak = max(s["max_velocity_m_s"] for s in report["segments"])
        assert math.isclose(float(r["max_velocity"]), peak, rel_tol=1e-10)


@pytest.mark.parametrize("fmt", ["csv", "parquet"])
def test_one_process_and_a_pool_write_the_same_bytes(fmt: str, tmp_path: Path) -> None:
    if fmt == "parquet" and find_spec("pyarrow") is None:
        if REQUIRED:
            pytest.fail("pyarrow (camfab[sweep]) is not installed")
        pytest.skip("pyarrow (camfab[sweep]) is not installed")
    outputs = []
    for jobs in ("1", "2"):
        result = run_cli("sweep", str(SEED), *VARY, "-o", f"j{jobs}", "-j", jobs,
                         "--format", fmt, cwd=tmp_path)
        assert result.exit_code == 0, result.output
        outputs.append((tmp_path / f"j{jobs}" / f"seed-10-4-sweep.{fmt}").read_bytes())
    assert outputs[0] == outputs[1]
    if fmt == "parquet":
        import pyarrow.parquet as pq

        rows = pq.read_table(io.BytesIO(outputs[0])).to_pylist()
        csv_rows = swept(tmp_path, *VARY, folder="c")
        assert len(rows) == len(csv_rows) == 24
        assert [r["status"] for r in rows] == [r["status"] for r in csv_rows]
        assert rows[5]["pressure_angle_max_deg"] == float(csv_rows[5]["pressure_angle_max_deg"])


def _dask(*args: str, **kwargs) -> subprocess.Popen:  # type: ignore[no-untyped-def]
    return subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_" + args[0],
                             *args[1:]], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            **kwargs)


def test_a_dask_cluster_of_separate_processes_writes_the_local_table(tmp_path: Path) -> None:
    if find_spec("distributed") is None:
        if REQUIRED:
            pytest.fail("dask distributed (camfab[cluster]) is not installed")
        pytest.skip("dask distributed (camfab[cluster]) is not installed")
    file = tmp_path / "scheduler.json"
    scheduler = _dask("scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                      "--scheduler-file", str(file))
    workers = []
    try:
        deadline = time.monotonic() + 60
        while not file.exists() and time.monotonic() < deadline:
            time.sleep(0.2)
        address = json.loads(file.read_text())["address"]
        workers = [_dask("worker", address, "--nthreads", "1", "--no-dashboard",
                         "--name", f"w{i}", cwd=tmp_path) for i in range(2)]
        from distributed import Client

        with Client(address, timeout=30) as client:
            client.wait_for_workers(2, timeout=60)
        local = run_cli("sweep", str(SEED), *VARY, "-o", "local", "-j", "2", "--format", "csv",
                        cwd=tmp_path)
        assert local.exit_code == 0, local.output
        remote = subprocess.run(
            [sys.executable, "-m", "camfab", "sweep", str(SEED), *VARY, "-o", "dask",
             "--scheduler", address, "--format", "csv"], cwd=tmp_path, capture_output=True,
            text=True, timeout=300, check=False)
        assert remote.returncode == 0, remote.stdout + remote.stderr
        name = "seed-10-4-sweep.csv"
        assert (tmp_path / "dask" / name).read_bytes() == (tmp_path / "local" / name).read_bytes()
    finally:
        for process in [*workers, scheduler]:
            process.terminate()
        for process in [*workers, scheduler]:
            try:
                process.wait(timeout=30)
            except subprocess.TimeoutExpired:
                process.kill()


def test_an_unreachable_scheduler_is_one_line(tmp_path: Path) -> None:
    if find_spec("distributed") is None:
        pytest.skip("dask distributed (camfab[cluster]) is not installed")
    result = run_cli("sweep", str(SEED), "--vary", "cam.base_radius=20,30", "--scheduler",
                     "tcp://127.0.0.1:9", "-o", "out", cwd=tmp_path)
    assert result.exit_code == 2, result.output
    assert "cannot reach a Dask scheduler" in result.output
    assert len(result.output.strip().splitlines()) == 1


def test_ctrl_c_keeps_the_rows_done_so_far(tmp_path: Path) -> None:
    process = subprocess.Popen(
        [sys.executable, "-m", "camfab", "sweep", str(SEED), "--vary",
         "cam.base_radius=20:80:0.001", "-o", "out", "-j", "2", "--format", "csv"],
        cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    folder = tmp_path / "out"
    # a backstop against a sweep that makes no progress, not a measure of speed: a loaded
    # machine takes minutes to the first group of rows
    deadline = time.monotonic() + 900
    # rows under way: the table's temporary file holds its first rows (how many, whatever the
    # machine's speed, is counted, not assumed)
    done = 0
    while time.monotonic() < deadline and process.poll() is None:
        temps = list(folder.glob(".seed-10-4-sweep.csv.*.tmp")) if folder.exists() else []
        if temps and temps[0].stat().st_size > 20_000:
            done = temps[0].read_bytes().count(b"\n") - 1  # whole rows, past the header
            break
        time.sleep(0.1)
    assert done > 0, "the sweep wrote no row in fifteen minutes"
    process.send_signal(signal.SIGINT)
    out, err = process.communicate(timeout=120)
    assert process.returncode == 130, out + err
    rows = table(folder / "seed-10-4-sweep.csv")
    assert done <= len(rows) < 60_001  # every row written before the signal is kept
    assert [int(r["variant"]) for r in rows] == list(range(len(rows)))  # whole, in order
    assert "stopped after" in out
    page = (folder / "seed-10-4-sweep.html").read_text()
    assert "Stopped before the end" in page
    assert not list(folder.glob(".*.tmp"))


def test_variants_from_a_csv_file_and_the_best_built(tmp_path: Path) -> None:
    (tmp_path / "v.csv").write_text("cam.base_radius,motion[0].law\n"
                                    "100,harmonic\n45,cycloidal\n120,cycloidal\n10,harmonic\n")
    result = run_cli("sweep", str(SEED), "--variants", "v.csv", "-o", "out", "-j", "1",
                     "--format", "csv", "--build-best", "2", "--minimize", "cam.base_radius",
                     cwd=tmp_path)
    assert result.exit_code in (0, 1), result.output
    rows = table(tmp_path / "out" / "seed-10-4-sweep.csv")
    assert [r["cam.base_radius"] for r in rows] == ["100", "45", "120", "10"]
    ok = sorted((float(r["cam.base_radius"]), int(r["variant"])) for r in rows
                if r["status"] == "OK")
    assert len(ok) >= 2, rows
    for radius, index in ok[:2]:
        folder = tmp_path / "out" / "best" / f"seed-10-4-v{index}"
        assert (folder / f"seed-10-4-v{index}.dxf").is_file(), result.output
        assert f"base_radius: {radius:g}" in (tmp_path / "out" / "best" /
                                               f"seed-10-4-v{index}.yaml").read_text()
        assert f"built out/best/seed-10-4-v{index}/" in result.output
        # written as the studio saves an edit: the design's comments and layout kept
        best = (tmp_path / "out" / "best" / f"seed-10-4-v{index}.yaml").read_text()
        design = SEED.read_text()
        comments = [line for line in design.splitlines() if line.lstrip().startswith("#")]
        assert comments and all(line in best.splitlines() for line in comments)
        assert len(best.splitlines()) == len(design.splitlines()) + 1  # the variant's header
    page = (tmp_path / "out" / "seed-10-4-sweep.html").read_text()
    assert "Best by least cam.base_radius" in page and "<svg" in page


def test_the_page_counts_each_cell_of_the_region_from_the_table(tmp_path: Path) -> None:
    import xml.etree.ElementTree as ET

    rows = swept(tmp_path, *VARY)
    expected: dict[tuple[float, float], list[int]] = {}
    for r in rows:  # the two laws of each (radius, offset) in one cell
        key = (float(r["cam.base_radius"]), float(r["follower.offset"]))
        cell = expected.setdefault(key, [0, 0, 0])
        cell[("OK", "FAIL", "INVALID").index(r["status"])] += 1
    page = (tmp_path / "out" / "seed-10-4-sweep.html").read_text()
    svg = ET.fromstring(re.search(r"<svg.*?</svg>", page, re.S).group(0))  # type: ignore[union-attr]
    found = {}
    for title in svg.iter("{http://www.w3.org/2000/svg}title"):
        m = re.fullmatch(r"cam\.base_radius (\S+), follower\.offset (\S+): (\d+) OK, (\d+) "
                         r"FAIL, (\d+) INVALID(\nfailing: .*)?", title.text or "")
        assert m is not None, title.text
        found[(float(m.group(1)), float(m.group(2)))] = [int(m.group(i)) for i in (3, 4, 5)]
    assert found == expected
    assert "24 variants" in page and "Every variant's row is in" in page


def test_size_gives_the_radius_at_which_the_pressure_angle_reaches_its_limit(
        tmp_path: Path) -> None:
    rows = swept(tmp_path, "--vary", "follower.offset=0,10", "--size")
    text = SEED.read_text()
    for r in rows:
        least = float(r["least_size_mm"])
        variant = (text.replace("base_radius: 20 ", f"base_radius: {least!r} ")
                   .replace("offset: 10 ", f"offset: {r['follower.offset']} "))
        analysis = analyse(design_from_text(variant, "variant.yaml"), advice=False)
        pressure = next(f for f in analysis.findings if f.id == "pressure_angle")
        assert pressure.value == pytest.approx(30.0, abs=1e-3)  # the seed's limit, reached
    assert float(rows[1]["least_size_mm"]) == pytest.approx(90.0761, abs=1e-4)  # camfab size


def test_a_drums_row_holds_its_worst_pressure_angle_and_its_groove(tmp_path: Path) -> None:
    result = run_cli("sweep", str(DESIGNS / "demo-cylindrical.yaml"), "--vary",
                     "cam.radius=20,60", "-o", "out", "-j", "1", "--format", "csv",
                     cwd=tmp_path)
    assert result.exit_code == 0, result.output
    rows = table(tmp_path / "out" / "demo-cylindrical-sweep.csv")
    text = (DESIGNS / "demo-cylindrical.yaml").read_text()
    from camfab.export.report_json import render_report_json

    for r in rows:
        variant = re.sub(r"(?m)^(\s*radius:)\s*[^#\n]*", rf"\g<1> {r['cam.radius']} ", text,
                         count=1)
        analysis = analyse(design_from_text(variant, "variant.yaml"), advice=False)
        geometry = json.loads(render_report_json(analysis))["geometry"]
        assert math.isclose(float(r["pressure_angle_max_deg"]),
                            geometry["root_pressure_angle_max_deg"], rel_tol=1e-10)
        assert float(r["pressure_angle_max_at_deg"]) == geometry["root_pressure_angle_max_at_deg"]
        assert math.isclose(float(r["profile_min_radius_of_curvature_mm"]),
                            geometry["developed_min_radius_of_curvature_mm"], rel_tol=1e-10)
        groove = next(f for f in analysis.findings if f.id == "groove")
        assert (r["undercut"] == "true") == (not groove.ok)
    assert rows[0]["status"] == "FAIL" and rows[1]["status"] == "OK"
