"""Run the ``camfab`` command line in a forked child under limits of CPU time and memory, and
measure what it used.

The child is forked from the test process, which has imported camfab and its libraries already,
so a case costs its own work and not a new interpreter's start. Runaway work is stopped by CPU
time (``RLIMIT_CPU``), not by the clock, so a case does not fail because the machine is busy;
the clock only guards against a child that waits forever (a FIFO), far beyond any real run.
The peak resident memory is the child's growth over what it shared with its parent at the fork.
"""

from __future__ import annotations

import os
import resource
import signal
import sys
import tempfile
import time
import traceback
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

#: A child that has not ended after this many seconds of the clock is stuck waiting, not working
#: (a FIFO, a device): far beyond the CPU limits the cases use, so a loaded machine passes.
WALL_GUARD_SECONDS = 300.0

#: Address space a child may map (bytes): room for numpy's and the libraries' reservations, and
#: a runaway allocation fails at once instead of taking the machine's memory.
ADDRESS_SPACE = 6 << 30


@dataclass(frozen=True)
class Run:
    """A finished child: its exit status (None when a signal ended it), that signal, what it
    printed, the CPU seconds it used and the growth of its resident memory (MB)."""

    code: int | None
    signal: int | None
    out: str
    err: str
    cpu_seconds: float
    peak_rss_mb: float

    def describe(self) -> str:
        end = f"exit {self.code}" if self.code is not None else f"signal {self.signal}"
        return (f"{end}, {self.cpu_seconds:.2f} s CPU, +{self.peak_rss_mb:.0f} MB resident; "
                f"stderr: {self.err.strip()[:400]!r}")


def _resident_kb() -> int:
    with open("/proc/self/statm") as stream:
        return int(stream.read().split()[1]) * (os.sysconf("SC_PAGE_SIZE") // 1024)


def _warm() -> None:
    """Import what a build uses once, in the parent, so that every child shares it."""
    import ezdxf
    import manifold3d
    import shapely
    import trimesh

    import camfab.cli
    import camfab.design.units
    import camfab.export.report_html
    import camfab.pipeline
    import camfab.verification

    assert ezdxf and manifold3d and shapely and trimesh and camfab.cli and camfab.pipeline
    assert camfab.export.report_html and camfab.verification
    camfab.design.units.registry()


def run_bounded(args: Sequence[str], cwd: Path, cpu_seconds: float = 30.0,
                env: dict[str, str] | None = None) -> Run:
    """``camfab ARGS`` run in *cwd* in a forked child limited to *cpu_seconds* of CPU time and
    :data:`ADDRESS_SPACE` of memory, with *env* added to its environment."""
    _warm()
    with tempfile.TemporaryDirectory(prefix="camfab-bounded-") as tmp:
        out_path, err_path, base_path = (Path(tmp) / n for n in ("out", "err", "base"))
        sys.stdout.flush()
        sys.stderr.flush()
        pid = os.fork()
        if pid == 0:  # the child: never returns
            _child(args, cwd, cpu_seconds, env or {}, out_path, err_path, base_path)
        start = time.monotonic()
        while True:
            done, status, usage = os.wait4(pid, os.WNOHANG)
            if done:
                break
            if time.monotonic() - start > WALL_GUARD_SECONDS:
                os.kill(pid, signal.SIGKILL)
                done, status, usage = os.wait4(pid, 0)
                break
            time.sleep(0.01)
        base_kb = int(base_path.read_text() or 0) if base_path.exists() else 0
        return Run(os.WEXITSTATUS(status) if os.WIFEXITED(status) else None,
                   os.WTERMSIG(status) if os.WIFSIGNALED(status) else None,
                   out_path.read_text(errors="replace"), err_path.read_text(errors="replace"),
                   usage.ru_utime + usage.ru_stime, max(0, usage.ru_maxrss - base_kb) / 1024)


def _child(args: Sequence[str], cwd: Path, cpu_seconds: float, env: dict[str, str],
           out_path: Path, err_path: Path, base_path: Path) -> None:
    code = 70
    try:
        os.chdir(cwd)
        os.environ.update(env)
        os.environ.pop("CAMFAB_DEBUG", None)
        out = os.open(out_path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
        err = os.open(err_path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
        os.dup2(out, 1)
        os.dup2(err, 2)
        sys.stdout = open(1, "w", encoding="utf-8", closefd=False)
        sys.stderr = open(2, "w", encoding="utf-8", closefd=False)
        for number in (signal.SIGINT, signal.SIGTERM, signal.SIGALRM, signal.SIGPROF):
            signal.signal(number, signal.SIG_DFL)
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.setitimer(signal.ITIMER_PROF, 0)
        seconds = max(1, int(cpu_seconds + 0.999))
        resource.setrlimit(resource.RLIMIT_CPU, (seconds, seconds + 2))
        resource.setrlimit(resource.RLIMIT_AS, (ADDRESS_SPACE, ADDRESS_SPACE))
        base_path.write_text(str(_resident_kb()))
        from camfab.cli import main

        main.main(list(args), prog_name="camfab")
        code = 0
    except SystemExit as exc:
        code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    except BaseException:
        traceback.print_exc()
        code = 70
    finally:
        try:
            sys.stdout.flush()
            sys.stderr.flush()
        finally:
            os._exit(code)
