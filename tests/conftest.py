"""Shared helpers: the example designs, a way to run the command line in a temporary folder,
every example and starter built once for the tests of the files, and the real consumer programs
those tests run."""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner, Result

from camfab.cli import STARTER_KINDS, main

ROOT = Path(__file__).resolve().parents[1]
DESIGNS = ROOT / "designs"
DESIGN_FILES = sorted(DESIGNS.glob("*.yaml"))

#: Every example design (by file stem) and every starter of ``camfab new`` (``new-KIND``).
EVERY_DESIGN = [p.stem for p in DESIGN_FILES] + [f"new-{kind}" for kind in STARTER_KINDS]

#: CI sets this so that a missing consumer fails the run instead of skipping its tests.
REQUIRED = bool(os.environ.get("CAMFAB_REQUIRE_CONSUMERS"))


def tool(name: str, package: str | None = None) -> str:
    """The path of the program *name*; a skip (a failure in CI) when it is not installed."""
    path = shutil.which(name)
    if path is None:
        if REQUIRED:
            pytest.fail(f"{name} is not installed")
        pytest.skip(f"{name} is not installed (apt-get install {package or name})")
    return path


def chromium(*flags: str) -> Any:
    """Debian's Chromium, headless, driven through Selenium (chromium-driver; nothing downloads
    a browser), with *flags* besides the ones every test gives it; a skip (a failure in CI)
    when any of them is not installed."""
    webdriver = pytest.importorskip("selenium.webdriver")
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    for flag in ("--headless=new", "--no-sandbox", "--disable-background-networking",
                 "--no-first-run", *flags):
        options.add_argument(flag)
    options.binary_location = tool("chromium", "chromium")
    return webdriver.Chrome(service=Service(tool("chromedriver", "chromium-driver")),
                            options=options)


def page_wait(browser: Any, script: str, *args: Any, seconds: float = 120.0) -> Any:
    """The first true value *script* (run in the page with *args*) returns, asked every 50 ms
    (a failure after *seconds*)."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        value = browser.execute_script(script, *args)
        if value:
            return value
        time.sleep(0.05)
    raise AssertionError(f"the page never came to: {script}")


@contextmanager
def serving(file: Path, seconds: float = 120.0) -> Iterator[str]:
    """``camfab serve`` of the design *file* (run in its folder, on a free port): the address of
    its page; on leaving, stopped by Ctrl-C, which it must take cleanly (a backstop of
    *seconds* on the stop)."""
    server = subprocess.Popen([sys.executable, "-m", "camfab", "serve", file.name, "--no-open",
                               "--port", "0"], cwd=file.parent, stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True)
    url = re.search(r"http://\S+", server.stdout.readline())
    if url is None:
        server.kill()
        pytest.fail(server.communicate(timeout=seconds)[1])
    try:
        yield url.group(0)
    finally:
        server.send_signal(signal.SIGINT)
        _, err = server.communicate(timeout=seconds)
    assert server.returncode == 130 and err == "camfab: interrupted\n"


def need_step_extra() -> None:
    """At a test module's top: skip the module (fail it in CI, which installs the extra) when
    the STEP extra's OpenCASCADE bindings are not installed."""
    from importlib.util import find_spec

    if find_spec("OCP") is None:
        why = "the STEP extra (pip install 'camfab[step]') is not installed"
        if REQUIRED:
            pytest.fail(why, pytrace=False)
        pytest.skip(why, allow_module_level=True)


def run_cli(*args: str, cwd: Path | None = None) -> Result:
    """Run ``camfab ARGS`` in-process (in *cwd* when given) and return the click result."""
    runner = CliRunner()
    if cwd is None:
        return runner.invoke(main, list(args), catch_exceptions=False)
    import os

    old = Path.cwd()
    os.chdir(cwd)
    try:
        return runner.invoke(main, list(args), catch_exceptions=False)
    finally:
        os.chdir(old)


def rad(deg: float) -> float:
    return math.radians(deg)


@pytest.fixture
def seed_10_4_text() -> str:
    return (DESIGNS / "seed-10-4.yaml").read_text()


@dataclass(frozen=True)
class Built:
    """One design built into *folder*: its design, report (the JSON, parsed) and the outputs it
    asked for and did not get (with why)."""

    design: Any
    folder: Path
    report: dict[str, Any]
    not_produced: tuple[str, ...]

    def files(self, suffix: str) -> list[Path]:
        """The files written with this suffix (``.dxf``, ``.svg``, ``.stl``), sorted."""
        return sorted(self.folder.glob(f"*{suffix}"))


@pytest.fixture(scope="session")
def every_build(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Built]:
    """Every example design and every starter (as ``camfab new KIND`` prints it), built once
    for the session, each into a folder of its own, by :data:`EVERY_DESIGN` name."""
    from camfab.pipeline import analyse, load_design, render

    root = tmp_path_factory.mktemp("every-build")
    sources = {p.stem: p for p in DESIGN_FILES}
    for kind in STARTER_KINDS:
        result = run_cli("new", kind)
        assert result.exit_code == 0, result.output
        sources[f"new-{kind}"] = root / f"new-{kind}.yaml"
        sources[f"new-{kind}"].write_text(result.output)
    built = {}
    for name, path in sources.items():
        design = load_design(path)
        artifacts = render(analyse(design))
        folder = root / name
        folder.mkdir()
        for file_name, data in artifacts.files.items():
            (folder / file_name).write_bytes(data)
        report = json.loads(artifacts.files[f"{design.name}-report.json"])
        built[name] = Built(design, folder, report, artifacts.not_produced)
    return built


@pytest.fixture(autouse=True)
def _no_stop_noted() -> Iterator[None]:
    """Each test starts and ends with no stopping signal noted (:data:`camfab.stopping.RECEIVED`),
    whatever a test before it raised."""
    from camfab import stopping

    stopping.RECEIVED.clear()
    yield
    stopping.RECEIVED.clear()
