"""Running camfab in a child process under limits of CPU time and memory.

A run that would hang or eat the machine (a pipe read forever, an array of terabytes) must not
take the test session with it: the child gets ``RLIMIT_CPU`` (it is killed by SIGXCPU past it)
and ``RLIMIT_AS`` (an allocation past it fails), and the parent reaps it with ``os.wait4`` to
learn the CPU seconds and the peak resident memory it used. CPU time, not wall-clock time, is
what the limits count, so a busy machine does not fail a test; the wall-clock guard is only a
backstop, many times the time the run should take.
"""

from __future__ import annotations

import os
import resource
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: Address space a child may map (bytes): the interpreter with numpy, scipy, shapely, ezdxf and
#: matplotlib maps some 1.5 GB, a run's arrays a few hundred megabytes more.
ADDRESS_SPACE = 4 * 1024**3
#: The same for a child forked from the test process, which maps what that process has mapped.
FORKED_ADDRESS_SPACE = 8 * 1024**3


@dataclass(frozen=True)
class ChildRun:
    """How a child process ended: its exit status (negative: killed by that signal), what it
    wrote, and the CPU seconds and peak resident memory (MB) it used."""

    code: int
    stdout: str
    stderr: str
    cpu_s: float
    peak_mb: float
    wall_s: float

    def describe(self) -> str:
        """How it ended and what it used, for an assertion's message."""
        return (f"exit {self.code}, {self.cpu_s:.2f} s CPU, {self.peak_mb:.0f} MB; "
                f"stderr: {self.stderr.strip()[:400]!r}")


def child_env() -> dict[str, str]:
    """The environment of a child: this checkout's camfab first on the path, one thread per
    numerical library (the limits count the child alone)."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT), env.get("PYTHONPATH")) if p)
    for name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        env[name] = "1"
    env.pop("CAMFAB_DEBUG", None)
    return env


def limits(cpu_s: float, address_space: int = ADDRESS_SPACE):  # type: ignore[no-untyped-def]
    """A ``preexec_fn`` setting the child's CPU time (s) and address space (bytes) limits."""

    def apply() -> None:
        seconds = max(1, int(cpu_s + 0.999))
        resource.setrlimit(resource.RLIMIT_CPU, (seconds, seconds + 1))
        resource.setrlimit(resource.RLIMIT_AS, (address_space, address_space))

    return apply


def run_limited(command: list[str], cpu_s: float, wall_s: float,
                address_space: int = ADDRESS_SPACE, cwd: Path | None = None,
                env: dict[str, str] | None = None) -> ChildRun:
    """Run *command* (argv) with at most *cpu_s* CPU seconds and *address_space* bytes; kill it
    after *wall_s* seconds of wall-clock time (a backstop). Its output goes through files, so a
    chatty child cannot block on a full pipe. Its environment is *env*, by default
    :func:`child_env`'s."""
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        started = time.monotonic()
        proc = subprocess.Popen(command, stdout=out, stderr=err, stdin=subprocess.DEVNULL,
                                cwd=cwd, env=child_env() if env is None else env,
                                preexec_fn=limits(cpu_s, address_space))
        status, usage = _reap(proc, started + wall_s)
        wall = time.monotonic() - started
        out.seek(0)
        err.seek(0)
        stdout = out.read().decode("utf-8", "replace")
        stderr = err.read().decode("utf-8", "replace")
    code = -os.WTERMSIG(status) if os.WIFSIGNALED(status) else os.WEXITSTATUS(status)
    peak_mb = usage.ru_maxrss / (1024.0 * 1024.0 if sys.platform == "darwin" else 1024.0)
    return ChildRun(code, stdout, stderr, usage.ru_utime + usage.ru_stime, peak_mb, wall)


def run_camfab(args: list[str], cpu_s: float = 30.0, wall_s: float = 300.0,
               cwd: Path | None = None) -> ChildRun:
    """``python -m camfab ARGS`` under :func:`run_limited`."""
    return run_limited([sys.executable, "-m", "camfab", *args], cpu_s, wall_s, cwd=cwd)


def _reap(proc: subprocess.Popen[bytes], deadline: float) -> tuple[int, resource.struct_rusage]:
    """Wait for *proc* (killing it at *deadline*, a monotonic time) and return its status and
    resource usage, from ``os.wait4``."""
    status, usage = _wait(proc.pid, deadline)
    proc.returncode = status  # reaped here: Popen must not wait for it again
    return status, usage


def _wait(pid: int, deadline: float) -> tuple[int, resource.struct_rusage]:
    """Wait for the child *pid*, killing it at *deadline* (a monotonic time): its status and
    resource usage, from ``os.wait4``."""
    while True:
        done, status, usage = os.wait4(pid, os.WNOHANG)
        if done == pid:
            return status, usage
        if time.monotonic() > deadline:
            os.kill(pid, signal.SIGKILL)
            _, status, usage = os.wait4(pid, 0)
            return status, usage
        time.sleep(0.01)


# ---- forked from this process: a case costs its own work, not a new interpreter's start -------

def run_forked(args: list[str], cwd: Path, cpu_s: float = 30.0,
               wall_s: float = 300.0) -> ChildRun:
    """``camfab ARGS`` run in *cwd* in a child forked from this process, which has imported
    camfab and its libraries already (:func:`_warm`), under the limits of :func:`limits`. Its
    peak memory is its growth over what it shared with this process at the fork (MB)."""
    _warm()
    with tempfile.TemporaryDirectory(prefix="camfab-forked-") as tmp:
        out_path, err_path, base_path = (Path(tmp) / n for n in ("out", "err", "base"))
        sys.stdout.flush()
        sys.stderr.flush()
        started = time.monotonic()
        pid = os.fork()
        if pid == 0:  # the child: never returns
            _forked_child(args, cwd, cpu_s, out_path, err_path, base_path)
        status, usage = _wait(pid, started + wall_s)
        wall = time.monotonic() - started
        base_kb = int(base_path.read_text() or 0) if base_path.exists() else 0
        code = -os.WTERMSIG(status) if os.WIFSIGNALED(status) else os.WEXITSTATUS(status)
        return ChildRun(code, out_path.read_text(errors="replace"),
                        err_path.read_text(errors="replace"), usage.ru_utime + usage.ru_stime,
                        max(0, usage.ru_maxrss - base_kb) / 1024.0, wall)


def _warm() -> None:
    """Import what a build uses once, in this process, so that every forked child shares it."""
    import ezdxf
    import manifold3d
    import shapely

    import camfab.cli
    import camfab.design.units
    import camfab.export.report_html
    import camfab.kinds.readback
    import camfab.pipeline

    assert ezdxf and manifold3d and shapely and camfab.cli and camfab.pipeline
    assert camfab.export.report_html and camfab.kinds.readback
    camfab.design.units.registry()


def _resident_kb() -> int:
    with open("/proc/self/statm") as stream:
        return int(stream.read().split()[1]) * (os.sysconf("SC_PAGE_SIZE") // 1024)


def _forked_child(args: list[str], cwd: Path, cpu_s: float, out_path: Path, err_path: Path,
                  base_path: Path) -> None:
    code = 70
    try:
        os.chdir(cwd)
        os.environ.pop("CAMFAB_DEBUG", None)
        os.dup2(os.open(out_path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600), 1)
        os.dup2(os.open(err_path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600), 2)
        sys.stdout = open(1, "w", encoding="utf-8", closefd=False)
        sys.stderr = open(2, "w", encoding="utf-8", closefd=False)
        for number in (signal.SIGINT, signal.SIGTERM, signal.SIGALRM, signal.SIGPROF):
            signal.signal(number, signal.SIG_DFL)
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.setitimer(signal.ITIMER_PROF, 0)
        # the fork maps all this process has mapped: room for that on top of the run's own
        limits(cpu_s, FORKED_ADDRESS_SPACE)()
        base_path.write_text(str(_resident_kb()))
        from camfab.cli import main

        main.main(list(args), prog_name="camfab")
        code = 0
    except SystemExit as exc:
        code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    except BaseException:
        import traceback

        traceback.print_exc()
        code = 70
    finally:
        try:
            sys.stdout.flush()
            sys.stderr.flush()
        finally:
            os._exit(code)
