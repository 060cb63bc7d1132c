"""A stop at any moment from camfab's first instruction is one line and 128 + the signal; a
batch's worker stopped with its process group says nothing of its own; a worker that dies
costs its one design; a set of files is renamed into place whole or not at all."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from camfab import stopping, writing
from camfab.batch import Outcome, run_all

from .conftest import DESIGNS
from .limited_child import child_env

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"),
                                reason="signals and forks as Linux has them")

DESIGN = DESIGNS / "seed-10-4.yaml"
#: A child that installs camfab's handlers first, says so, then runs the ``camfab`` program
#: (:mod:`camfab.start`) on its arguments: a stop from the word "ready" on is camfab's to handle.
BOOT = ("import sys\nfrom camfab.stopping import catch\ncatch()\nprint('ready', flush=True)\n"
        "sys.argv = ['camfab', *sys.argv[1:]]\nfrom camfab.start import main\nmain()\n")
LINES = {signal.SIGINT: "camfab: interrupted", signal.SIGTERM: "camfab: stopped by signal 15"}


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_a_stop_at_any_moment_is_one_line(tmp_path: Path, signum: int) -> None:
    """While the command line's modules import, while the design loads and builds, while the
    files are renamed and while the process exits: one line and 130 or 143, or (the stop after
    the exit) the build's own status with every file whole."""
    seen = set()
    for delay in (0.0, 0.003, 0.01, 0.03, 0.06, 0.12, 0.25, 0.5, 1.0, 2.0):
        out = tmp_path / f"out-{delay}"
        child = subprocess.Popen([sys.executable, "-c", BOOT, "build", str(DESIGN), "-o",
                                  str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                 text=True, env=child_env())
        assert child.stdout is not None
        assert child.stdout.readline() == "ready\n"
        time.sleep(delay)
        child.send_signal(signum)
        _, err = child.communicate(timeout=300)
        lines = err.strip().splitlines()
        if child.returncode in (0, 1):  # done before the stop: the build's status (1: FAIL)
            assert lines == [], err
            seen.add("done")
        else:
            assert (child.returncode, lines) == (128 + signum, [LINES[signum]]), err
            seen.add("stopped")
        assert not list(out.glob(".*.tmp")) if out.exists() else True
    assert "stopped" in seen


def test_a_stop_of_a_batchs_process_group_is_one_line(tmp_path: Path) -> None:
    """SIGTERM to the whole group (the shell's way, or a service manager's) reaches the workers
    too: they end without a word of their own, and the batch says its one line."""
    designs = []
    for i in range(4):
        design = tmp_path / f"d{i}.yaml"
        design.write_text(DESIGN.read_text().replace("name: seed-10-4", f"name: d{i}", 1))
        designs.append(str(design))
    child = subprocess.Popen([sys.executable, "-m", "camfab", "build", *designs, "-j", "2",
                              "-o", str(tmp_path / "out")], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, env=child_env(),
                             start_new_session=True)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and len(_children(child.pid)) < 2:
        time.sleep(0.02)
    assert len(_children(child.pid)) == 2, "the batch started no workers"
    os.killpg(child.pid, signal.SIGTERM)
    _, err = child.communicate(timeout=300)
    assert (child.returncode, err) == (143, "camfab: stopped by signal 15\n")
    assert not list((tmp_path / "out").rglob(".*.tmp"))


def _children(pid: int) -> list[str]:
    try:
        return Path(f"/proc/{pid}/task/{pid}/children").read_text().split()
    except OSError:
        return []


def _crashes_on_b(path: str, out_dir: Path | None) -> Outcome:
    if Path(path).stem == "b":
        import faulthandler

        faulthandler.disable()  # (pytest's, inherited: no stack dump)
        os.kill(os.getpid(), signal.SIGSEGV)
    return Outcome(0, out=[f"{path}: OK"])


def test_a_design_whose_worker_dies_fails_and_the_batch_goes_on() -> None:
    outcomes = run_all(["a.yaml", "b.yaml", "c.yaml", "d.yaml"], None, 2, _crashes_on_b)
    assert [o.code for o in outcomes] == [0, 1, 0, 0]
    assert outcomes[1].out == ["b.yaml: FAIL — its worker died: signal 11 (SIGSEGV)"]
    assert [o.name for o in outcomes] == ["a.yaml", "b.yaml", "c.yaml", "d.yaml"]


def test_a_set_of_files_is_renamed_whole_when_a_stop_comes_between(tmp_path: Path,
                                                                    monkeypatch) -> None:
    """A SIGTERM between two renames waits for the last: the new set is whole, then camfab
    stops."""
    writing.write_files(tmp_path, {"a.dxf": b"old", "b.svg": b"old", "c.stl": b"old"})
    real = os.replace
    done = []

    def replace(source, target):  # type: ignore[no-untyped-def]
        real(source, target)
        done.append(target)
        if len(done) == 1:
            signal.raise_signal(signal.SIGTERM)

    old = signal.signal(signal.SIGTERM, stopping.raise_interrupted)
    monkeypatch.setattr(writing.os, "replace", replace)
    try:
        with pytest.raises(stopping.Interrupted):
            writing.write_files(tmp_path, {"a.dxf": b"new", "b.svg": b"new", "c.stl": b"new"})
    finally:
        signal.signal(signal.SIGTERM, old)
    assert len(done) == 3
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == {
        "a.dxf": b"new", "b.svg": b"new", "c.stl": b"new"}
