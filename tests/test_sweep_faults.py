"""``camfab sweep`` on bad input and faults: a design's name that would place the table outside
its folder, writes that fail (a folder it may not write, a full disk, a folder where the table
goes), ranges that overflow, variants files over their limits, an objective that is no number
of the design, and a worker process that dies under a variant. Each ends in one line and exit
2 (or, for a dead worker, a FAIL row), with nothing written outside the output folder and no
temporary file left."""

from __future__ import annotations

import errno
import os
import signal
import time
from pathlib import Path

import pytest

from camfab.sweep.vary import MAX_FILE_VARIANTS, MAX_KEYS, MAX_VALUES, SweepError, parse_spec

from .conftest import DESIGNS, run_cli

SEED = DESIGNS / "seed-10-4.yaml"


def files_under(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


def refused(tmp_path: Path, *args: str) -> str:
    """The one stderr line of a sweep that must be refused (exit 2) and write nothing."""
    before = files_under(tmp_path)
    result = run_cli("sweep", *args, cwd=tmp_path)
    assert result.exit_code == 2, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    assert files_under(tmp_path) == before
    return lines[0]


def seed_named(tmp_path: Path, name: str) -> Path:
    text = SEED.read_text().replace("name: seed-10-4", f"name: {name}", 1)
    assert f"name: {name}" in text
    design = tmp_path / "design.yaml"
    design.write_text(text)
    return design


# ---- the design's name --------------------------------------------------------------------------

@pytest.mark.parametrize("name", ['"../../ESCAPED"', '"/tmp/ESCAPED-camfab"', '".hidden"',
                                  '"a/b"', "x" * 101])
def test_a_name_that_would_leave_the_folder_is_refused_on_its_line(tmp_path: Path,
                                                                    name: str) -> None:
    design = seed_named(tmp_path, name)
    line = refused(tmp_path, str(design), "--vary", "cam.base_radius=20,30", "-o", "out/a")
    assert line.startswith(f"{design}:") and ": name: " in line
    assert not Path("/tmp/ESCAPED-camfab-sweep.parquet").exists()


# ---- writes that fail ---------------------------------------------------------------------------

def test_a_folder_that_cannot_hold_files_is_one_line(tmp_path: Path) -> None:
    line = refused(tmp_path, str(SEED), "--vary", "cam.base_radius=20,30", "-o", "/proc/self",
                   "-j", "1")
    assert line.startswith("/proc/self: cannot write the outputs (")


@pytest.mark.parametrize("table_format", ["csv", "parquet"])
def test_a_folder_where_the_table_goes_is_one_line_and_nothing_is_written(
        tmp_path: Path, table_format: str) -> None:
    from camfab.sweep.table import parquet_available

    if table_format == "parquet" and not parquet_available():
        pytest.skip("pyarrow (camfab[sweep]) is not installed")
    (tmp_path / "out" / f"seed-10-4-sweep.{table_format}").mkdir(parents=True)
    line = refused(tmp_path, str(SEED), "--vary", "cam.base_radius=20,30", "-o", "out",
                   "-j", "1", "--format", table_format)
    assert line.startswith("out: cannot write the outputs (")


@pytest.mark.parametrize("table_format", ["csv", "parquet"])
def test_a_full_disk_is_one_line_and_leaves_no_file(tmp_path: Path, monkeypatch,
                                                      table_format: str) -> None:
    """A disk that fills after some kilobytes (every temporary file the sweep opens is on it):
    the table's and the page's temporary files removed, the folder the sweep made removed."""
    from camfab import writing
    from camfab.sweep.table import parquet_available

    if table_format == "parquet" and not parquet_available():
        pytest.skip("pyarrow (camfab[sweep]) is not installed")
    real = writing.open_temp

    class Full:
        def __init__(self, stream) -> None:  # type: ignore[no-untyped-def]
            self.stream, self.size = stream, 0

        def write(self, data: bytes) -> int:
            self.size += len(data)
            if self.size > 2000:
                raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
            return self.stream.write(data)

        def __getattr__(self, name: str):  # type: ignore[no-untyped-def]
            return getattr(self.stream, name)

        def __enter__(self):  # type: ignore[no-untyped-def]
            return self

        def __exit__(self, *exc: object) -> None:
            self.stream.close()

    monkeypatch.setattr(writing, "open_temp", lambda folder, name: (
        lambda made: (made[0], Full(made[1])))(real(folder, name)))
    line = refused(tmp_path, str(SEED), "--vary", "cam.base_radius=10:100:0.5", "-o", "out/new",
                   "-j", "1", "--format", table_format)
    assert line == f"out/new: cannot write the outputs ({os.strerror(errno.ENOSPC)})"
    assert not (tmp_path / "out").exists()


# ---- ranges, variants files, options ------------------------------------------------------------

@pytest.mark.parametrize(("spec", "problem"), [
    ("0:1:1e-320", f"more than {MAX_VALUES:,} values"),
    ("0:1e308:1e-308", f"more than {MAX_VALUES:,} values"),
])
def test_a_range_too_fine_to_count_is_refused(spec: str, problem: str) -> None:
    with pytest.raises(SweepError, match=problem):
        parse_spec(spec, "--vary cam.base_radius")


@pytest.mark.parametrize(("spec", "values"), [
    ("-1e308:1e308:1e308", (-1e308, 0.0, 1e308)),
    ("1e308:-1e308:-1e308", (1e308, 0.0, -1e308)),
    ("log:1e-320:1e308:2", (1e-320, 1e308)),
])
def test_a_range_at_the_ends_of_the_numbers_gives_its_values(spec: str, values: tuple) -> None:
    assert parse_spec(spec, "--vary cam.base_radius") == values


def test_an_overflowing_range_on_the_command_line_is_one_line(tmp_path: Path) -> None:
    line = refused(tmp_path, str(SEED), "--vary", "cam.base_radius=0:1:1e-320", "-o", "out")
    assert line.startswith("camfab sweep: --vary cam.base_radius=0:1:1e-320: more than")


def _cpu_refused(tmp_path: Path, text: str, problem: str) -> None:
    file = tmp_path / "variants.csv"
    file.write_text(text)
    start = time.process_time()
    line = refused(tmp_path, str(SEED), "--variants", str(file), "-o", "out")
    assert time.process_time() - start < 10.0  # linear work: seconds at most
    assert line.startswith(f"camfab sweep: --variants {file}: ") and problem in line, line


def test_a_variants_file_of_too_many_rows_is_refused_as_they_pass_the_limit(
        tmp_path: Path) -> None:
    _cpu_refused(tmp_path, "cam.base_radius\n" + "30\n" * (MAX_FILE_VARIANTS + 1),
                 f"more than {MAX_FILE_VARIANTS:,} variants")


def test_a_variants_header_of_too_many_keys_is_refused_at_once(tmp_path: Path) -> None:
    _cpu_refused(tmp_path, ",".join(f"k{i}" for i in range(200_000)) + "\n1\n",
                 f"at most {MAX_KEYS}")


def test_a_variants_field_too_long_to_read_is_one_line(tmp_path: Path) -> None:
    _cpu_refused(tmp_path, "cam.base_radius\n" + "9" * 200_000 + "\n", "line 2:")


def test_a_repeated_key_among_many_is_found_in_linear_time(tmp_path: Path) -> None:
    keys = [f"cam.k{i}" for i in range(MAX_KEYS - 1)] + ["cam.k3"]
    _cpu_refused(tmp_path, ",".join(keys) + "\n" + ",".join("1" * len(keys)) + "\n",
                 "the key cam.k3 is given twice")


def test_the_variant_number_is_no_objective(tmp_path: Path) -> None:
    line = refused(tmp_path, str(SEED), "--vary", "cam.base_radius=20,30", "--minimize",
                   "variant", "-o", "out")
    assert line.startswith("camfab sweep: --minimize variant: not a numeric column")


# ---- a worker that dies -------------------------------------------------------------------------

def _dies_at_seven(batch):  # type: ignore[no-untyped-def]
    """A sweep's task whose worker dies (SIGSEGV) under variant 7."""
    if any(index == 7 for index, _ in batch):
        import faulthandler

        faulthandler.disable()  # (pytest's, inherited: no stack dump)
        os.kill(os.getpid(), signal.SIGSEGV)
    return [(index, *values, "OK", "") for index, values in batch]


def test_a_variant_whose_worker_dies_is_a_fail_row_and_the_sweep_goes_on() -> None:
    from camfab.sweep.engines import local_rows
    from camfab.workers import Died

    batches = [[(i, (float(i),)) for i in range(start, start + 4)] for start in range(0, 16, 4)]
    rows = [r for chunk in local_rows(_dies_at_seven, batches, 2, lambda: None,
                                      lambda v, died: (v[0], *v[1], "FAIL", died.words()))
            for r in chunk]
    assert [r[0] for r in rows] == list(range(16))
    assert rows[7][2:] == ("FAIL", Died(-signal.SIGSEGV).words())
    assert "signal 11" in rows[7][3]
    assert all(r[2] == "OK" for r in rows if r[0] != 7)
