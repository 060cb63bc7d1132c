"""The user's environment changes no byte camfab writes and stops no run: ezdxf's font cache in
``$XDG_CACHE_HOME`` or ``~/.cache`` (unreadable, damaged, a file where a folder should be, a
path too long) is never read or written.

ezdxf reads its font cache when it is imported, so each case runs camfab in a process of its
own. A folder of mode 0 stops only a user that is not root (root reads it regardless); the other
cases fail whoever runs them.
"""

from __future__ import annotations

import os
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


def test_the_environment_is_restored_after_the_import(tmp_path: Path) -> None:
    """The variables hidden from ezdxf for the moment of its import, and the working directory,
    are the user's again after it."""
    env = {"HOME": str(tmp_path / "home"), "XDG_CACHE_HOME": str(tmp_path / "cache"),
           "XDG_CONFIG_HOME": str(tmp_path / "config"),
           "EZDXF_CONFIG_FILE": str(tmp_path / "ezdxf.ini")}
    script = ("import os, sys; from camfab.export.ezdxf_import import load_ezdxf; load_ezdxf(); "
              "print('|'.join(os.environ.get(k, '-') for k in sys.argv[1:]), os.getcwd())")
    run = subprocess.run([sys.executable, "-c", script, *env, "USERPROFILE"], cwd=tmp_path,
                         env={**child_env(), **env}, capture_output=True, text=True,
                         check=False, timeout=120)
    assert run.returncode == 0, run.stderr
    shown, cwd = run.stdout.split()
    assert shown == "|".join([*env.values(), os.environ.get("USERPROFILE", "-")])
    assert Path(cwd).resolve() == tmp_path.resolve()
