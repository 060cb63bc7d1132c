"""Batches and determinism: many designs in one command, and the same bytes on every build.

Two builds of every example design run as separate processes, with different string-hash seeds,
in opposite orders and in parallel (so each worker builds a different sequence of designs), must
write identical files: no timestamps, no set or memory order, no state carried from one design
to the next.
"""

from __future__ import annotations

import filecmp
import multiprocessing
import os
import subprocess
import sys
from pathlib import Path

import pytest

from camfab.batch import Outcome, run_all

from .conftest import DESIGN_FILES, DESIGNS, run_cli


def _build(paths: list[Path], out: Path, seed: str) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONHASHSEED": seed}
    return subprocess.run([sys.executable, "-m", "camfab", "build", *map(str, paths), "-j", "2",
                           "-o", str(out)], capture_output=True, text=True, env=env, check=False)


def test_two_builds_of_every_design_give_identical_bytes(tmp_path: Path) -> None:
    """And a batch writes each design into a folder of its name inside -o DIR, as under
    exports/ (not 200 files flat in DIR)."""
    first = _build(DESIGN_FILES, tmp_path / "first", "1")
    second = _build(DESIGN_FILES[::-1], tmp_path / "second", "2")
    assert first.returncode == second.returncode, first.stderr + second.stderr
    assert "Traceback" not in first.stderr + second.stderr
    folders = sorted(p.name for p in (tmp_path / "first").iterdir())
    assert folders == sorted(p.stem for p in DESIGN_FILES)  # (each example's name is its stem)
    assert folders == sorted(p.name for p in (tmp_path / "second").iterdir())
    for folder in folders:
        names = sorted(p.name for p in (tmp_path / "first" / folder).iterdir())
        # every design wrote its files (a conjugate pair writes NAME-a.dxf and NAME-b.dxf)
        assert names and all(n.startswith(folder) for n in names), folder
        assert names == sorted(p.name for p in (tmp_path / "second" / folder).iterdir())
        _, mismatch, errors = filecmp.cmpfiles(tmp_path / "first" / folder,
                                               tmp_path / "second" / folder, names,
                                               shallow=False)
        assert not mismatch and not errors, mismatch + errors


def test_a_batch_goes_on_past_failures_and_ends_with_a_summary(tmp_path: Path) -> None:
    (tmp_path / "broken.yaml").write_text("name: broken\ncam: {type: disc}\n")
    designs = [str(DESIGNS / "seed-10-4.yaml"), "broken.yaml", str(DESIGNS / "demo-table.yaml")]
    result = run_cli("build", *designs, "-j", "2", "-o", "out", cwd=tmp_path)
    # the worst status: the invalid design's 2; the others were built all the same
    assert result.exit_code == 2
    assert "broken.yaml:1: follower: required" in result.stderr
    out = tmp_path / "out"
    assert (out / "seed-10-4" / "seed-10-4.dxf").exists()
    assert (out / "demo-table" / "demo-table.dxf").exists()
    assert sorted(p.name for p in out.iterdir()) == ["demo-table", "seed-10-4"]
    lines = result.stdout.splitlines()
    table = lines[lines.index(next(line for line in lines if line.startswith("design "))):]
    rows = {line.split()[0]: line.split() for line in table[2:5]}
    # seed 10.4 fails its pressure-angle check (exit 1), demo-table passes
    assert rows["seed-10-4"][1] == "FAIL" and rows["seed-10-4"][4] == "6"
    assert rows["broken.yaml"][1] == "INVALID" and rows["broken.yaml"][4] == "0"
    assert rows["demo-table"][1] == "OK" and rows["demo-table"][2] == "0"
    assert table[-1].startswith("3 design(s): 1 OK, 1 FAIL, 1 INVALID; 12 file(s) in ")
    assert table[-1].endswith("designs/s)")


def test_one_design_prints_no_summary_and_a_long_batch_can_show_progress(tmp_path: Path) -> None:
    single = run_cli("build", str(DESIGNS / "demo-table.yaml"), "-o", "out", cwd=tmp_path)
    assert single.exit_code == 0 and "design(s):" not in single.stdout
    designs = [str(DESIGNS / "demo-table.yaml"), str(DESIGNS / "seed-poly-345.yaml")]
    shown = run_cli("build", *designs, "--progress", "-o", "out", cwd=tmp_path)
    assert shown.exit_code == 0
    assert "building" in shown.stderr
    quiet = run_cli("build", *designs, "--no-progress", "-o", "out", cwd=tmp_path)
    assert "building" not in quiet.stderr


def _named(path: str, out_dir: Path | None) -> Outcome:
    return Outcome(0, out=[f"{path} in process {os.getpid()}"])


def test_only_a_parallel_batch_imports_ahead_for_its_workers() -> None:
    """What the designs need is imported once in the batch's process, before the workers are
    forked from it, and only when workers run: one design, or ``-j 1``, is built as it is."""
    calls: list[int] = []
    serial = run_all(["a", "b"], None, 1, _named, preload=lambda: calls.append(os.getpid()))
    single = run_all(["a"], None, 2, _named, preload=lambda: calls.append(os.getpid()))
    assert calls == []
    assert [o.out for o in serial + single] == [[f"{p} in process {os.getpid()}"]
                                                for p in ("a", "b", "a")]
    parallel = run_all(["a", "b", "c"], None, 2, _named,
                       preload=lambda: calls.append(os.getpid()))
    assert [o.name for o in parallel] == ["a", "b", "c"]
    assert all(o.out[0] != f"{o.name} in process {os.getpid()}" for o in parallel)
    forks = "fork" in multiprocessing.get_all_start_methods() and sys.platform != "darwin"
    assert calls == ([os.getpid()] if forks else [])


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_the_imports_ahead_of_a_batch_start_no_thread() -> None:
    """The workers are forked from the process that imported what a build needs: a thread
    running there then could hold a lock they would inherit taken. numpy's BLAS threads (which
    stop themselves before a fork) are there before; nothing else may start one."""
    code = ("import os, numpy; before = len(os.listdir('/proc/self/task')); "
            "from camfab.pipeline import import_build_modules; import_build_modules(); "
            "print(len(os.listdir('/proc/self/task')) - before)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    assert done.stdout.strip() == "0", done.stderr
