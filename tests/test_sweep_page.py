"""The sweep's summary page in Debian's Chromium through Selenium (chromium-driver; nothing
downloads a browser), for a sweep whose vertical key takes text values (laws) and whose
variants fail two checks: every label of the region's plot is whole inside it
(``polynomial-345``, not ``ynomial-345``), and each cell where variants fail writes, in it, the
marks of exactly the checks that fail there by the table, the page's legend naming each mark's
check; the page does not scroll sideways."""

from __future__ import annotations

import csv
import io
from pathlib import Path
from typing import Any

import pytest

from .conftest import DESIGNS, chromium, run_cli

VARY = ("--vary", "cam.base_radius=10:50:10",
        "--vary", "motion[0].law=harmonic,cycloidal,polynomial-345",
        "--vary", "follower.roller_radius=5,15,25")

#: The plot as Chromium lays it out: the SVG's box; each text's words and box; each cell's
#: place (its data-cell) and box; each cell's marks (data-marks), their words, box and size of
#: type (px); the legend's checks by mark.
PLOT = r"""
const svg = document.querySelector('figure svg');
function box(e) { const r = e.getBoundingClientRect(); return [r.left, r.top, r.right, r.bottom]; }
return {
  svg: box(svg),
  texts: Array.prototype.map.call(svg.querySelectorAll('text'), t => [t.textContent, box(t)]),
  cells: Array.prototype.map.call(svg.querySelectorAll('rect[data-cell]'),
                                  r => [r.dataset.cell, box(r)]),
  marks: Array.prototype.map.call(svg.querySelectorAll('text[data-marks]'),
    t => [t.dataset.marks, t.textContent, box(t), parseFloat(getComputedStyle(t).fontSize)]),
  legend: Object.fromEntries(Array.prototype.map.call(document.querySelectorAll('.checks .check'),
                                                      s => [s.dataset.mark, s.dataset.check])),
  sideways: document.documentElement.scrollWidth - document.documentElement.clientWidth,
};
"""


@pytest.fixture(scope="module")
def browser() -> Any:
    driver = chromium("--disable-gpu")
    yield driver
    driver.quit()


@pytest.fixture(scope="module")
def swept(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, list[dict[str, str]]]:
    """The page and the table's rows of a sweep of the undercut example."""
    folder = tmp_path_factory.mktemp("sweep-page")
    result = run_cli("sweep", str(DESIGNS / "demo-undercut.yaml"), *VARY, "-o", "out", "-j",
                     "1", "--format", "csv", cwd=folder)
    assert result.exit_code == 0, result.output
    out = folder / "out"
    rows = list(csv.DictReader(io.StringIO(
        (out / "demo-undercut-sweep.csv").read_text(encoding="utf-8"))))
    return out / "demo-undercut-sweep.html", rows


def _inside(inner: list[float], outer: list[float]) -> bool:
    return (inner[0] >= outer[0] - 0.5 and inner[1] >= outer[1] - 0.5
            and inner[2] <= outer[2] + 0.5 and inner[3] <= outer[3] + 0.5)


@pytest.mark.parametrize("width", [1024, 1280])
def test_every_label_is_whole_and_each_failing_cell_names_its_checks(
        browser: Any, swept: tuple[Path, list[dict[str, str]]], width: int) -> None:
    page, rows = swept
    expected: dict[str, set[str]] = {}
    radii = sorted({float(r["cam.base_radius"]) for r in rows})
    laws = list(dict.fromkeys(r["motion[0].law"] for r in rows))
    for r in rows:
        cell = f"{radii.index(float(r['cam.base_radius']))} {laws.index(r['motion[0].law'])}"
        failed = expected.setdefault(cell, set())
        if r["status"] == "FAIL":
            failed.update(r["message"].removeprefix("failed: ").split(", "))
    assert {c for f in expected.values() for c in f} == {"pressure_angle", "undercut"}
    browser.execute_cdp_cmd("Emulation.setDeviceMetricsOverride", {
        "width": width, "height": 900, "deviceScaleFactor": 1, "mobile": False})
    browser.get(page.as_uri())
    plot = browser.execute_script(PLOT)
    words = [text for text, _ in plot["texts"]]
    assert "polynomial-345" in words and "motion[0].law" in words
    for text, where in plot["texts"]:
        assert _inside(where, plot["svg"]), (text, where, plot["svg"])
    cells = dict(plot["cells"])
    marked = {}
    for cell, text, where, size in plot["marks"]:
        assert _inside(where, cells[cell]) and size >= 8, (cell, text, where, size)
        marked[cell] = {plot["legend"][mark] for mark in text.split()}
    assert marked == {cell: failed for cell, failed in expected.items() if failed}
    assert plot["sideways"] == 0
