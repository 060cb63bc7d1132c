"""What the build benchmarks share: the repository, camfab byte-compiled as ``pip install``
leaves it, and the wall time of a command in a fresh process."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def compile_package() -> None:
    """Byte-compile camfab, so that a build reads bytecode even where writing it is off."""
    subprocess.run([sys.executable, "-m", "compileall", "-q", str(ROOT / "camfab")], check=True)


def wall(args: list[str]) -> float:
    """Seconds a command takes, run from the repository with its output discarded."""
    start = time.perf_counter()
    subprocess.run(args, check=False, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                   cwd=ROOT)
    return time.perf_counter() - start
