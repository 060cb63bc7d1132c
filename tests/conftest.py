"""Shared helpers: the example designs and a way to run the command line in a temporary folder."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from click.testing import CliRunner, Result

from camfab.cli import main

ROOT = Path(__file__).resolve().parents[1]
DESIGNS = ROOT / "designs"
DESIGN_FILES = sorted(DESIGNS.glob("*.yaml"))


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
