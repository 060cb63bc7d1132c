"""The user's environment changes no byte camfab writes and stops no run: ezdxf's font cache in
``$XDG_CACHE_HOME`` or ``~/.cache`` (unreadable, damaged, a file where a folder should be, a
path too long) is never read or written.

ezdxf reads its font cache when it is imported, so each case runs camfab in a process of its
own. A folder of mode 0 stops only a user that is not root (root reads it regardless); the other
cases fail whoever runs them. Keeping the user's files out of ezdxf's reach changes neither the
working directory nor the environment, which the studio's other threads read meanwhile.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from .conftest import DESIGNS, run_cli
from .limited_child import child_env

DESIGN = DESIGNS / "seed-poly-345.yaml"

#: What ezdxf's font cache folder (or the home folder holding it) is: see :func:`_environment`.
CASES = ["cache-unreadable", "home-unreadable", "cache-damaged", "home-cache-damaged",
         "cache-is-a-file", "cache-name-too-long"]


def _environment(case: str, scratch: Path) -> dict[str, str]:
    """The variables that point ezdxf's font cache at what *case* names, made in *scratch*."""
    if case in ("cache-unreadable", "home-unreadable"):
        locked = scratch / "locked"
        (locked / ".cache" / "ezdxf").mkdir(parents=True)
        locked.chmod(0)
        return {"XDG_CACHE_HOME" if case == "cache-unreadable" else "HOME": str(locked)}
    if case == "cache-damaged":
        (scratch / "cache" / "ezdxf").mkdir(parents=True)
        (scratch / "cache" / "ezdxf" / "font_manager_cache.json").write_text("[]")
        return {"XDG_CACHE_HOME": str(scratch / "cache")}
    if case == "home-cache-damaged":
        (scratch / "home" / ".cache" / "ezdxf").mkdir(parents=True)
        (scratch / "home" / ".cache" / "ezdxf" / "font_manager_cache.json").write_text(
            '{"version": 2, "font-faces": 7}')
        return {"HOME": str(scratch / "home")}
    if case == "cache-is-a-file":
        (scratch / "file").write_text("not a folder")
        return {"XDG_CACHE_HOME": str(scratch / "file")}
    return {"XDG_CACHE_HOME": str(scratch / ("x" * 300))}  # a name longer than any allows


def _camfab(args: list[str], cwd: Path, env: dict[str, str]) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "camfab", *args], cwd=cwd,
                          env={**child_env(), **env}, capture_output=True, text=True,
                          check=False, timeout=300)


@pytest.fixture
def scratch(tmp_path: Path) -> Iterator[Path]:
    """A scratch folder, its locked folder opened again afterwards so it can be removed."""
    yield tmp_path
    for locked in tmp_path.glob("locked"):
        locked.chmod(0o700)


@pytest.mark.parametrize("case", CASES)
def test_ezdxfs_font_cache_is_not_the_users(scratch: Path, case: str) -> None:
    env = _environment(case, scratch)
    run = _camfab(["build", str(DESIGN), "-o", "out"], scratch, env)
    assert run.returncode == 0 and run.stderr == "", run.stderr
    clean = run_cli("build", str(DESIGN), "-o", "clean", cwd=scratch)
    assert clean.exit_code == 0
    for name in ("seed-poly-345.dxf", "seed-poly-345.svg", "seed-poly-345.stl"):
        assert (scratch / "out" / name).read_bytes() == (scratch / "clean" / name).read_bytes()
    if case in ("cache-damaged", "cache-name-too-long"):  # inspect imports ezdxf the same way
        inspect = _camfab(["inspect", "out/seed-poly-345.dxf", "--design", str(DESIGN), "-o",
                           "inspection"], scratch, env)
        assert inspect.returncode == 0 and inspect.stderr == "", inspect.stderr
        assert (scratch / "inspection" / "seed-poly-345-inspection.json").is_file()


#: A child that imports ezdxf through camfab in one thread while another reads the working
#: directory and the environment as fast as it can: every change it saw, and how many reads.
_WATCHED_IMPORT = """
import os, sys, threading
import numpy  # (imported by the studio long before ezdxf; it sets a variable of its own)
from camfab.export.ezdxf_import import load_ezdxf

before = (os.getcwd(), dict(os.environ))
done = threading.Event()
seen, reads = [], [0]

def watch():
    while not done.is_set():
        now = (os.getcwd(), dict(os.environ))
        reads[0] += 1
        if now != before and len(seen) < 5:
            changed = {k for k in set(now[1]) | set(before[1]) if now[1].get(k) != before[1].get(k)}
            seen.append((now[0], sorted(changed)))

watcher = threading.Thread(target=watch)
watcher.start()
try:
    load_ezdxf()
finally:
    done.set()
    watcher.join()
after = (os.getcwd(), dict(os.environ)) == before
print(repr((seen, reads[0], "ezdxf" in sys.modules and after)))
"""


def test_importing_ezdxf_changes_neither_the_working_directory_nor_the_environment(
        tmp_path: Path) -> None:
    """Another thread (the studio's) sees the working directory and every variable of the
    environment unchanged all through ezdxf's import, whatever the user's ezdxf files are; and
    the variables ezdxf would read its files from are the user's after it."""
    env = {"HOME": str(tmp_path / "home"), "XDG_CACHE_HOME": str(tmp_path / "cache"),
           "XDG_CONFIG_HOME": str(tmp_path / "config"),
           "EZDXF_CONFIG_FILE": str(tmp_path / "ezdxf.ini")}
    (tmp_path / "ezdxf.ini").write_text("garbage\n")
    run = subprocess.run([sys.executable, "-c", _WATCHED_IMPORT], cwd=tmp_path,
                         env={**child_env(), **env}, capture_output=True, text=True,
                         check=False, timeout=120)
    assert run.returncode == 0 and run.stderr == "", run.stderr
    seen, reads, imported = ast.literal_eval(run.stdout)
    assert imported and reads > 1
    assert seen == []
