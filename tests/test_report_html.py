"""The HTML report's content, read back from the page: every check, the drawing and the
diagrams inline, dynamics when the design has them, and nothing fetched from a network."""

from __future__ import annotations

import re

import pytest

from camfab.pipeline import analyse, load_design, render

from .conftest import DESIGNS


@pytest.mark.parametrize("name", ["seed-jump-eccentric", "demo-undercut", "demo-cylindrical",
                                  "demo-oscillating-flat"])
def test_report_holds_every_check_and_its_figures(name: str) -> None:
    artifacts = render(analyse(load_design(DESIGNS / f"{name}.yaml")))
    analysis = artifacts.analysis
    assert analysis is not None
    page = artifacts.files[f"{name}-report.html"].decode()
    assert page.startswith("<!DOCTYPE html>")
    assert re.search(r"<span class=\"verdict (ok|fail)\">(PASS|FAIL)</span>", page)
    assert ("PASS" if analysis.exit_code == 0 else "FAIL") in page
    # one table row per check, with its id
    rows = re.findall(r'<tr class="(fail|warn|)"><td class="mark', page)
    assert len(rows) == len(analysis.findings)
    for finding in analysis.findings:
        label = finding.id if finding.quantity is None else f"{finding.id} ({finding.quantity})"
        assert f"<td>{label}</td>" in page
    assert len(re.findall(r"<svg[ >]", page)) >= 2  # the drawing and the diagrams
    dyn = analysis.dynamics
    assert ('id="dynamics"' in page) == (dyn is not None and dyn.force_N is not None)
    assert "<metadata>" not in page
    # the verification's numbers are on the page
    assert "max lift error (mm)" in page


def test_undercut_is_marked_on_the_drawing() -> None:
    page = render(analyse(load_design(DESIGNS / "demo-undercut.yaml"))).files[
        "demo-undercut-report.html"].decode()
    assert "undercut" in page and "pressure angle over the limit" in page
