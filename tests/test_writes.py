"""How a build puts its files on disk and how it stops: files readable as the umask allows,
no temporary file left on any way out (an error, Ctrl-C, SIGTERM, a SIGKILL followed by the next
build), exit status 130 on Ctrl-C and 143 on SIGTERM, and designs of one batch that would write
the same files refused."""

from __future__ import annotations

import os
import signal
import stat
import subprocess
import sys
import time
from pathlib import Path

import pytest

from camfab import writing
from camfab.writing import STALE_TEMP_SECONDS, remove_stale_temps, write_files

from .conftest import DESIGNS, run_cli

FILES = {"a.dxf": b"dxf", "a.svg": b"svg", "a.stl": b"stl"}


def _temps(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.endswith(".tmp"))


@pytest.mark.parametrize("umask", [0o022, 0o002, 0o077])
def test_files_are_readable_as_the_umask_allows(tmp_path: Path, umask: int) -> None:
    old = os.umask(umask)
    try:
        written = write_files(tmp_path / "out", FILES)
    finally:
        os.umask(old)
    for path in written:
        assert stat.S_IMODE(path.stat().st_mode) == 0o666 & ~umask, path


def test_a_build_writes_files_others_can_read(tmp_path: Path) -> None:
    old = os.umask(0o022)
    try:
        assert run_cli("build", str(DESIGNS / "seed-poly-345.yaml"), "-o", "out",
                       cwd=tmp_path).exit_code == 0
    finally:
        os.umask(old)
    modes = {p.name: stat.S_IMODE(p.stat().st_mode) for p in (tmp_path / "out").iterdir()}
    assert modes and set(modes.values()) == {0o644}, modes


@pytest.mark.parametrize("error", [KeyboardInterrupt, SystemExit, OSError])
def test_an_interrupted_write_removes_its_temporary_files(tmp_path: Path, monkeypatch,
                                                          error: type[BaseException]) -> None:
    folder = tmp_path / "out"
    write_files(folder, {"a.dxf": b"old"})
    calls = []
    real = os.replace

    def interrupted(src, dst):  # the second rename is interrupted
        calls.append(dst)
        if len(calls) == 2:
            raise error("stop")
        real(src, dst)

    monkeypatch.setattr(writing.os, "replace", interrupted)
    with pytest.raises((error, writing.OutputError)):
        write_files(folder, FILES)
    assert _temps(folder) == []


def test_stale_temporary_files_are_removed_by_the_next_build(tmp_path: Path) -> None:
    folder = tmp_path / "out"
    folder.mkdir()
    sleeper = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    try:
        dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                              capture_output=True, text=True, check=True).stdout.strip()
        names = {
            f".a.dxf.{dead}.0a1b2c3d.tmp": False,           # its build was killed: removed
            ".a.svg.k3j4h5g6.tmp": False,                    # an older camfab's name: removed
            f".a.stl.{sleeper.pid}.0a1b2c3d.tmp": True,      # a build still running: kept
            f".a.dxf.{sleeper.pid}.99999999.tmp": False,     # running, but a day old: removed
            f".other.dxf.{dead}.0a1b2c3d.tmp": True,         # not an output of this build
            "a.dxf.tmp": True,                               # not camfab's temporary name
        }
        for name in names:
            (folder / name).write_bytes(b"partial")
        old = time.time() - STALE_TEMP_SECONDS - 60
        os.utime(folder / f".a.dxf.{sleeper.pid}.99999999.tmp", (old, old))
        remove_stale_temps(folder, FILES)
        left = {p.name for p in folder.iterdir()}
        assert left == {name for name, kept in names.items() if kept}
    finally:
        sleeper.kill()
        sleeper.wait()


# ---- real processes, stopped by signals ------------------------------------------------------

def _caught(pid: int, signum: int) -> bool:
    """True once process *pid* has a handler of its own for *signum* (/proc's SigCgt)."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return False
    mask = next(int(line.split()[1], 16) for line in status.splitlines()
                if line.startswith("SigCgt:"))
    return bool(mask >> (signum - 1) & 1)


def _slow_design(folder: Path, name: str = "slow") -> Path:
    text = (DESIGNS / "seed-10-4.yaml").read_text().replace("name: seed-10-4", f"name: {name}")
    path = folder / f"{name}.yaml"
    path.write_text(text + "manufacturing: {tolerance: 0.0002}\n")
    return path


def _as_at_a_terminal() -> None:
    """Ctrl-C as a terminal's foreground command has it, whoever runs the tests: a shell's
    background job starts with SIGINT ignored, and camfab rightly keeps it ignored then."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
@pytest.mark.parametrize(("signum", "status"), [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
@pytest.mark.parametrize(("jobs", "delay"), [("1", 0.3), ("2", 0.3), ("2", 0.0)])
def test_a_signal_stops_a_build_with_its_status_and_no_temporary_files(
        tmp_path: Path, signum: int, status: int, jobs: str, delay: float) -> None:
    """A signal as soon as camfab has its handlers (a batch still setting up its workers), or
    once it is building."""
    designs = [str(_slow_design(tmp_path, f"slow{i}")) for i in range(3 if jobs == "2" else 1)]
    child = subprocess.Popen([sys.executable, "-m", "camfab", "build", *designs, "-o", "out",
                              "-j", jobs], cwd=tmp_path, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, start_new_session=True,
                             preexec_fn=_as_at_a_terminal)
    deadline = time.monotonic() + 120  # far beyond the second it takes to start
    while not _caught(child.pid, signal.SIGTERM) and time.monotonic() < deadline:
        time.sleep(0.01)
    time.sleep(delay)
    # Ctrl-C reaches every process of the terminal's group; SIGTERM is sent to camfab alone
    if signum == signal.SIGINT:
        os.killpg(child.pid, signum)
    else:
        child.send_signal(signum)
    out, err = child.communicate(timeout=300)
    # the status the shell reports; Python may end by the signal itself after the cleanup (when
    # it was delivered inside a library's embedded code), which a shell reports the same way
    assert child.returncode in (status, -signum), (out, err)
    assert err == ("camfab: interrupted\n" if signum == signal.SIGINT
                   else "camfab: stopped by signal 15\n"), err
    left = [p.name for p in tmp_path.rglob("*.tmp")]
    assert left == [], left


# ---- a batch -----------------------------------------------------------------------------------

@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_a_signal_a_library_wrapped_is_still_the_signal(monkeypatch, signum: int) -> None:
    """pydantic builds a model's schema on first use and wraps whatever is raised inside it in
    its own SchemaError: a SIGTERM arriving then must stop camfab as a signal, not be reported
    as an internal error of the design."""
    from camfab import cli, stopping

    def work() -> cli.Outcome:
        stopping.RECEIVED.append(signum)  # what the handler notes before it raises
        raise RuntimeError("SchemaError: Error building ... Interrupted: 15")

    stopping.RECEIVED.clear()
    with pytest.raises(cli.Interrupted) as caught:
        cli._guarded("d.yaml", work)
    assert caught.value.signum == signum


def test_a_wrapped_signal_outside_a_design_is_still_the_signal(monkeypatch, capsys) -> None:
    """The same when the wrapped signal escapes while camfab sets up (its modules imported
    before a batch starts): status 143 and the one line, not a traceback."""
    import click

    from camfab import cli, stopping

    @click.command("wrapped-signal")
    def wrapped() -> None:
        stopping.RECEIVED.append(signal.SIGTERM)
        raise RuntimeError("SchemaError: Error building ... Interrupted: 15")

    stopping.RECEIVED.clear()
    monkeypatch.setitem(cli.main.commands, "wrapped-signal", wrapped)
    old = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)}
    try:
        code = cli.main.main(["wrapped-signal"], standalone_mode=False)
    finally:
        for number, handler in old.items():
            signal.signal(number, handler)
    assert code == 143
    assert capsys.readouterr().err == "camfab: stopped by signal 15\n"


def test_two_designs_of_one_name_in_a_batch_are_not_both_written(tmp_path: Path) -> None:
    text = (DESIGNS / "seed-poly-345.yaml").read_text()
    (tmp_path / "a.yaml").write_text(text)
    (tmp_path / "b.yaml").write_text(text.replace("description:", "description: another,"))
    result = run_cli("build", "a.yaml", "b.yaml", "-o", "out", cwd=tmp_path)
    assert result.exit_code == 2
    assert result.stderr.strip() == (
        "b.yaml:5: name: 'seed-poly-345' is also the name of a.yaml in this batch: both would "
        "write the same files (give each design its own name)")
    assert "seed-poly-345  INVALID" in result.stdout
    assert "seed-poly-345  OK" in result.stdout
    assert (tmp_path / "out" / "seed-poly-345" / "seed-poly-345.dxf").is_file()


# ---- the user's environment --------------------------------------------------------------------

@pytest.mark.parametrize("content", [b"garbage\n", b"\xff\xfe[\x00c\x00",
                                     b"[core]\nx = 1\nx = 2\n"])
def test_a_damaged_ezdxf_config_changes_nothing(tmp_path: Path, content: bytes) -> None:
    """ezdxf reads ezdxf.ini from the user's config folder and the working directory when it is
    imported; a damaged one must neither fail the build nor change its bytes."""
    home = tmp_path / "home"
    (home / ".config" / "ezdxf").mkdir(parents=True)
    (home / ".config" / "ezdxf" / "ezdxf.ini").write_bytes(content)
    work = tmp_path / "work"
    work.mkdir()
    (work / "ezdxf.ini").write_bytes(content)
    design = str(DESIGNS / "seed-poly-345.yaml")
    env = {**os.environ, "HOME": str(home), "XDG_CONFIG_HOME": str(home / ".config")}
    env.pop("CAMFAB_DEBUG", None)
    run = subprocess.run([sys.executable, "-m", "camfab", "build", design, "-o", "out"],
                         cwd=work, env=env, capture_output=True, text=True, check=False)
    assert run.returncode == 0 and run.stderr == "", run.stderr
    clean = run_cli("build", design, "-o", "clean", cwd=tmp_path)
    assert clean.exit_code == 0
    for name in ("seed-poly-345.dxf", "seed-poly-345.svg", "seed-poly-345.stl"):
        assert (work / "out" / name).read_bytes() == (tmp_path / "clean" / name).read_bytes()
