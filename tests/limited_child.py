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
                address_space: int = ADDRESS_SPACE, cwd: Path | None = None) -> ChildRun:
    """Run *command* (argv) with at most *cpu_s* CPU seconds and *address_space* bytes; kill it
    after *wall_s* seconds of wall-clock time (a backstop). Its output goes through files, so a
    chatty child cannot block on a full pipe."""
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        started = time.monotonic()
        proc = subprocess.Popen(command, stdout=out, stderr=err, stdin=subprocess.DEVNULL,
                                cwd=cwd, env=child_env(), preexec_fn=limits(cpu_s, address_space))
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
    while True:
        pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
        if pid == proc.pid:
            proc.returncode = status  # reaped here: Popen must not wait for it again
            return status, usage
        if time.monotonic() > deadline:
            proc.send_signal(signal.SIGKILL)
            _, status, usage = os.wait4(proc.pid, 0)
            proc.returncode = status
            return status, usage
        time.sleep(0.02)
