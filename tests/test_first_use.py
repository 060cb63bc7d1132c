"""What a new user meets first: every starter of ``camfab new`` and the design of the README's
first command build with no warning and exit 0 — a warning that stays in a starter is there to
teach, and the starter's comments say so."""

from __future__ import annotations

import re

import pytest

from camfab.cli import STARTER_KINDS
from camfab.pipeline import analyse, design_from_text, load_design

from .conftest import ROOT, run_cli

#: The starters whose shape steps the follower's acceleration, on purpose (their comments say
#: why): circular-arc and tangent cams always do.
TEACHING = {"circular-arc": "acceleration", "tangent": "acceleration"}


@pytest.mark.parametrize("kind", STARTER_KINDS)
def test_every_starter_builds_clean_or_says_why_it_warns(kind: str) -> None:
    text = run_cli("new", kind).output
    analysis = analyse(design_from_text(text))
    assert analysis.exit_code == 0
    warned = [f for f in analysis.findings if not f.ok]
    if kind not in TEACHING:
        assert not warned, [f.message for f in warned]
        return
    [warning] = warned
    assert warning.severity == "warning" and warning.quantity == TEACHING[kind]
    assert "It builds with one warning, on purpose" in text


def test_the_readmes_first_command_builds_clean() -> None:
    """The README's first command builds a design that passes with no warning (the advice of a
    failing design is its second example)."""
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    command = next(line for line in readme.splitlines() if "camfab build" in line)
    path = re.search(r"camfab build (\S+)", command)
    assert path is not None, command
    analysis = analyse(load_design(ROOT / path.group(1)))
    assert analysis.exit_code == 0
    assert all(f.ok for f in analysis.findings), [f.message for f in analysis.findings
                                                  if not f.ok]
