"""Every command run as the ``camfab`` program, with a standard output that cannot be written (a
full disk, a closed stdout, a pipe whose reader is gone) or that does not take UTF-8 (ASCII,
latin-1, a Windows code page): one line and status 74 for the first, the command's own work and
status for the second, never a traceback."""

from __future__ import annotations

import io
import os
import re
import signal
import subprocess
import sys
import time
from functools import cache
from pathlib import Path

import pytest

from camfab.terminal import CANNOT_WRITE, fit, stand_in

from .conftest import DESIGNS
from .limited_child import _wait, _warm, child_env

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"),
                                reason="/dev/full, and forks as Linux has them")

DESIGN = DESIGNS / "seed-10-4.yaml"  # FAIL (status 1): its pressure angle is over the limit

#: Each command with its arguments (a placeholder ``OUT`` for a folder to write into) and the
#: status it ends with when its output is written.
COMMANDS = {
    "build": (["build", str(DESIGN), "-o", "OUT"], 1),
    "check": (["check", str(DESIGN)], 1),
    "size": (["size", str(DESIGN)], 0),
    "laws": (["laws"], 0),
    "new": (["new", "globoidal"], 0),
    "sweep": (["sweep", str(DESIGN), "--vary", "cam.base_radius=30,40", "-j", "1", "-o", "OUT"],
              0),
    "inspect": (["inspect", "OUTLINE", "--type", "roller", "--roller-radius", "5", "-o", "OUT"],
                0),
    "--version": (["--version"], 0),
    "--help": (["--help"], 0),
}

#: What standard output is, and the reason the one line gives when it cannot be written.
BROKEN = {"full": "No space left on device", "closed": "standard output is closed",
          "pipe": "Broken pipe"}


def _outline(tmp_path: Path) -> Path:
    """A CSV outline of a circle of radius 30 mm (a cam with no lift) for ``inspect``."""
    import numpy as np

    angle = np.linspace(0.0, 2.0 * np.pi, 360, endpoint=False)
    path = tmp_path / "circle.csv"
    path.write_text("".join(f"{30 * np.cos(a):.6f},{30 * np.sin(a):.6f}\n" for a in angle))
    return path


def _args(command: str, tmp_path: Path) -> tuple[list[str], int]:
    args, status = COMMANDS[command]
    named = {"OUT": str(tmp_path / "out")}
    if "OUTLINE" in args:
        named["OUTLINE"] = str(_outline(tmp_path))
    return [named.get(a, a) for a in args], status


def run_program(args: list[str], cwd: Path, stdout: str = "file",
                encoding: str = "utf-8") -> tuple[int, bytes, str]:
    """``camfab ARGS`` as the program (:func:`camfab.start.main`) in a child forked from this
    process, with standard output *stdout* (``file``, ``full``: /dev/full, ``closed``,
    ``pipe``: a pipe whose reader is gone) and the standard streams in *encoding*, as Python
    opens them under a locale or ``PYTHONIOENCODING`` of it: its status, stdout bytes, stderr
    (decoded as *encoding*)."""
    _warm_all()
    out, err = cwd / "stdout", cwd / "stderr"
    sys.stdout.flush()
    sys.stderr.flush()
    pid = os.fork()
    if pid == 0:  # the child: never returns
        code = 70
        try:
            code = _child(args, cwd, stdout, encoding, out, err)
        finally:
            os._exit(code)
    status, _ = _wait(pid, time.monotonic() + 600.0)  # (a backstop)
    code = -os.WTERMSIG(status) if os.WIFSIGNALED(status) else os.WEXITSTATUS(status)
    data = out.read_bytes() if out.exists() else b""
    return code, data, err.read_bytes().decode(encoding, "replace")


@cache
def _warm_all() -> None:
    """Import what every command here uses once, in this process, so that each child has it:
    an inspection run here (its libraries are imported inside the functions that use them)."""
    import contextlib
    import tempfile

    from camfab.cli import main

    _warm()
    with tempfile.TemporaryDirectory() as tmp, contextlib.redirect_stdout(io.StringIO()):
        main.main(["inspect", str(_outline(Path(tmp))), "--type", "roller", "--roller-radius",
                   "5", "-o", tmp], standalone_mode=False)


def _child(args: list[str], cwd: Path, stdout: str, encoding: str, out: Path,
           err: Path) -> int:
    from camfab import stopping

    flags = os.O_WRONLY | os.O_CREAT | os.O_TRUNC
    os.chdir(cwd)
    os.environ.pop("CAMFAB_DEBUG", None)
    os.dup2(os.open(err, flags, 0o600), 2)
    if stdout == "file":
        os.dup2(os.open(out, flags, 0o600), 1)
    elif stdout == "full":
        os.dup2(os.open("/dev/full", os.O_WRONLY), 1)
    elif stdout == "pipe":
        read, write = os.pipe()
        os.dup2(write, 1)
        os.close(read)
        os.close(write)
    else:
        os.close(1)
    sys.stdout = None if stdout == "closed" else io.TextIOWrapper(  # type: ignore[assignment]
        io.BufferedWriter(io.FileIO(1, "w", closefd=False)), encoding=encoding)
    sys.stderr = io.TextIOWrapper(io.BufferedWriter(io.FileIO(2, "w", closefd=False)),
                                  encoding=encoding, errors="backslashreplace",
                                  line_buffering=True)
    signal.signal(signal.SIGINT, signal.default_int_handler)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    stopping.RECEIVED.clear()
    sys.argv = ["camfab", *args]
    try:
        from camfab.start import main

        main()
    except SystemExit as exc:
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    except BaseException:
        import traceback

        traceback.print_exc()
    return 70


@pytest.mark.parametrize("command", list(COMMANDS))
def test_an_output_that_cannot_be_written_is_one_line_and_74(tmp_path: Path,
                                                             command: str) -> None:
    args, _ = _args(command, tmp_path)
    for stdout, reason in BROKEN.items():
        code, _, err = run_program(args, tmp_path, stdout)
        assert (code, err) == (CANNOT_WRITE, f"camfab: cannot write the output ({reason})\n"), \
            (stdout, err)


@pytest.mark.parametrize("command", list(COMMANDS))
def test_every_command_writes_to_an_output_without_utf8(tmp_path: Path, command: str) -> None:
    """The command's own status and work; what the encoding lacks written as ASCII stand-ins
    (an ASCII output gets ASCII alone)."""
    args, status = _args(command, tmp_path)
    code, text, err = run_program(args, tmp_path)
    assert (code, err) == (status, ""), err
    utf8 = text.decode("utf-8")
    for encoding in ("ascii", "latin-1", "cp1252"):
        code, data, err = run_program(args, tmp_path, encoding=encoding)
        assert (code, err) == (status, ""), (encoding, err)
        written = data.decode(encoding)  # strictly: nothing but the encoding's own bytes
        if command not in ("check", "laws"):  # (no table, whose frame an encoding changes)
            expected = fit(utf8, io.TextIOWrapper(io.BytesIO(), encoding=encoding))
            assert _untimed(written) == _untimed(expected)


def _untimed(text: str) -> str:
    """*text* without the times a sweep says it took."""
    return re.sub(r"in [\d.]+ s( \([\d.]+ a second\))?", "in ...", text)


def test_the_stand_ins_read_as_words() -> None:
    assert [stand_in(c) for c in "✔✖—θ°Ψé₀∞"] == ["ok", "x", "-", "theta", " deg", "Psi", "e",
                                                  "0", "inf"]
    ascii_ = io.TextIOWrapper(io.BytesIO(), encoding="ascii")
    assert fit("θ (°) up to 40° — ✔", ascii_) == "theta (deg) up to 40 deg - ok"
    latin = io.TextIOWrapper(io.BytesIO(), encoding="latin-1")
    assert fit("θ (°) up to 40° — ✔", latin) == "theta (°) up to 40° - ok"


@pytest.mark.parametrize(("environment", "stdout", "line", "status"), [
    ({"PYTHONIOENCODING": "latin-1"}, "full", "cannot write the output (No space left on device)",
     CANNOT_WRITE),
    ({"LC_ALL": "C", "PYTHONUTF8": "0", "PYTHONCOERCECLOCALE": "0"}, "file", None, 0),
])
def test_the_program_itself(tmp_path: Path, environment: dict[str, str], stdout: str,
                            line: str | None, status: int) -> None:
    """``python -m camfab laws`` started afresh: Python's own streams of that locale."""
    target = "/dev/full" if stdout == "full" else tmp_path / "laws.txt"
    with open(target, "wb") as out:
        done = subprocess.run([sys.executable, "-m", "camfab", "laws"], stdout=out,
                              stderr=subprocess.PIPE, env={**child_env(), **environment},
                              timeout=300)
    err = done.stderr.decode("ascii")
    assert (done.returncode, err) == (status, f"camfab: {line}\n" if line else "")
    if stdout == "file":
        text = (tmp_path / "laws.txt").read_bytes().decode("ascii")
        assert "| uniform-velocity" in text and "inf at ends" in text
