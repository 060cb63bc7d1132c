"""What the build benchmarks share: the repository, camfab byte-compiled as ``pip install``
leaves it, the modules a build imports, the wall time of a command in a fresh process, and the
median time of a call made in process."""

from __future__ import annotations

import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]


def compile_package(checkout: Path = ROOT) -> None:
    """Byte-compile the camfab of *checkout* (this one by default), so that a build reads
    bytecode even where writing it is off."""
    subprocess.run([sys.executable, "-m", "compileall", "-q", str(checkout / "camfab")],
                   check=True)


#: Prints the modules ``camfab build`` of the arguments argv[1:] has imported when it ends.
_MODULES_OF_A_BUILD = """
import contextlib, io, runpy, sys, tempfile
with tempfile.TemporaryDirectory() as out:
    sys.argv = ["camfab", "build", *sys.argv[1:], "-o", out]
    try:
        with contextlib.redirect_stdout(io.StringIO()):
            runpy.run_module("camfab", run_name="__main__")
    except SystemExit:
        pass
print(" ".join(name for name in sys.modules if not name.startswith("_")
               and name.split(".")[0] not in sys.stdlib_module_names
               and name != "cython_runtime"))
"""


def modules_of_build(design: Path, *options: str) -> list[str]:
    """The modules ``camfab build DESIGN OPTIONS`` (this checkout's) has imported when it ends,
    in the order imported: camfab's and other packages', not Python's own."""
    return subprocess.run([sys.executable, "-c", _MODULES_OF_A_BUILD, str(design), *options],
                          check=True, capture_output=True, text=True,
                          cwd=ROOT).stdout.split()


def wall(args: list[str]) -> float:
    """Seconds a command takes, run from the repository with its output discarded."""
    return wall_and_cpu(args)[0]


def wall_in(args: list[str], env: dict[str, str] | None) -> float:
    """Seconds a command takes in the environment *env* (None: this one, from the repository),
    run from the checkout *env* puts on ``PYTHONPATH`` (``python -m`` puts its folder first on
    the path), its output discarded."""
    if env is None:
        return wall(args)
    start = time.perf_counter()
    subprocess.run(args, check=False, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                   cwd=env["PYTHONPATH"], env=env)
    return time.perf_counter() - start


def wall_and_cpu(args: list[str]) -> tuple[float, float]:
    """Seconds a command takes, run from the repository with its output discarded, and the
    processor seconds (user and system) it and its children used (0 where the platform does not
    count them)."""
    before = _children_cpu()
    start = time.perf_counter()
    subprocess.run(args, check=False, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                   cwd=ROOT)
    return time.perf_counter() - start, _children_cpu() - before


def _children_cpu() -> float:
    """Processor seconds used so far by the waited-for children of this process."""
    try:
        import resource
    except ImportError:  # not on Windows
        return 0.0
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def use_checkout() -> None:
    """Import camfab from this checkout (ahead of any installed copy)."""
    if str(ROOT) not in sys.path:
        sys.path.insert(0, str(ROOT))


def seconds(job: Callable[[], Any]) -> float:
    """Seconds one call of *job* takes."""
    start = time.perf_counter()
    job()
    return time.perf_counter() - start


def median_seconds(job: Callable[[], Any], runs: int, warm: int = 1) -> float:
    """Median seconds of *runs* calls of *job*, after *warm* untimed calls (imports, caches)."""
    for _ in range(warm):
        job()
    return statistics.median(seconds(job) for _ in range(runs))


def build_time(design_path: Path, runs: int) -> float:
    """Median wall seconds of ``camfab build DESIGN`` (every output) in a fresh process, after
    one run that is not counted."""
    import tempfile

    compile_package()
    with tempfile.TemporaryDirectory() as folder:
        command = [sys.executable, "-m", "camfab", "build", str(design_path), "-o", folder]
        times = [wall(command) for _ in range(runs + 1)]
    return statistics.median(times[1:])
