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


def _stopped_in_its_task(item: int) -> int:
    from camfab.workers import WorkerStopped

    raise WorkerStopped(signal.SIGTERM)


def test_a_worker_stopped_in_its_task_ends_there() -> None:
    """Two stops that come together are one to Python: a worker that took the one as its task's
    end and went back for work would wait on the pool's queue for ever, and the batch with it."""
    from concurrent.futures.process import BrokenProcessPool

    from camfab.workers import _stoppable, worker_pool

    pool = worker_pool(1, None)
    try:
        future = pool.submit(_stoppable, _stopped_in_its_task, 0)
        assert isinstance(future.exception(timeout=120), BrokenProcessPool)
        processes = list(pool._processes.values())
    finally:
        pool.shutdown(wait=True)
    assert [p.exitcode for p in processes] == [128 + signal.SIGTERM]


def test_a_stop_sent_back_from_a_worker_keeps_its_signal() -> None:
    import pickle

    from camfab.workers import WorkerStopped

    stopped = pickle.loads(pickle.dumps(WorkerStopped(signal.SIGTERM)))
    assert (stopped.signum, stopped.code) == (signal.SIGTERM, 128 + signal.SIGTERM)


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


def test_a_stop_passed_to_another_thread_still_waits_for_the_last_rename(tmp_path: Path,
                                                                          monkeypatch) -> None:
    """The renames' thread blocks the stops; the kernel then gives one to another thread of the
    process (numpy's BLAS, manifold3d's workers have theirs), whose handler has the main thread
    run Python's all the same: it too waits for the last rename."""
    import threading

    writing.write_files(tmp_path, {"a.dxf": b"old", "b.svg": b"old", "c.stl": b"old"})
    other = threading.Thread(target=time.sleep, args=(5,), daemon=True)  # stops not blocked
    other.start()
    real = os.replace
    done = []

    def replace(source, target):  # type: ignore[no-untyped-def]
        real(source, target)
        done.append(target)
        if len(done) == 1:
            signal.pthread_kill(other.ident, signal.SIGTERM)
            time.sleep(0.05)  # (a wait with its checks for signals, as any code has)

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


def test_a_stop_as_a_temporary_file_is_made_leaves_none(tmp_path: Path, monkeypatch) -> None:
    """A stop between the making of a temporary file and the noting of it: the earlier set
    stays, and no temporary file."""
    writing.write_files(tmp_path, {"a.dxf": b"old", "b.svg": b"old"})
    real = os.fdopen

    def fdopen(*args, **kwargs):  # type: ignore[no-untyped-def]
        signal.raise_signal(signal.SIGINT)  # the file is made: its stream is not yet
        return real(*args, **kwargs)

    old = signal.signal(signal.SIGINT, stopping.raise_interrupted)
    monkeypatch.setattr(writing.os, "fdopen", fdopen)
    try:
        with pytest.raises(KeyboardInterrupt):
            writing.write_files(tmp_path, {"a.dxf": b"new", "b.svg": b"new"})
    finally:
        signal.signal(signal.SIGINT, old)
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == {"a.dxf": b"old",
                                                                     "b.svg": b"old"}


def test_a_stop_after_the_last_word_does_not_kill_camfab_silently(tmp_path: Path) -> None:
    """Once the program holds its stops for its exit, a stop the kernel gives another thread
    (one of a native library's, which blocks nothing) neither raises nor kills the process as
    the interpreter shuts down and gives up Python's handlers."""
    script = ("import os, signal, sys, threading, time\n"
              "from camfab.stopping import catch, hold_to_the_end\n"
              "catch()\n"
              "threading.Thread(target=time.sleep, args=(30,), daemon=True).start()\n"
              "print(hold_to_the_end(), flush=True)\n"
              "for _ in range(3):\n"
              "    os.kill(os.getpid(), signal.SIGINT)\n"
              "    time.sleep(0.05)\n"
              "sys.exit(5)\n")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          env=child_env(), timeout=120)
    assert (done.returncode, done.stdout, done.stderr) == (5, "None\n", "")


def _forked_build(design: Path, out: Path, err: Path) -> int:
    """``camfab build DESIGN -o OUT`` as the program (:func:`camfab.start.main`) in a child
    forked from this process, its stderr into *err*, with a thread that does not block the
    stopping signals (as a native library's): the child's pid."""
    pid = os.fork()
    if pid:
        return pid
    code = 70
    try:
        import threading

        os.dup2(os.open(os.devnull, os.O_WRONLY), 1)
        os.dup2(os.open(err, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600), 2)
        sys.stdout = open(1, "w", closefd=False)
        sys.stderr = open(2, "w", closefd=False)
        signal.signal(signal.SIGINT, signal.default_int_handler)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        stopping.RECEIVED.clear()
        threading.Thread(target=time.sleep, args=(60,), daemon=True).start()
        sys.argv = ["camfab", "build", str(design), "-o", str(out)]
        from camfab.start import main

        main()
    except SystemExit as exc:
        code = exc.code if isinstance(exc.code, int) else 1
    except BaseException:
        import traceback

        traceback.print_exc()
    finally:
        os._exit(code)


def test_builds_stopped_while_they_write_leave_a_whole_set(tmp_path: Path) -> None:
    """Builds stopped at random moments while they write their files (from the first temporary
    file on): the folder holds the whole earlier set or the whole new one, no temporary file,
    and camfab ends with the build's own status or with its one line and 128 + the signal."""
    import random

    from camfab.pipeline import build

    from .limited_child import _wait, _warm

    _warm()
    earlier = tmp_path / "earlier.yaml"
    earlier.write_text(DESIGN.read_text().replace("base_radius: 20", "base_radius: 21", 1))
    sets = {}
    for name, design in (("old", earlier), ("new", DESIGN)):
        build(design, tmp_path / name)
        sets[name] = {p.name: p.read_bytes() for p in (tmp_path / name).iterdir()}
    assert all(sets["old"][k] != sets["new"][k] for k in sets["new"])
    rng = random.Random(45)
    seen = set()
    for trial in range(6):
        signum = (signal.SIGINT, signal.SIGTERM)[trial % 2]
        out, err = tmp_path / f"out-{trial}", tmp_path / f"err-{trial}"
        out.mkdir()
        for name, data in sets["old"].items():
            (out / name).write_bytes(data)
        pid = _forked_build(DESIGN, out, err)
        started = time.monotonic()
        while not any(p.suffix == ".tmp" for p in out.iterdir()):
            if os.waitid(os.P_PID, pid, os.WEXITED | os.WNOHANG | os.WNOWAIT) is not None \
                    or time.monotonic() - started > 120:  # (ended, not reaped)
                break
            time.sleep(0.0005)  # (the child's core is not taken by the wait)
        time.sleep(rng.uniform(0.0, 0.004))
        os.kill(pid, signum)  # (a child that ended is a zombie until it is waited for)
        status, _ = _wait(pid, time.monotonic() + 300)
        code = -os.WTERMSIG(status) if os.WIFSIGNALED(status) else os.WEXITSTATUS(status)
        files = {p.name: p.read_bytes() for p in out.iterdir()}
        lines = err.read_text().splitlines()
        assert files in (sets["old"], sets["new"]), (trial, sorted(files))
        if code in (0, 1):
            assert (files, lines) == (sets["new"], []), (trial, lines)
            seen.add("done")
        else:
            assert (code, lines) == (128 + signum, [LINES[signum]]), (trial, lines)
            seen.add("old" if files == sets["old"] else "new")
    assert "old" in seen


def test_the_handler_imports_nothing_inside_the_import_systems_lock() -> None:
    """A stop can come while the import system waits for a module's lock; the handler then
    delivers it again a moment later. An import of its own there (a module not yet loaded)
    would take and drop the lock's note of the waiting thread first, and the lock's cleanup
    would fail with a KeyError traceback instead of camfab's one line."""
    script = ("import builtins, signal, sys, time, types\n"
              "from camfab import stopping\n"
              "signal.signal(signal.SIGTERM, lambda *_: print('again', flush=True))\n"
              "code = types.SimpleNamespace(co_filename='<frozen importlib._bootstrap>',\n"
              "                             co_name='acquire')\n"
              "imported = []\n"
              "real = builtins.__import__\n"
              "def spy(name, *args, **kwargs):\n"
              "    imported.append(name)\n"
              "    return real(name, *args, **kwargs)\n"
              "builtins.__import__ = spy\n"
              "stopping.raise_interrupted(signal.SIGTERM, types.SimpleNamespace(f_code=code))\n"
              "builtins.__import__ = real\n"
              "time.sleep(0.5)\n"
              "print(imported, flush=True)\n")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          env=child_env(), timeout=120)
    assert (done.returncode, done.stdout, done.stderr) == (0, "again\n[]\n", "")
